//! Bounce directions aimed at glossy surfaces that lamps light brightly.
//!
//! On the night street a rough aluminium pole stands 40 cm from each
//! lamp. Its glossy reflection of the lamp lights the walls and the road
//! around it, but a wall point's cosine-sampled bounce reaches the 12 cm
//! pole rarely, and then carries a reflection of thousands of cd/m²: the
//! dots that remained in `make demo`'s picture. Here a diffuse vertex
//! draws its bounce from a mixture (one-sample MIS, Veach 1997 §9.2.2,
//! balance heuristic): with probability 1 − [`SHARE`] the BSDF, otherwise
//! a point on such a reflector, and weighs the sample by f·cos over the
//! mixture's density q(ω) = (1 − c)·p_bsdf(ω) + c·p_refl(ω). Next-event
//! estimation weighs lamps against the same q, so the path's MIS stays
//! consistent.
//!
//! **Reflectors** are meshes (at most [`MAX_TRIANGLES`] triangles) of a
//! rough conductor or rough plastic that do not emit, each keeping at least
//! [`MIN_SHARE`] of the finite lights' power by an irradiance estimate; the
//! [`MAX_REFLECTORS`] that intercept most are kept. A reflector's points are
//! drawn by area times the lamps' irradiance there (plus a defensive share
//! of its mean), tabulated on a [`CELLS`]² grid of sub-triangles per
//! triangle, on the triangles facing the vertex (outward normals, taken
//! away from the mesh's centre); a reflector is chosen by its intercepted
//! power over the squared distance from the vertex. p_refl(ω) sums that
//! area density, turned into solid angle, over every facing triangle the
//! line from the vertex along ω crosses, so it is the exact density of the
//! directions drawn, whatever hides them.
//!
//! Scenes without reflectors, and vertices that are not diffuse, sample
//! the BSDF as before, bit for bit.

use scotopia_color::SampledWavelengths;

use super::path::ScatterPoint;
use crate::accel::Aabb;
use crate::bsdf::{Bsdf, BsdfSample, Transport};
use crate::geometry::{intersect_triangle, RayShear, Shape};
use crate::light::{Light, SceneExtent};
use crate::math::{Ray, Vec3};
use crate::sampling::distribution::Distribution1D;

/// The mixture's share c of reflector sampling at a diffuse vertex: the
/// BSDF keeps 0.8, so other indirect light's variance grows by at most
/// 1/0.8.
pub const SHARE: f32 = 0.2;

/// The share of reflector sampling at a point in a medium (the volume
/// path tracer's `sample_phase`): the phase function and the halos keep
/// 0.9, so the fog's other light's variance grows by at most 1/0.9.
pub const MEDIUM_SHARE: f32 = 0.1;

/// Sub-triangles per triangle edge: a pole's 6.5 m side is tabulated in
/// 40 cm steps.
pub const CELLS: usize = 16;

/// Share of the finite lights' power a reflector must intercept.
pub const MIN_SHARE: f32 = 1e-3;

/// Share of a reflector's mean irradiance added to each cell's, so that
/// every point keeps a density.
const DEFENSIVE: f32 = 0.1;

pub const MAX_REFLECTORS: usize = 8;
pub const MAX_TRIANGLES: usize = 64;

/// One triangle of a reflector and its table of sub-triangles.
#[derive(Debug, Clone)]
struct Triangle {
    a: Vec3,
    e1: Vec3,
    e2: Vec3,
    /// Unit normal, outward (away from the mesh's centre).
    n: Vec3,
    area: f32,
    /// Sum of its cells' weights (its share of the reflector).
    mass: f32,
    /// Cells `2·(i·CELLS + j) + upper`, by weight (invalid cells 0).
    cells: Distribution1D,
}

#[derive(Debug, Clone)]
struct Reflector {
    triangles: Vec<Triangle>,
    bounds: Aabb,
    /// The power it intercepts (W), by the irradiance estimate.
    power: f32,
    /// Squared distance below which the choice stops growing nearer it.
    near2: f32,
}

/// The scene's reflectors (empty: bounces sample the BSDF alone).
#[derive(Debug, Clone, Default)]
pub struct Reflectors {
    list: Vec<Reflector>,
}

/// Each reflector's weight at a point and its facing mass, and the
/// weights' sum.
type Weights = ([(f32, f32); MAX_REFLECTORS], f32);

/// A finite light as the tables see it: centre and power (W).
#[derive(Debug, Clone, Copy)]
pub struct Lamp {
    pub centre: Vec3,
    pub watts: f32,
}

/// The cell of barycentrics (b1, b2) and its corners (in barycentrics).
fn cell_of(b1: f32, b2: f32) -> usize {
    let n = CELLS as f32;
    let (x, y) = (b1 * n, b2 * n);
    let i = (x.floor().max(0.0) as usize).min(CELLS - 1);
    let j = (y.floor().max(0.0) as usize).min(CELLS - 1 - i);
    let upper = (x - i as f32) + (y - j as f32) > 1.0 && i + j + 2 <= CELLS;
    2 * (i * CELLS + j) + upper as usize
}

fn cell_corners(k: usize) -> [[f32; 2]; 3] {
    let (ij, upper) = (k / 2, k % 2 == 1);
    let (i, j) = ((ij / CELLS) as f32, (ij % CELLS) as f32);
    let n = CELLS as f32;
    let c = |x: f32, y: f32| [x / n, y / n];
    if upper {
        [c(i + 1.0, j + 1.0), c(i, j + 1.0), c(i + 1.0, j)]
    } else {
        [c(i, j), c(i + 1.0, j), c(i, j + 1.0)]
    }
}

fn cell_valid(k: usize) -> bool {
    let (ij, upper) = (k / 2, k % 2 == 1);
    let (i, j) = (ij / CELLS, ij % CELLS);
    if upper {
        i + j + 2 <= CELLS
    } else {
        i + j < CELLS
    }
}

/// Whether light leaving `bsdf` is glossy: worth aiming diffuse bounces
/// at when lamps light it.
pub(super) fn glossy(bsdf: &Bsdf) -> bool {
    match bsdf {
        Bsdf::Conductor(c) => !c.is_smooth(),
        Bsdf::RoughPlastic(_) => true,
        Bsdf::TwoSided(inner) => glossy(inner),
        _ => false,
    }
}

/// Whether a vertex of `bsdf` draws its bounce from the mixture.
fn guided(bsdf: &Bsdf) -> bool {
    match bsdf {
        Bsdf::Diffuse(_) => true,
        Bsdf::TwoSided(inner) => matches!(**inner, Bsdf::Diffuse(_)),
        _ => false,
    }
}

impl Triangle {
    fn new(a: Vec3, b: Vec3, c: Vec3, centre: Vec3, lamps: &[Lamp]) -> Option<(Self, f32)> {
        let (e1, e2) = (b - a, c - a);
        let cross = e1.cross(e2);
        let area = 0.5 * cross.length();
        let mut n = cross.normalize();
        if !(area > 0.0 && n.is_finite()) {
            return None;
        }
        if n.dot((a + b + c) / 3.0 - centre) < 0.0 {
            n = -n;
        }
        // Irradiance at each cell's centroid from every lamp, as from a
        // point (inverse square, |cos|), ignoring occlusion.
        let cell_area = area / (CELLS * CELLS) as f32;
        let irradiance: Vec<f32> = (0..2 * CELLS * CELLS)
            .map(|k| {
                if !cell_valid(k) {
                    return 0.0;
                }
                let [p, q, r] = cell_corners(k);
                let (b1, b2) = ((p[0] + q[0] + r[0]) / 3.0, (p[1] + q[1] + r[1]) / 3.0);
                let y = a + e1 * b1 + e2 * b2;
                lamps
                    .iter()
                    .map(|l| {
                        let d = l.centre - y;
                        let d2 = d.length_squared().max(1e-6);
                        l.watts / (4.0 * std::f32::consts::PI) * (n.dot(d).abs() / d2.sqrt()) / d2
                    })
                    .sum()
            })
            .collect();
        let intercepted = irradiance.iter().sum::<f32>() * cell_area;
        Some((
            Self {
                a,
                e1,
                e2,
                n,
                area,
                mass: 0.0,
                cells: Distribution1D::new(irradiance),
            },
            intercepted,
        ))
    }

    /// Whether the triangle's outer side faces `x`.
    #[inline]
    fn faces(&self, x: Vec3) -> bool {
        self.n.dot(x - self.a) > 0.0
    }
}

impl Reflector {
    fn new(triangles: &[[Vec3; 3]], lamps: &[Lamp]) -> Option<Self> {
        let points: Vec<Vec3> = triangles.iter().flatten().copied().collect();
        let bounds = Aabb::from_points(&points);
        let centre = bounds.centroid();
        let mut made = Vec::new();
        let mut power = 0.0;
        for [a, b, c] in triangles {
            if let Some((t, e)) = Triangle::new(*a, *b, *c, centre, lamps) {
                power += e;
                made.push(t);
            }
        }
        let area: f32 = made.iter().map(|t| t.area).sum();
        if !(power > 0.0 && area > 0.0) {
            return None;
        }
        // Each cell: area × (irradiance + DEFENSIVE × the mean irradiance).
        let floor = DEFENSIVE * power / area;
        for t in &mut made {
            let cell_area = t.area / (CELLS * CELLS) as f32;
            let weights: Vec<f32> = (0..2 * CELLS * CELLS)
                .map(|k| {
                    if cell_valid(k) {
                        cell_area * (t.cells.probability(k) * t.cells.sum() as f32 + floor)
                    } else {
                        0.0
                    }
                })
                .collect();
            t.mass = weights.iter().sum();
            t.cells = Distribution1D::new(weights);
        }
        let diagonal = bounds.extent().length();
        Some(Self {
            triangles: made,
            bounds,
            power,
            near2: (0.25 * diagonal).powi(2).max(1e-6),
        })
    }

    /// Its weight in the choice at `x` and the mass of its triangles
    /// facing `x`.
    fn weight(&self, x: Vec3) -> (f32, f32) {
        let front: f32 = self
            .triangles
            .iter()
            .filter(|t| t.faces(x))
            .map(|t| t.mass)
            .sum();
        if front <= 0.0 {
            return (0.0, 0.0);
        }
        let nearest = x.max(self.bounds.min).min(self.bounds.max);
        let d2 = (x - nearest).length_squared().max(self.near2);
        (self.power / d2, front)
    }
}

impl Reflectors {
    /// The reflectors among `meshes` (each its triangles) under `lamps`.
    pub fn from_meshes(meshes: &[Vec<[Vec3; 3]>], lamps: &[Lamp]) -> Self {
        let total: f32 = lamps.iter().map(|l| l.watts).sum();
        let mut list: Vec<Reflector> = meshes
            .iter()
            .filter(|m| !m.is_empty() && m.len() <= MAX_TRIANGLES)
            .filter_map(|m| Reflector::new(m, lamps))
            .filter(|r| r.power >= MIN_SHARE * total)
            .collect();
        list.sort_by(|a, b| b.power.total_cmp(&a.power));
        list.truncate(MAX_REFLECTORS);
        Self { list }
    }

    /// The scene's reflectors: glossy, non-emitting meshes lit by its
    /// finite lights (`power[i]`: light i's watts).
    pub fn new(
        materials: &[Bsdf],
        shape_material: &[u32],
        shape_light: &[Option<u32>],
        lights: &[Light],
        power: &[f32],
        extent: &SceneExtent,
    ) -> Self {
        let lamps: Vec<Lamp> = lights
            .iter()
            .zip(power)
            .filter_map(|(l, &watts)| {
                let centre = l.centre(extent.shapes)?;
                (watts.is_finite() && watts > 0.0).then_some(Lamp { centre, watts })
            })
            .collect();
        if lamps.is_empty() {
            return Self::default();
        }
        let meshes: Vec<Vec<[Vec3; 3]>> = extent
            .shapes
            .iter()
            .enumerate()
            .filter_map(|(i, shape)| {
                let Shape::Mesh(m) = shape else { return None };
                let material = materials.get(*shape_material.get(i)? as usize)?;
                let emits = shape_light.get(i).copied().flatten().is_some();
                (glossy(material) && !emits && m.triangle_count() <= MAX_TRIANGLES).then(|| {
                    (0..m.triangle_count())
                        .map(|f| {
                            let (a, b, c) = m.vertices(f);
                            [a, b, c]
                        })
                        .collect()
                })
            })
            .collect();
        Self::from_meshes(&meshes, &lamps)
    }

    /// Whether a vertex of `bsdf` draws from the mixture.
    #[inline]
    fn guides(&self, bsdf: &Bsdf) -> bool {
        !self.list.is_empty() && guided(bsdf)
    }

    pub fn is_empty(&self) -> bool {
        self.list.is_empty()
    }

    /// How many reflectors the scene has.
    pub fn len(&self) -> usize {
        self.list.len()
    }

    /// Each reflector's weight at `x` and its facing mass, and their sum.
    fn weights(&self, x: Vec3) -> Weights {
        let mut w = [(0.0, 0.0); MAX_REFLECTORS];
        let mut total = 0.0;
        for (slot, r) in w.iter_mut().zip(&self.list) {
            *slot = r.weight(x);
            total += slot.0;
        }
        (w, total)
    }

    /// Density per solid angle of reflector sampling at `x` drawing the
    /// unit direction `d`.
    pub fn pdf_refl(&self, x: Vec3, d: Vec3) -> f32 {
        self.pdf_refl_with(x, d, &self.weights(x))
    }

    /// [`Self::pdf_refl`] with the weights at `x`.
    fn pdf_refl_with(&self, x: Vec3, d: Vec3, (w, total): &Weights) -> f32 {
        let total = *total;
        if total <= 0.0 {
            return 0.0;
        }
        let ray = Ray::new(x, d);
        let inv_d = Vec3::new(1.0 / d.x, 1.0 / d.y, 1.0 / d.z);
        let shear = RayShear::new(&ray);
        let mut pdf = 0.0;
        for (r, &(wr, front)) in self.list.iter().zip(w.iter()) {
            if wr <= 0.0 || !r.bounds.hit(&ray, inv_d, f32::INFINITY) {
                continue;
            }
            let choose = wr / total / front;
            for t in r.triangles.iter().filter(|t| t.faces(x)) {
                let Some(h) =
                    intersect_triangle(&ray, &shear, t.a, t.a + t.e1, t.a + t.e2, f32::INFINITY)
                else {
                    continue;
                };
                let cos = t.n.dot(d).abs();
                if cos <= 0.0 {
                    continue;
                }
                let k = cell_of(h.b[1], h.b[2]);
                let cell_area = t.area / (CELLS * CELLS) as f32;
                // P(r)·P(t | r)·P(cell | t)/area(cell), in solid angle.
                let p_area = choose * t.mass * t.cells.probability(k) / cell_area;
                pdf += p_area * h.t * h.t / cos;
            }
        }
        pdf
    }

    /// A direction from `x` towards a reflector point, drawn with `u`
    /// (one number for the choices, two for the point); `None` when none
    /// faces `x`.
    pub fn sample_refl(&self, x: Vec3, u: f32, u_point: [f32; 2]) -> Option<Vec3> {
        self.sample_refl_with(x, u, u_point, &self.weights(x))
    }

    /// [`Self::sample_refl`] with the weights at `x`.
    fn sample_refl_with(
        &self,
        x: Vec3,
        u: f32,
        u_point: [f32; 2],
        (w, total): &Weights,
    ) -> Option<Vec3> {
        let total = *total;
        if total <= 0.0 {
            return None;
        }
        // The reflector, then a facing triangle by mass, then a cell.
        let mut u = u * total;
        let (ri, &(wr, front)) = w[..self.list.len()]
            .iter()
            .enumerate()
            .find(|(_, (wr, _))| {
                let hit = u < *wr;
                if !hit {
                    u -= wr;
                }
                hit
            })
            .or_else(|| {
                w[..self.list.len()]
                    .iter()
                    .enumerate()
                    .rfind(|(_, (wr, _))| *wr > 0.0)
            })?;
        let mut u = (u / wr).clamp(0.0, 1.0) * front;
        let facing = || self.list[ri].triangles.iter().filter(|t| t.faces(x));
        let t = facing()
            .find(|t| {
                let hit = u < t.mass;
                if !hit {
                    u -= t.mass;
                }
                hit
            })
            .or_else(|| facing().next_back())?;
        let (k, _, _) = t
            .cells
            .sample_discrete((u / t.mass).clamp(0.0, 1.0 - f32::EPSILON))?;
        let [p, q, r] = cell_corners(k);
        let s = u_point[0].sqrt();
        let (c1, c2) = (u_point[1] * s, s - u_point[1] * s);
        let b1 = p[0] + c1 * (q[0] - p[0]) + c2 * (r[0] - p[0]);
        let b2 = p[1] + c1 * (q[1] - p[1]) + c2 * (r[1] - p[1]);
        let d = (t.a + t.e1 * b1 + t.e2 * b2 - x).normalize();
        d.is_finite().then_some(d)
    }

    /// The density a bounce from `x` at a vertex of `bsdf` has in unit
    /// direction `d` (world), given the BSDF's own `bsdf_pdf`: what
    /// next-event estimation weighs a light against.
    #[inline]
    pub fn pdf(&self, bsdf: &Bsdf, x: Vec3, d: Vec3, bsdf_pdf: f32) -> f32 {
        if !self.guides(bsdf) {
            return bsdf_pdf;
        }
        (1.0 - SHARE) * bsdf_pdf + SHARE * self.pdf_refl(x, d)
    }

    /// The path tracer's bounce at `point` (its position, shading frame
    /// and shading point): the BSDF sample, or at diffuse vertices a
    /// sample of the mixture, its weight f·cos/q and density q.
    pub(super) fn sample<const K: usize>(
        &self,
        bsdf: &Bsdf,
        wl: &SampledWavelengths<K>,
        point: &ScatterPoint,
        wi: Vec3,
        u_lobe: f32,
        u: [f32; 2],
    ) -> Option<BsdfSample<K>> {
        let ScatterPoint {
            p: x, frame, at, ..
        } = *point;
        let mode = Transport::Radiance;
        if !self.guides(bsdf) {
            return bsdf.sample(wl, at, wi, u_lobe, u, mode);
        }
        let weights = self.weights(x);
        let (f, pdf_bsdf, wo) = if u_lobe < SHARE {
            let d = self.sample_refl_with(x, u_lobe / SHARE, u, &weights)?;
            let wo = frame.to_local(d);
            let f = bsdf.eval(wl, at, wi, wo, mode);
            (f, bsdf.pdf_at(wl, at, wi, wo), wo)
        } else {
            let u_lobe = ((u_lobe - SHARE) / (1.0 - SHARE)).min(1.0 - f32::EPSILON);
            let bs = bsdf.sample(wl, at, wi, u_lobe, u, mode)?;
            if bs.delta {
                return Some(bs);
            }
            (bs.weight * bs.pdf, bs.pdf, bs.wo)
        };
        let q =
            (1.0 - SHARE) * pdf_bsdf + SHARE * self.pdf_refl_with(x, frame.to_world(wo), &weights);
        BsdfSample::mixed(wo, f, q)
    }
}

#[cfg(test)]
mod tests;
