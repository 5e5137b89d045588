//! The photometric distribution both file formats are read into: type C
//! luminous intensity I(γ, C) in candela on a table covering the whole
//! circle of C planes, with its interpolation and its luminous flux.
//!
//! Angles: γ is the vertical angle from the nadir (0° straight down, 180°
//! straight up); C is the plane angle, counter-clockwise seen from above,
//! C = 0° the plane of the luminaire's length (CIE 121-1996 and LM-63's type C).
//!
//! Interpolation: piecewise cubic Hermite with Fritsch–Butland/Brodlie
//! slopes (monotone, "PCHIP"), first along γ within each C plane, then
//! along C (periodically) between the planes' values. Monotone cubics do
//! not overshoot: on each interval the curve stays between its two data
//! values, so the intensity is never negative and never exceeds the
//! table's maximum. The curve is C¹ (bilinear interpolation is not)
//! except beside a run of equal values, typically a cut-off to 0: there
//! the flat side keeps slope 0 and the other side takes a one-sided
//! three-point slope, a kink that follows the data instead of rounding
//! off the cut-off (a C¹ monotone curve must flatten there, which loses
//! ~0.1 % of a cosine lamp's flux at 5° steps). At the ends of the γ
//! range — poles included — the slope is the one-sided three-point
//! estimate (PCHIP's end rule), limited to keep monotonicity.
//! F. N. Fritsch and R. E. Carlson, "Monotone piecewise cubic
//! interpolation", SIAM J. Numer. Anal. 17(2):238–246, 1980;
//! F. N. Fritsch and J. Butland, "A method for constructing local monotone
//! piecewise cubic interpolants", SIAM J. Sci. Stat. Comput. 5(2):300–304, 1984.

/// How the file's C planes cover the circle (the table is expanded to the
/// whole circle with it; kept to report it).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Symmetry {
    /// One plane: the same in every C plane.
    Rotational,
    /// C 0–90° given: mirror symmetric about both the C0–C180 and the
    /// C90–C270 planes.
    Quadrant,
    /// One half given, mirror symmetric about the C0–C180 plane:
    /// I(γ, C) = I(γ, 360° − C).
    AboutC0C180,
    /// One half given, mirror symmetric about the C90–C270 plane:
    /// I(γ, C) = I(γ, 180° − C).
    AboutC90C270,
    /// The whole circle given.
    None,
}

impl Symmetry {
    /// The mirror images of a C angle under this symmetry (the angle itself first).
    fn images(self, c: f64) -> Vec<f64> {
        match self {
            Symmetry::Rotational | Symmetry::None => vec![c],
            Symmetry::AboutC0C180 => vec![c, -c],
            Symmetry::AboutC90C270 => vec![c, 180.0 - c],
            Symmetry::Quadrant => vec![c, -c, 180.0 - c, 180.0 + c],
        }
    }
}

/// The luminous opening (luminous area) of the luminaire, in metres:
/// `length` along C0 (x), `width` along C90 (y), `height` along the
/// vertical (z). Negative values follow LM-63-2019's shape codes (e.g.
/// width = length < 0: a circle of that diameter); all zero: a point.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Opening {
    pub width_m: f64,
    pub length_m: f64,
    pub height_m: f64,
}

/// A tilt table (LM-63 `TILT=INCLUDE`): the lamp output multiplier as a
/// function of the luminaire's tilt, for lamps whose output depends on
/// their burning position. Read and kept, not applied: it depends on how
/// the scene aims the luminaire.
#[derive(Debug, Clone, PartialEq)]
pub struct Tilt {
    /// 1: vertical base-up or base-down; 2: horizontal, stays horizontal
    /// when tilted about C0; 3: horizontal, tilts with the luminaire about C90.
    pub lamp_to_luminaire_geometry: u8,
    pub angles_deg: Vec<f64>,
    pub factors: Vec<f64>,
}

/// Which file it came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// IES LM-63 with the year of its header (1986 for a file without one,
    /// 1991 for `IESNA91`).
    Ies {
        year: u16,
    },
    Eulumdat,
}

/// A type C luminous intensity distribution, in candela after all the
/// file's multipliers, tabulated over the whole sphere of directions.
#[derive(Debug, Clone, PartialEq)]
pub struct Photometry {
    pub format: Format,
    /// Vertical angles, strictly increasing within [0°, 180°]; outside
    /// them the luminaire emits nothing (a 0–90° table: nothing upwards).
    pub gamma_deg: Vec<f64>,
    /// C angles, strictly increasing from 0° to 360° (the plane at 360°
    /// repeats the one at 0°), expanded by the file's symmetry.
    pub c_deg: Vec<f64>,
    /// Candela, C-plane-major: `candela[j * gamma_deg.len() + i]` is
    /// I(gamma_deg[i], c_deg[j]).
    pub candela: Vec<f32>,
    /// The symmetry the file declared (already applied to the table).
    pub symmetry: Symmetry,
    pub opening: Opening,
    /// The total rated flux of the lamps in lm for relative photometry;
    /// `None` for absolute photometry (LM-63's lumens per lamp = −1).
    pub lamp_lumens: Option<f64>,
    /// The luminaire's input power in W, where the file gives it.
    pub input_watts: Option<f64>,
    pub tilt: Option<Tilt>,
    /// Slopes dI/dγ (left, right) of each plane's γ interpolant at its
    /// nodes (cd/°), same layout as `candela`.
    gamma_slopes: Vec<(f64, f64)>,
}

impl Photometry {
    /// Builds the full table from the planes a file gives: `planes` are
    /// (C angle in degrees, candela at each of `gamma_deg`) in the order
    /// given; `symmetry` says how they extend to the circle. The caller has
    /// checked the angles (increasing, in range) and that the candela are
    /// finite and non-negative; this function checks the expanded table
    /// covers the circle from C = 0°.
    pub(crate) fn from_planes(
        format: Format,
        gamma_deg: Vec<f64>,
        planes: Vec<(f64, Vec<f32>)>,
        symmetry: Symmetry,
    ) -> Result<Self, String> {
        let ng = gamma_deg.len();
        let mut full: Vec<(f64, &Vec<f32>)> = Vec::new();
        match symmetry {
            Symmetry::Rotational => {
                let Some((_, column)) = planes.first() else {
                    return Err("no C plane".into());
                };
                full.push((0.0, column));
            }
            _ => {
                for (c, column) in &planes {
                    for image in symmetry.images(*c) {
                        let mut a = image.rem_euclid(360.0);
                        if 360.0 - a < 1e-9 {
                            a = 0.0;
                        }
                        full.push((a, column));
                    }
                }
                // An angle there twice (a plane on a mirror, or 360°
                // repeating 0°) keeps the first column given: the sort is
                // stable. Sorting, not searching, keeps a file of many
                // planes linear-logarithmic.
                full.sort_by(|a, b| a.0.total_cmp(&b.0));
                full.dedup_by(|later, kept| (later.0 - kept.0).abs() < 1e-6);
            }
        }
        match full.first() {
            Some((c0, _)) if *c0 == 0.0 => {}
            _ => return Err("the C planes do not include C = 0°".into()),
        }
        let first = full[0].1;
        full.push((360.0, first));
        let c_deg: Vec<f64> = full.iter().map(|(c, _)| *c).collect();
        let candela: Vec<f32> = full
            .iter()
            .flat_map(|(_, col)| col.iter().copied())
            .collect();
        let mut p = Photometry {
            format,
            gamma_slopes: Vec::new(),
            gamma_deg,
            c_deg,
            candela,
            symmetry,
            opening: Opening::default(),
            lamp_lumens: None,
            input_watts: None,
            tilt: None,
        };
        debug_assert_eq!(p.candela.len(), ng * p.c_deg.len());
        p.gamma_slopes = (0..p.c_deg.len())
            .flat_map(|j| {
                let column: Vec<f64> = p.column(j).iter().map(|&v| v as f64).collect();
                gamma_node_slopes(&p.gamma_deg, &column)
            })
            .collect();
        Ok(p)
    }

    fn column(&self, j: usize) -> &[f32] {
        let ng = self.gamma_deg.len();
        &self.candela[j * ng..(j + 1) * ng]
    }

    /// I(γ, C) in candela, interpolated as the module says; 0 outside the
    /// table's vertical angles and for non-finite angles. C is taken
    /// modulo 360°.
    pub fn intensity(&self, gamma_deg: f32, c_deg: f32) -> f32 {
        self.intensity_f64(gamma_deg as f64, c_deg as f64) as f32
    }

    fn intensity_f64(&self, gamma: f64, c: f64) -> f64 {
        if !gamma.is_finite() || !c.is_finite() {
            return 0.0;
        }
        let g = &self.gamma_deg;
        if gamma < g[0] || gamma > g[g.len() - 1] {
            return 0.0;
        }
        let c = c.rem_euclid(360.0);
        // Unique planes: the last (360°) repeats the first.
        let m = self.c_deg.len() - 1;
        let j = segment(&self.c_deg, c).min(m - 1);
        // Values of planes j−1 … j+2 (periodic) at this γ.
        let value = |k: isize| self.plane_at(k.rem_euclid(m as isize) as usize, gamma);
        let angle = |k: isize| {
            let wraps = k.div_euclid(m as isize) as f64;
            self.c_deg[k.rem_euclid(m as isize) as usize] + 360.0 * wraps
        };
        let j = j as isize;
        let (x0, x1) = (angle(j), angle(j + 1));
        let (y0, y1) = (value(j), value(j + 1));
        let h = x1 - x0;
        if m == 1 || h <= 0.0 {
            return y0.max(0.0);
        }
        // Intervals j−2 … j+2 around this one (j).
        let side = |k: isize| {
            let w = angle(k + 1) - angle(k);
            Side {
                h: w,
                d: (value(k + 1) - value(k)) / w,
            }
        };
        let (s_m2, s_m1, s0, s1, s2) =
            (side(j - 2), side(j - 1), side(j), side(j + 1), side(j + 2));
        let (_, m0) = node_slopes(Some((s_m1, Some(s_m2))), Some((s0, Some(s1))));
        let (m1, _) = node_slopes(Some((s0, Some(s_m1))), Some((s1, Some(s2))));
        hermite(y0, y1, m0, m1, h, (c - x0) / h).max(0.0)
    }

    /// Plane `j`'s γ interpolant at `gamma` (within the table's range).
    fn plane_at(&self, j: usize, gamma: f64) -> f64 {
        let ng = self.gamma_deg.len();
        let column = self.column(j);
        let slopes = &self.gamma_slopes[j * ng..(j + 1) * ng];
        let i = segment(&self.gamma_deg, gamma).min(ng - 2);
        let h = self.gamma_deg[i + 1] - self.gamma_deg[i];
        let t = ((gamma - self.gamma_deg[i]) / h).clamp(0.0, 1.0);
        hermite(
            column[i] as f64,
            column[i + 1] as f64,
            slopes[i].1,
            slopes[i + 1].0,
            h,
            t,
        )
    }

    /// The luminous flux Φ = ∫ I dΩ = ∫∫ I(γ, C) sin γ dγ dC in lumens,
    /// of the interpolated distribution: over C exactly (a cubic Hermite
    /// piece integrates to h·((y₀+y₁)/2 + h·(m₀−m₁)/12)), over γ by
    /// 8-point Gauss–Legendre on each interval of the table (exact to
    /// rounding for smooth pieces; a ≤ 1e-6 relative error where PCHIP's
    /// slope limiter switches within an interval).
    pub fn total_flux_lm(&self) -> f64 {
        let g = &self.gamma_deg;
        let mut flux = 0.0;
        for i in 0..g.len() - 1 {
            let (a, b) = (g[i], g[i + 1]);
            let half = 0.5 * (b - a);
            for (x, w) in GAUSS_LEGENDRE_8 {
                let gamma = a + half * (1.0 + x);
                let around = self.integral_over_c(gamma);
                flux += w * half * around * gamma.to_radians().sin();
            }
        }
        // dγ in degrees → radians.
        flux * std::f64::consts::PI / 180.0
    }

    /// ∫ I(γ, C) dC over the circle, C in radians.
    fn integral_over_c(&self, gamma: f64) -> f64 {
        let m = self.c_deg.len() - 1;
        let values: Vec<f64> = (0..m).map(|j| self.plane_at(j, gamma)).collect();
        if m == 1 {
            return values[0] * 2.0 * std::f64::consts::PI;
        }
        // Interval k (periodic) from plane k to plane k+1.
        let side = |k: usize| {
            let k = k % m;
            let h = self.c_deg[k + 1] - self.c_deg[k];
            Side {
                h,
                d: (values[(k + 1) % m] - values[k]) / h,
            }
        };
        // Node k's (left, right) slopes, from intervals k−2 … k+1.
        let slopes: Vec<(f64, f64)> = (0..m)
            .map(|k| {
                let (l, ll) = (side(k + m - 1), side(k + 2 * m - 2));
                let (r, rr) = (side(k), side(k + 1));
                node_slopes(Some((l, Some(ll))), Some((r, Some(rr))))
            })
            .collect();
        let mut sum = 0.0;
        for k in 0..m {
            let h = side(k).h;
            let (y0, y1) = (values[k], values[(k + 1) % m]);
            let (m0, m1) = (slopes[k].1, slopes[(k + 1) % m].0);
            sum += h * (0.5 * (y0 + y1) + h * (m0 - m1) / 12.0);
        }
        sum.to_radians()
    }
}

/// The index i of the interval [x[i], x[i+1]] holding `v` (clamped to the
/// table; `x` increasing, at least two long).
fn segment(x: &[f64], v: f64) -> usize {
    x.partition_point(|&a| a <= v).saturating_sub(1)
}

/// The monotone slope at a node between intervals of widths `h0` (left)
/// and `h1` (right) with secants `d0` and `d1`: zero at a local extremum,
/// else Brodlie's weighted harmonic mean (Fritsch & Butland 1984), which
/// keeps |slope| ≤ 3·min(|d0|, |d1|), Fritsch & Carlson's monotonicity bound.
fn pchip_slope(h0: f64, h1: f64, d0: f64, d1: f64) -> f64 {
    if d0 * d1 <= 0.0 {
        return 0.0;
    }
    let w0 = 2.0 * h1 + h0;
    let w1 = h1 + 2.0 * h0;
    (w0 + w1) / (w0 / d0 + w1 / d1)
}

/// An interval beside a node: its width and secant.
#[derive(Debug, Clone, Copy)]
struct Side {
    h: f64,
    d: f64,
}

/// A one-sided three-point slope at a node, from the interval `near` next
/// to it and the one beyond (`far`), as PCHIP's end rule: 0 if it points
/// against `near`'s secant, and at most 3× that secant (Fritsch &
/// Carlson's bound), so the curve on `near` stays monotone.
fn one_sided(near: Side, far: Option<Side>) -> f64 {
    let Some(far) = far else {
        return near.d;
    };
    let m = ((2.0 * near.h + far.h) * near.d - near.h * far.d) / (near.h + far.h);
    if m * near.d <= 0.0 {
        0.0
    } else if m.abs() > 3.0 * near.d.abs() {
        3.0 * near.d
    } else {
        m
    }
}

/// A node's (left, right) slopes from the intervals on either side (each
/// with the one beyond it): the same PCHIP slope on both sides where the
/// data runs through the node; 0 at a strict extremum; beside a flat
/// interval, 0 on its side and a one-sided slope on the other; at an end,
/// the one-sided slope.
fn node_slopes(
    left: Option<(Side, Option<Side>)>,
    right: Option<(Side, Option<Side>)>,
) -> (f64, f64) {
    match (left, right) {
        (Some((l, ll)), Some((r, rr))) => {
            if l.d * r.d > 0.0 {
                let m = pchip_slope(l.h, r.h, l.d, r.d);
                (m, m)
            } else if l.d == 0.0 && r.d != 0.0 {
                (0.0, one_sided(r, rr))
            } else if r.d == 0.0 && l.d != 0.0 {
                (one_sided(l, ll), 0.0)
            } else {
                (0.0, 0.0)
            }
        }
        (Some((l, ll)), None) => (one_sided(l, ll), 0.0),
        (None, Some((r, rr))) => (0.0, one_sided(r, rr)),
        (None, None) => (0.0, 0.0),
    }
}

/// The (left, right) slopes at each node of a column's γ interpolant.
fn gamma_node_slopes(x: &[f64], y: &[f64]) -> Vec<(f64, f64)> {
    let n = x.len();
    let side = |i: usize| {
        let h = x[i + 1] - x[i];
        Side {
            h,
            d: (y[i + 1] - y[i]) / h,
        }
    };
    (0..n)
        .map(|i| {
            let left = (i > 0).then(|| (side(i - 1), (i > 1).then(|| side(i - 2))));
            let right = (i + 1 < n).then(|| (side(i), (i + 2 < n).then(|| side(i + 1))));
            node_slopes(left, right)
        })
        .collect()
}

/// The cubic Hermite piece through (0, y0) and (1, y1) with slopes m0, m1
/// per unit of the abscissa, on an interval of width h, at t ∈ [0, 1].
fn hermite(y0: f64, y1: f64, m0: f64, m1: f64, h: f64, t: f64) -> f64 {
    let t2 = t * t;
    let t3 = t2 * t;
    (2.0 * t3 - 3.0 * t2 + 1.0) * y0
        + (t3 - 2.0 * t2 + t) * h * m0
        + (-2.0 * t3 + 3.0 * t2) * y1
        + (t3 - t2) * h * m1
}

/// Gauss–Legendre nodes and weights on [−1, 1], 8 points (Abramowitz &
/// Stegun, Table 25.4).
const GAUSS_LEGENDRE_8: [(f64, f64); 8] = [
    (-0.960_289_856_497_536_2, 0.101_228_536_290_376_3),
    (-0.796_666_477_413_626_7, 0.222_381_034_453_374_5),
    (-0.525_532_409_916_329, 0.313_706_645_877_887_3),
    (-0.183_434_642_495_649_8, 0.362_683_783_378_362),
    (0.183_434_642_495_649_8, 0.362_683_783_378_362),
    (0.525_532_409_916_329, 0.313_706_645_877_887_3),
    (0.796_666_477_413_626_7, 0.222_381_034_453_374_5),
    (0.960_289_856_497_536_2, 0.101_228_536_290_376_3),
];

#[cfg(test)]
mod tests {
    use super::*;

    fn lamp(gammas: &[f64], planes: Vec<(f64, Vec<f32>)>, s: Symmetry) -> Photometry {
        Photometry::from_planes(Format::Eulumdat, gammas.to_vec(), planes, s).unwrap()
    }

    #[test]
    fn isotropic_flux_is_four_pi() {
        let p = lamp(
            &[0.0, 90.0, 180.0],
            vec![(0.0, vec![1.0; 3])],
            Symmetry::Rotational,
        );
        assert!((p.total_flux_lm() - 4.0 * std::f64::consts::PI).abs() < 1e-9);
        assert_eq!(p.intensity(37.0, 123.0), 1.0);
        assert_eq!(p.c_deg, vec![0.0, 360.0]);
    }

    #[test]
    fn interpolation_passes_through_nodes_and_never_overshoots() {
        let g = [0.0, 30.0, 60.0, 90.0];
        let planes = vec![
            (0.0, vec![100.0, 0.0, 100.0, 0.0]),
            (90.0, vec![0.0, 50.0, 0.0, 10.0]),
        ];
        let p = lamp(&g, planes, Symmetry::Quadrant);
        assert_eq!(p.intensity(30.0, 90.0), 50.0);
        assert_eq!(p.intensity(60.0, 180.0), 100.0);
        assert_eq!(p.intensity(95.0, 0.0), 0.0);
        for a in 0..=90 {
            for c in 0..72 {
                let v = p.intensity(a as f32, c as f32 * 5.0);
                assert!((0.0..=100.0).contains(&v), "{v} at {a}, {}", c * 5);
            }
        }
        assert_eq!(p.intensity(f32::NAN, 0.0), 0.0);
    }
}
