//! Per-light bounds (box, power, cone of emitted directions) and the
//! importance of a cluster of lights at a receiving point.
//!
//! The bounds and the importance follow Conty Estevez & Kulla 2018,
//! "Importance Sampling of Many Lights with Adaptive Tree Splitting"
//! (§4.1 the orientation bounds (axis w, θ_o, θ_e); §4.2 the cluster
//! importance), in the form of pbrt-v4's `LightBounds::Importance` (Pharr,
//! Jakob & Humphreys, *Physically Based Rendering*, 4th ed., §12.6.3):
//! the angles are clamped conservatively by the cone the cluster's
//! bounding sphere fills as seen from the point, so that no light that can
//! reach the point gets importance 0.

use std::f32::consts::{FRAC_PI_2, PI};

use super::super::Light;
use crate::geometry::Shape;
use crate::math::{Aabb, Vec3};

/// Widening of every angular bound, radians: the importance's cosines and
/// the lights' own direction tests round differently, and a light on the
/// edge of its cone must not lose its probability to that.
pub(super) const ANGLE_MARGIN: f32 = 1e-2;

/// Least orientation and receiver factor of a cluster that passes the
/// cone test: a light at grazing angle keeps a small probability (the
/// cosines are bounds, and rounding may put them at or below 0).
const COS_FLOOR: f32 = 1e-3;

/// A cone of directions: unit axis `w`, half-angle `theta` (π: all).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Cone {
    pub w: Vec3,
    pub theta: f32,
}

impl Cone {
    pub const ALL: Cone = Cone {
        w: Vec3::new(0.0, 0.0, 1.0),
        theta: PI,
    };

    pub fn new(w: Vec3, theta: f32) -> Self {
        let w = w.normalize();
        if theta >= PI || !w.is_finite() || !theta.is_finite() {
            return Self::ALL;
        }
        Self {
            w,
            theta: theta.max(0.0),
        }
    }

    /// The least cone (up to a margin for rounding) that holds both: the
    /// cone around the arc from one axis to the other (Conty Estevez &
    /// Kulla 2018, §4.1).
    pub fn union(self, o: Cone) -> Cone {
        if self.theta >= PI || o.theta >= PI {
            return Self::ALL;
        }
        let d = angle_between(self.w, o.w);
        if (d + o.theta).min(PI) <= self.theta {
            return self;
        }
        if (d + self.theta).min(PI) <= o.theta {
            return o;
        }
        let theta = 0.5 * (self.theta + d + o.theta);
        if theta >= PI {
            return Self::ALL;
        }
        // Turn our axis towards the other's by θ − θ_self.
        let perp = o.w - self.w * self.w.dot(o.w);
        let len = perp.length();
        if len.is_nan() || len <= 1e-6 {
            return Self::ALL;
        }
        let r = theta - self.theta;
        let w = self.w * r.cos() + perp * (r.sin() / len);
        Cone::new(w, theta + 1e-4)
    }
}

/// Angle between unit vectors, accurate near 0 and π.
fn angle_between(a: Vec3, b: Vec3) -> f32 {
    if a.dot(b) < 0.0 {
        PI - 2.0 * ((a + b).length() * 0.5).min(1.0).asin()
    } else {
        2.0 * ((b - a).length() * 0.5).min(1.0).asin()
    }
}

/// What the tree knows of a light or a cluster: its box, its power φ, the
/// cone `normals` around which it emits (θ_o) and how far beyond that cone
/// emission reaches (θ_e).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct LightBounds {
    pub aabb: Aabb,
    pub phi: f32,
    pub normals: Cone,
    pub theta_e: f32,
}

impl LightBounds {
    pub fn union(&self, o: &LightBounds) -> LightBounds {
        LightBounds {
            aabb: self.aabb.union(o.aabb),
            phi: (self.phi + o.phi).min(f32::MAX),
            normals: self.normals.union(o.normals),
            theta_e: self.theta_e.max(o.theta_e),
        }
    }

    /// The orientation measure M_Ω of the paper's SAOH (Conty Estevez &
    /// Kulla 2018, §4.3): the solid angle of the normal cone plus the
    /// cosine-weighted spread beyond it out to θ_w = min(θ_o + θ_e, π).
    pub fn orientation_measure(&self) -> f32 {
        let (o, e) = (self.normals.theta, self.theta_e);
        let w = (o + e).min(PI);
        let (sin_o, cos_o) = o.sin_cos();
        2.0 * PI * (1.0 - cos_o)
            + FRAC_PI_2 * (2.0 * w * sin_o - (o - 2.0 * w).cos() - 2.0 * o * sin_o + cos_o)
    }

    /// What the traversal needs, with the cosines precomputed.
    pub fn compact(&self) -> NodeBounds {
        let centre = self.aabb.centroid();
        let r2 = 0.25 * self.aabb.extent().length_squared();
        let (sin_o, cos_o) = if self.normals.theta >= PI {
            (0.0, -1.0)
        } else {
            self.normals.theta.sin_cos()
        };
        NodeBounds {
            centre,
            r2,
            w: self.normals.w,
            phi: self.phi,
            cos_o,
            sin_o,
            cos_e: (self.theta_e.min(PI)).cos(),
        }
    }
}

/// A node's bounds as the importance reads them: the centre and squared
/// radius of the box's bounding sphere, the cone (w, cos θ_o, sin θ_o),
/// cos θ_e and φ.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct NodeBounds {
    pub centre: Vec3,
    pub r2: f32,
    pub w: Vec3,
    pub phi: f32,
    pub cos_o: f32,
    pub sin_o: f32,
    pub cos_e: f32,
}

/// (cos, sin) of max(0, a − b), from the cosines and sines of a and b
/// (angles in [0, π]).
#[inline]
fn minus_clamped(cos_a: f32, sin_a: f32, cos_b: f32, sin_b: f32) -> (f32, f32) {
    if cos_a >= cos_b {
        (1.0, 0.0)
    } else {
        (cos_a * cos_b + sin_a * sin_b, sin_a * cos_b - cos_a * sin_b)
    }
}

#[inline]
fn sin_of(cos: f32) -> f32 {
    (1.0 - cos * cos).max(0.0).sqrt()
}

impl NodeBounds {
    /// The importance of the cluster at `p` (receiving normal `n`, unit,
    /// counted on both sides; `None`: no cosine at the receiver):
    ///
    ///   I = φ · cos θ' / max(d², r²/4) · cos θ'_i,  0 when θ' ≥ θ_e,
    ///
    /// (Conty Estevez & Kulla 2018, §4.2, the cluster importance; pbrt-v4
    /// §12.6.3, `LightBounds::Importance`), with d the distance from `p` to
    /// the centre of the box's bounding sphere, r its radius (half the
    /// box's diagonal), θ_b the half-angle of the
    /// cone that sphere fills seen from `p` (π inside it),
    /// θ' = max(0, θ_w − θ_o − θ_b) the least angle between the cluster's
    /// normal cone and the directions from its points to `p` (θ_w the angle
    /// between the axis w and the direction from the centre to `p`), and
    /// θ'_i = max(0, θ_i − θ_b) the least angle between ±n and the
    /// directions from `p` to the box. Both cosines are bounds from above
    /// over the cluster, so a light that can reach `p` has I > 0.
    ///
    /// The clamp at (r/2)² keeps points inside or near a box from blowing
    /// up. Half the radius rather than pbrt's whole: seen from its
    /// surface a sphere light of radius R irradiates as a point light at
    /// distance R would, and (r/2)² = ¾R² is near that where r² = 3R² is
    /// not; and a point beside a long row of lamps (a street) would
    /// otherwise see the row as though it were as far as its half-length,
    /// and spend half its samples on lamps far down the street.
    #[inline]
    pub fn importance(&self, p: Vec3, n: Option<Vec3>) -> f32 {
        let to = p - self.centre;
        let dc2 = to.length_squared();
        // The distance term, clamped at half the bounding sphere's radius
        // (and at the least normal f32, for a point light at p).
        let d2 = dc2.max(0.25 * self.r2).max(f32::MIN_POSITIVE);
        let wi = if dc2 > 0.0 {
            to * (1.0 / dc2.sqrt())
        } else {
            Vec3::ZERO
        };
        // The cone of directions the bounding sphere fills from p.
        let (cos_b, sin_b) = if dc2 <= self.r2 {
            (-1.0, 0.0)
        } else {
            let sin2 = self.r2 / dc2;
            ((1.0 - sin2).max(0.0).sqrt(), sin2.sqrt())
        };
        // θ' = max(0, θ_w − θ_o − θ_b).
        let cos_w = self.w.dot(wi).clamp(-1.0, 1.0);
        let (cos_x, sin_x) = minus_clamped(cos_w, sin_of(cos_w), self.cos_o, self.sin_o);
        let (cos_p, _) = minus_clamped(cos_x, sin_x, cos_b, sin_b);
        if cos_p <= self.cos_e {
            return 0.0;
        }
        let mut importance = self.phi * cos_p.max(COS_FLOOR) / d2;
        if let Some(n) = n {
            // θ'_i = max(0, θ_i − θ_b), θ_i ∈ [0, π/2] from |cos|.
            let cos_i = n.dot(wi).abs().min(1.0);
            let (cos_ip, _) = minus_clamped(cos_i, sin_of(cos_i), cos_b, sin_b);
            importance *= cos_ip.max(COS_FLOOR);
        }
        if importance > 0.0 {
            importance.min(f32::MAX)
        } else {
            0.0
        }
    }
}

/// Solid angle of a cone of half-angle θ.
fn cone_solid_angle(theta: f32) -> f64 {
    2.0 * std::f64::consts::PI * (1.0 - (theta.min(PI) as f64).cos())
}

/// φ for the importance: 4π times the light's mean intensity over the
/// directions it emits into (the cone of half-angle θ_o + θ_e), so that
/// a spot light or a flat panel is weighed by the intensity it sends
/// where it shines rather than by its total power spread over the sphere
/// (pbrt-v4 weighs a spot light likewise, by 4π I_max); for a point light
/// or a sphere it is the power itself.
fn phi_of(power: f32, emit_theta: f32) -> f32 {
    let solid = cone_solid_angle(emit_theta).max(1e-12);
    (power as f64 * 4.0 * std::f64::consts::PI / solid).min(f32::MAX as f64 * 1e-6) as f32
}

/// A point-like light's bounds at `position`, emitting only within
/// `emit` (its axis and the angle out to which it emits; `Cone::ALL`: every
/// direction), bright along its axis out to `full` (≤ emit.theta).
fn point_like(position: Vec3, power: f32, emit: Cone, full: f32) -> LightBounds {
    let (normals, theta_e) = if emit.theta >= PI {
        (Cone::ALL, FRAC_PI_2)
    } else {
        let full = full.clamp(0.0, emit.theta);
        (Cone::new(emit.w, full), emit.theta - full + ANGLE_MARGIN)
    };
    LightBounds {
        aabb: Aabb {
            min: position,
            max: position,
        },
        phi: phi_of(power, emit.theta),
        normals,
        theta_e,
    }
}

/// The bounds of a light with a place (`None` for lights at infinity and
/// area lights whose shape is missing or empty). `power` > 0, finite.
pub(super) fn light_bounds(light: &Light, shapes: &[Shape], power: f32) -> Option<LightBounds> {
    match light {
        Light::Point(l) => Some(point_like(l.position, power, Cone::ALL, PI)),
        // Full intensity within the beam width, zero beyond the cutoff.
        Light::Spot(l) => {
            let emit = Cone::new(l.frame.n, l.cutoff);
            Some(point_like(l.position, power, emit, l.beam_width))
        }
        // Lit only between the grid's outermost lit rows: around the nadir
        // out to γ_hi, or around the zenith out to π − γ_lo, the narrower.
        Light::Goniometric(l) => {
            let (lo, hi) = l.grid.lit_gamma();
            let emit = if PI - lo < hi {
                Cone::new(-l.frame.n, PI - lo)
            } else {
                Cone::new(l.frame.n, hi)
            };
            Some(point_like(l.position, power, emit, emit.theta))
        }
        // A projector lights only directions in front of its lens (camera
        // z > 0): the half-space whose normal is camera space's z row in
        // world space (the inverse transpose of world-from-camera).
        Light::Projector(l) => {
            let axis = l.camera.world_from_camera.normal(Vec3::new(0.0, 0.0, 1.0));
            let emit = Cone::new(axis, FRAC_PI_2 + ANGLE_MARGIN);
            Some(point_like(l.position, power, emit, emit.theta))
        }
        Light::Area(a) => {
            let shape = shapes.get(a.shape as usize)?;
            let aabb = (0..shape.primitive_count())
                .fold(Aabb::EMPTY, |b, prim| b.union(shape.bounds(prim)));
            if aabb.is_empty() || !aabb.min.is_finite() || !aabb.max.is_finite() {
                return None;
            }
            let normals = normal_cone(shape);
            // One-sided (AreaLight::radiance): emission within π/2 of the
            // normals.
            let theta_e = FRAC_PI_2 + ANGLE_MARGIN;
            Some(LightBounds {
                aabb,
                phi: phi_of(power, normals.theta + theta_e),
                normals,
                theta_e,
            })
        }
        Light::Directional(_) | Light::Constant(_) | Light::EnvMap(_) => None,
    }
}

/// The cone of a shape's emitting normals.
fn normal_cone(shape: &Shape) -> Cone {
    match shape {
        Shape::Planar(p) => Cone::new(p.normal(), 0.0),
        Shape::Mesh(m) => {
            let mut cone: Option<Cone> = None;
            let add = |cone: &mut Option<Cone>, c: Cone| {
                *cone = Some(match *cone {
                    None => c,
                    Some(k) => k.union(c),
                });
            };
            for f in 0..m.triangle_count() {
                let (a, b, c) = m.vertices(f);
                let n = (b - a).cross(c - a).normalize();
                if !n.is_finite() {
                    // No area: never sampled, never hit.
                    continue;
                }
                add(&mut cone, Cone::new(n, 0.0));
                // A hit's normal follows the shading normals' side
                // (`Shape::surface`): where a vertex normal disagrees with
                // the winding, the triangle may emit from its back.
                if let Some(ns) = &m.normals {
                    if m.indices[f].iter().any(|&i| ns[i as usize].dot(n) <= 0.0) {
                        add(&mut cone, Cone::new(-n, 0.0));
                    }
                }
                if cone.is_some_and(|c| c.theta >= PI) {
                    break;
                }
            }
            cone.unwrap_or(Cone::ALL)
        }
        // Spheres and cylinders face every way.
        Shape::Sphere(_) | Shape::Cylinder(_) => Cone::ALL,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_rng::Rng;

    fn unit(rng: &mut Rng) -> Vec3 {
        loop {
            let v = rng.vec(-1.0, 1.0);
            if v.length_squared() > 1e-3 && v.length_squared() <= 1.0 {
                return v.normalize();
            }
        }
    }

    #[test]
    fn a_union_of_cones_holds_both() {
        let mut rng = Rng(7);
        for _ in 0..2000 {
            let a = Cone::new(unit(&mut rng), rng.next() * 1.5);
            let b = Cone::new(unit(&mut rng), rng.next() * 1.5);
            let u = a.union(b);
            for c in [a, b] {
                // Every direction of c is in u: c's axis within u.θ − c.θ.
                if u.theta < PI {
                    assert!(
                        angle_between(u.w, c.w) + c.theta <= u.theta + 1e-5,
                        "{a:?} {b:?} {u:?}"
                    );
                }
            }
        }
    }

    #[test]
    fn the_orientation_measure_of_a_hemisphere_emitter() {
        // θ_o = 0, θ_e = π/2: ∫ cos over the hemisphere = π.
        let b = LightBounds {
            aabb: Aabb::EMPTY,
            phi: 1.0,
            normals: Cone::new(Vec3::new(0.0, 0.0, 1.0), 0.0),
            theta_e: FRAC_PI_2,
        };
        assert!((b.orientation_measure() - PI).abs() < 1e-5);
        // θ_o = π: the whole sphere, 4π (+ the cosine lobe beyond it, 0).
        let all = LightBounds {
            normals: Cone::ALL,
            ..b
        };
        assert!((all.orientation_measure() - 4.0 * PI).abs() < 1e-4);
    }
}
