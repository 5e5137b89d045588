//! Road surfaces by the CIE r-tables (CIE 144:2001, CIE 30.2:1982, CIE 66;
//! the data and its source in `data/cie/cie_road_r_tables.csv`): the
//! reduced luminance coefficient r(β, tan γ) of classes R1–R4, C1 and C2,
//! for the standard observer looking at the road 1° below the horizontal.
//!
//! γ is the angle of the light's direction from the vertical, β the angle
//! between the vertical plane of incidence and that of observation, 0
//! where the luminaire stands beyond the point as the observer sees it.
//! A luminaire of intensity I towards the point, at height h above it,
//! makes L = I·r/h² (CIE 140:2000, eq. 2.1): the illuminance there is
//! E = I·cos³γ/h², so the BRDF is q = L/E = r/cos³γ (the luminance
//! coefficient), from the light's angles alone — the tables hold no
//! dependence on the observer's elevation, and scotopia uses them at any
//! elevation (not reciprocal, so light paths use its adjoint).
//!
//! Between the table's nodes r is interpolated bilinearly in β and tan γ;
//! in a blank cell of the printed table (large γ off the plane of
//! observation) and beyond tan γ = 12 (γ > 85.2°) q keeps the value of the
//! last cell given before it, so that light at grazing incidence stays
//! integrable. A `q0` scales the
//! table by q0 over its class's standard Q0 (CIE 144: a measured surface
//! of that class). A reflectance spectrum gives the surface its colour,
//! normalised to a luminous reflectance of 1 under an equal-energy
//! spectrum, so that its luminance stays the table's. Sampled by the
//! cosine, as a diffuse surface.

use std::sync::OnceLock;

use scotopia_color::{SampledSpectrum, SampledWavelengths, Spectrum};

use super::{BsdfSample, Transport};
use crate::math::Vec3;
use crate::sampling::warp::{cosine_hemisphere_pdf, square_to_cosine_hemisphere};

const CSV: &str = include_str!("../../../../data/cie/cie_road_r_tables.csv");

/// The classes, in the data's order, with their standard Q0 (CIE 144).
pub const CLASSES: [(&str, f32); 6] = [
    ("R1", 0.10),
    ("R2", 0.07),
    ("R3", 0.07),
    ("R4", 0.08),
    ("C1", 0.10),
    ("C2", 0.07),
];

/// The tables' β nodes, degrees.
pub const BETAS: [f32; 20] = [
    0.0, 2.0, 5.0, 10.0, 15.0, 20.0, 25.0, 30.0, 35.0, 40.0, 45.0, 60.0, 75.0, 90.0, 105.0, 120.0,
    135.0, 150.0, 165.0, 180.0,
];

/// The tables' tan γ nodes.
pub const TANS: [f32; 29] = [
    0.0, 0.25, 0.5, 0.75, 1.0, 1.25, 1.5, 1.75, 2.0, 2.5, 3.0, 3.5, 4.0, 4.5, 5.0, 5.5, 6.0, 6.5,
    7.0, 7.5, 8.0, 8.5, 9.0, 9.5, 10.0, 10.5, 11.0, 11.5, 12.0,
];

/// One class's r × 10⁴, [β][tan γ], blanks filled, and which cells the
/// printed table gives.
#[derive(Debug)]
struct Table {
    r: [[f32; 29]; 20],
    given: [[bool; 29]; 20],
}

/// The six tables, parsed once.
fn tables() -> &'static [Table; 6] {
    static TABLES: OnceLock<[Table; 6]> = OnceLock::new();
    TABLES.get_or_init(|| {
        let mut t: [Table; 6] = std::array::from_fn(|_| Table {
            r: [[0.0; 29]; 20],
            given: [[false; 29]; 20],
        });
        let mut rows = [0usize; 6];
        for line in CSV.lines().filter(|l| !l.starts_with('#')).skip(1) {
            let mut cells = line.split(',');
            let class = cells.next().unwrap_or_default();
            let Some(c) = CLASSES.iter().position(|(n, _)| *n == class) else {
                panic!("cie_road_r_tables.csv: unknown class {class}");
            };
            let b = rows[c];
            let beta: f32 = cells
                .next()
                .and_then(|v| v.parse().ok())
                .unwrap_or(f32::NAN);
            assert_eq!(beta, BETAS[b], "cie_road_r_tables.csv: {class}'s β rows");
            let row = &mut t[c];
            for (j, v) in cells.enumerate() {
                row.r[b][j] = v.parse().expect("cie_road_r_tables.csv: a number");
                row.given[b][j] = row.r[b][j] > 0.0;
            }
            // A blank (0) keeps q = r/cos³γ of the last given cell before
            // it: r falls as cos³γ.
            for j in 1..TANS.len() {
                if !row.given[b][j] {
                    let fall = ((1.0 + TANS[j - 1].powi(2)) / (1.0 + TANS[j].powi(2))).powf(1.5);
                    row.r[b][j] = row.r[b][j - 1] * fall;
                }
            }
            rows[c] += 1;
        }
        assert!(
            rows.iter().all(|&n| n == BETAS.len()),
            "cie_road_r_tables.csv: {rows:?}"
        );
        t
    })
}

/// Where `x` falls among `nodes`: the lower node's index and the weight
/// of the upper one (clamped at the ends).
fn locate(nodes: &[f32], x: f32) -> (usize, f32) {
    let last = nodes.len() - 1;
    if x <= nodes[0] {
        return (0, 0.0);
    }
    if x >= nodes[last] {
        return (last - 1, 1.0);
    }
    let i = nodes.partition_point(|&n| n <= x) - 1;
    (i, (x - nodes[i]) / (nodes[i + 1] - nodes[i]))
}

/// A CIE road surface.
#[derive(Debug, Clone, PartialEq)]
pub struct RoadSurface {
    /// Index into [`CLASSES`].
    class: usize,
    /// 10⁻⁴ × q0 over the class's standard Q0.
    scale: f32,
    /// The reflectance spectrum over its luminous reflectance, if any.
    tint: Option<Spectrum>,
}

impl RoadSurface {
    /// Class `name` (R1–R4, C1, C2) with average luminance coefficient
    /// `q0` (the class's standard one when `None`) and colour `tint`
    /// (grey when `None`); `None` for an unknown class, or a tint whose
    /// luminous reflectance is not positive.
    pub fn new(name: &str, q0: Option<f32>, tint: Option<Spectrum>) -> Option<Self> {
        let class = CLASSES
            .iter()
            .position(|(n, _)| n.eq_ignore_ascii_case(name))?;
        let standard = CLASSES[class].1;
        let tint = match tint {
            None => None,
            Some(s) => {
                let y = scotopia_color::photometry::integrate_observers(&s)[1];
                let white =
                    scotopia_color::photometry::integrate_observers(&Spectrum::Constant(1.0))[1];
                let luminous = (y / white) as f32;
                if !(luminous > 0.0 && luminous.is_finite()) {
                    return None;
                }
                Some(s.scaled(1.0 / luminous))
            }
        };
        Some(Self {
            class,
            scale: 1e-4 * q0.unwrap_or(standard) / standard,
            tint,
        })
    }

    /// The class's name.
    pub fn class(&self) -> &'static str {
        CLASSES[self.class].0
    }

    /// r (not × 10⁴) at angle `beta` (degrees) and `tan_gamma`, scaled by
    /// q0 over the standard Q0.
    pub fn r(&self, beta: f32, tan_gamma: f32) -> f32 {
        let t = &tables()[self.class].r;
        let (i, u) = locate(&BETAS, beta);
        let (j, v) = locate(&TANS, tan_gamma);
        let at = |b: usize, g: usize| t[b][g];
        let lo = at(i, j) * (1.0 - v) + at(i, j + 1) * v;
        let hi = at(i + 1, j) * (1.0 - v) + at(i + 1, j + 1) * v;
        self.scale * (lo * (1.0 - u) + hi * u)
    }

    /// The luminance coefficient q = r/cos³γ (sr⁻¹) for an observer along
    /// `view` and light arriving from `light` (both local, z up, away
    /// from the surface).
    pub fn q(&self, view: Vec3, light: Vec3) -> f32 {
        if view.z <= 0.0 || light.z <= 0.0 {
            return 0.0;
        }
        let side = (light.x * light.x + light.y * light.y).sqrt();
        let tan_gamma = side / light.z;
        // β: between the light's horizontal direction and the direction
        // from the observer through the point (0 with the light beyond).
        let seen = (view.x * view.x + view.y * view.y).sqrt();
        let beta = if side > 0.0 && seen > 0.0 {
            let c = -(light.x * view.x + light.y * view.y) / (side * seen);
            c.clamp(-1.0, 1.0).acos().to_degrees()
        } else {
            0.0
        };
        let last = TANS[TANS.len() - 1];
        // Beyond the table q keeps its last value (module doc).
        let t = tan_gamma.min(last);
        let cos2 = 1.0 / (1.0 + t * t);
        self.r(beta, t) / (cos2 * cos2.sqrt())
    }

    /// f(wi, wo)·cos θ_o: the table's q with the observer along `wi` for
    /// radiance (camera paths), along `wo` for importance (light paths).
    pub fn eval<const K: usize>(
        &self,
        wl: &SampledWavelengths<K>,
        wi: Vec3,
        wo: Vec3,
        mode: Transport,
    ) -> SampledSpectrum<K> {
        let (view, light) = match mode {
            Transport::Radiance => (wi, wo),
            Transport::Importance => (wo, wi),
        };
        let f = self.q(view, light) * wo.z.max(0.0);
        match &self.tint {
            Some(s) => s.sample(wl) * f,
            None => SampledSpectrum::splat(f),
        }
    }

    pub fn pdf(&self, wi: Vec3, wo: Vec3) -> f32 {
        super::diffuse::upper_cosine_pdf(wi, wo)
    }

    pub fn sample<const K: usize>(
        &self,
        wl: &SampledWavelengths<K>,
        wi: Vec3,
        u: [f32; 2],
        mode: Transport,
    ) -> Option<BsdfSample<K>> {
        if wi.z <= 0.0 {
            return None;
        }
        let wo = square_to_cosine_hemisphere(u);
        let f = self.eval(wl, wi, wo, mode);
        BsdfSample::mixed(wo, f, cosine_hemisphere_pdf(wo.z))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn light(beta_deg: f32, tan_gamma: f32) -> (Vec3, Vec3) {
        // The observer along −x, 1° above the road; the light's horizontal
        // direction β from +x (beyond the point).
        let view = Vec3::new(-1.0, 0.0, 1f32.to_radians().tan()).normalize();
        let b = beta_deg.to_radians();
        let l = Vec3::new(b.cos() * tan_gamma, b.sin() * tan_gamma, 1.0).normalize();
        (view, l)
    }

    #[test]
    fn the_tables_nodes_come_back_and_l_is_i_r_over_h_squared() {
        let r3 = RoadSurface::new("R3", None, None).unwrap();
        // R3 at (0, 0) is 294 × 10⁻⁴, at β 0, tan γ 2 326 (CIE 144 S1 1.11).
        assert!((r3.r(0.0, 0.0) - 0.0294).abs() < 1e-7);
        assert!((r3.r(0.0, 2.0) / r3.r(0.0, 0.0) - 1.109).abs() < 1e-3);
        // q·cos³γ = r at a node, from directions.
        for (beta, tan) in [
            (0.0, 0.0),
            (0.0, 2.0),
            (90.0, 1.0),
            (180.0, 4.0),
            (30.0, 3.0),
        ] {
            let (v, l) = light(beta, tan);
            let cos = l.z;
            let r = r3.q(v, l) * cos * cos * cos;
            assert!(
                (r - r3.r(beta, tan)).abs() < 1e-6 * r.max(1e-3),
                "{beta}, {tan}"
            );
        }
        // β is symmetric about the plane of observation.
        let (v, l) = light(60.0, 1.5);
        let mirrored = Vec3::new(l.x, -l.y, l.z);
        assert!((r3.q(v, l) - r3.q(v, mirrored)).abs() < 1e-6);
        // A q0 scales it.
        let bright = RoadSurface::new("r3", Some(0.14), None).unwrap();
        assert!((bright.r(45.0, 1.0) / r3.r(45.0, 1.0) - 2.0).abs() < 1e-5);
        // A blank cell keeps the q of the last given one: r falls as cos³γ.
        let fall = ((1.0 + 25.0) / (1.0 + 64.0f32)).powf(1.5);
        assert!((r3.r(180.0, 8.0) - r3.r(180.0, 5.0) * fall).abs() < 1e-9);
        assert!(RoadSurface::new("R5", None, None).is_none());
    }

    #[test]
    fn each_class_averages_its_standard_q0() {
        // Q0 = ∫ q dω / Ω0 over the light directions the printed table
        // gives (CIE 144), from the BSDF's own q: with q dω = r·t dt dβ
        // (t = tan γ), by the midpoint rule over each cell whose corners
        // are all given. Each class's within 5 % of its standard Q0 (the
        // CIE's coarser weighting factors give them within 1 %).
        for (c, (name, q0)) in CLASSES.iter().enumerate() {
            let s = RoadSurface::new(name, None, None).unwrap();
            let given = &tables()[c].given;
            let n = 12;
            let (mut sum, mut omega) = (0.0f64, 0.0f64);
            for i in 0..BETAS.len() - 1 {
                for j in 0..TANS.len() - 1 {
                    if !(given[i][j] && given[i + 1][j] && given[i][j + 1] && given[i + 1][j + 1]) {
                        continue;
                    }
                    let db = (BETAS[i + 1] - BETAS[i]).to_radians() / n as f32;
                    let dt = (TANS[j + 1] - TANS[j]) / n as f32;
                    for a in 0..n {
                        let beta =
                            BETAS[i] + (BETAS[i + 1] - BETAS[i]) * (a as f32 + 0.5) / n as f32;
                        for k in 0..n {
                            let t = TANS[j] + dt * (k as f32 + 0.5);
                            let (v, l) = light(beta, t);
                            let cos = 1.0 / (1.0 + t * t).sqrt();
                            // dω = sin γ dγ dβ = t cos³γ dt dβ.
                            let dw = f64::from(t * cos * cos * cos * dt * db);
                            sum += f64::from(s.q(v, l)) * dw;
                            omega += dw;
                        }
                    }
                }
            }
            let q = sum / omega;
            assert!(
                (q / f64::from(*q0) - 1.0).abs() < 0.05,
                "{name}: Q0 {q:.4} against {q0}"
            );
        }
    }

    #[test]
    fn light_paths_see_the_adjoint_and_a_tint_keeps_the_luminance() {
        let wl = SampledWavelengths::<4>::new([450.0, 520.0, 555.0, 620.0], [1.0; 4]);
        let grey = RoadSurface::new("C2", None, None).unwrap();
        let (v, l) = light(20.0, 2.0);
        let f = grey.eval(&wl, v, l, Transport::Radiance).0[0];
        let adj = grey.eval(&wl, l, v, Transport::Importance).0[0];
        // The same f, times the cosine of the outgoing direction.
        assert!((f / l.z - adj / v.z).abs() < 1e-5 * f / l.z);
        // Flat tint 0.3: normalised away.
        let flat = RoadSurface::new("C2", None, Some(Spectrum::Constant(0.3))).unwrap();
        let g = flat.eval(&wl, v, l, Transport::Radiance).0;
        assert!(g.iter().all(|x| (x - f).abs() < 1e-4 * f));
        assert!(RoadSurface::new("C2", None, Some(Spectrum::Constant(0.0))).is_none());
    }
}
