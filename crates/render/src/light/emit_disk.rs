//! Where lights at infinity (directional, constant, environment map) start
//! light subpaths: a point on a disk facing the direction d the light
//! travels, behind the scene's bounding sphere (radius R).
//!
//! Uniform over the whole disk, only the share πr²/πR² of the light paths
//! reaches a shape of radius r: for a 0.4 m glass ball in a scene of
//! R = 8.5 m, 0.2 %. Caustics of such a ball seen in a glossy reflection
//! are found by no strategy but a light subpath through it (sun → glass →
//! glass → floor, joined to a camera vertex on the metal), so they came
//! out as sparse, bright dots. Here the point is drawn from a mixture:
//! with probability 1 − [`CASTER_SHARE`] uniformly over the disk, and with
//! [`CASTER_SHARE`] uniformly over the projection of the bounding sphere of
//! a shape whose BSDF is all delta lobes (a "caster": mirrors, smooth
//! glass), each caster alike. The density at a point is the mixture's,
//! the sum over every disk that contains it, whichever branch drew it:
//! every estimate divides by that same density, so the image's expectation
//! is unchanged (a one-sample mixture, Veach 1997 §9.2.3 with the balance
//! heuristic's combined density), and it is the density the MIS weights
//! of the bidirectional tracer see.

use super::SceneExtent;
use crate::math::{Frame, Vec3};
use crate::sampling::warp::square_to_disk_concentric;

/// Share of the emission points aimed at casters, when there are any:
/// scotopia's choice. The rest of the scene keeps 3/4 of its light paths
/// (at most 4/3 on the variance of what they alone find), while each of
/// n casters of radius r gets (R/r)²·0.25/n times more paths than uniform
/// sampling gives it: ≈ 56 for the showcase's glass ball (R = 8.5 m,
/// r = 0.4 m, n = 2). Measured on the showcase (320×180, 48 spp): 0.25
/// removed as many of the outliers on the copper and plastic balls as 0.5
/// for 25 % more time instead of 50 % (docs/bdpt.md).
pub const CASTER_SHARE: f32 = 0.25;

/// Casters considered at most (the density sums over all of them at every
/// evaluation); the largest are kept.
pub const MAX_CASTERS: usize = 32;

/// The largest f32 below 1: keeps a rescaled sample number in [0, 1).
const ONE_MINUS_EPSILON: f32 = 0.999_999_94;

/// A caster's bounding sphere.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Caster {
    pub center: Vec3,
    pub radius: f32,
}

impl Caster {
    /// The casters among `bounds` (each shape's bounding sphere, and
    /// whether its BSDF is all delta lobes): the `MAX_CASTERS` largest,
    /// ignoring degenerate ones.
    pub fn select(bounds: impl IntoIterator<Item = (Caster, bool)>) -> Vec<Caster> {
        let mut v: Vec<Caster> = bounds
            .into_iter()
            .filter(|(c, delta)| *delta && c.radius > 0.0 && c.radius.is_finite())
            .map(|(c, _)| c)
            .collect();
        v.sort_by(|a, b| b.radius.total_cmp(&a.radius));
        v.truncate(MAX_CASTERS);
        v
    }
}

impl SceneExtent<'_> {
    fn caster_share(&self) -> f32 {
        if self.casters.is_empty() {
            0.0
        } else {
            CASTER_SHARE
        }
    }

    /// A point of the emission disk for light travelling in `d` (unit),
    /// drawn with `u` ∈ [0, 1)², and its density per unit area.
    pub fn sample_disk(&self, d: Vec3, u: [f32; 2]) -> (Vec3, f32) {
        let f = Frame::from_normal(d);
        let share = self.caster_share();
        let [x, y] = if u[0] < share {
            // Choose a caster with u₀ and reuse what is left of it.
            let n = self.casters.len();
            let v = u[0] / share * n as f32;
            let i = (v as usize).min(n - 1);
            let c = &self.casters[i];
            let u0 = (v - i as f32).clamp(0.0, ONE_MINUS_EPSILON);
            let [x, y] = square_to_disk_concentric([u0, u[1]]);
            let o = c.center - self.center;
            [o.dot(f.s) + x * c.radius, o.dot(f.t) + y * c.radius]
        } else {
            let u0 = ((u[0] - share) / (1.0 - share)).min(ONE_MINUS_EPSILON);
            let [x, y] = square_to_disk_concentric([u0, u[1]]);
            [x * self.radius, y * self.radius]
        };
        let p = self.center + (f.s * x + f.t * y - d * self.radius);
        (p, self.density(&f, x, y))
    }

    /// Density per unit area of [`Self::sample_disk`] at the point of the
    /// disk on the line through `p` along `d` (any point of that line).
    pub fn disk_pdf(&self, d: Vec3, p: Vec3) -> f32 {
        let f = Frame::from_normal(d);
        let o = p - self.center;
        self.density(&f, o.dot(f.s), o.dot(f.t))
    }

    /// The mixture's density at disk coordinates (x, y) in frame `f`.
    fn density(&self, f: &Frame, x: f32, y: f32) -> f32 {
        let share = self.caster_share();
        let pi = std::f32::consts::PI;
        let r2 = self.radius * self.radius;
        let mut pdf = if x * x + y * y <= r2 {
            (1.0 - share) / (pi * r2)
        } else {
            0.0
        };
        let each = share / self.casters.len().max(1) as f32;
        for c in self.casters {
            let o = c.center - self.center;
            let (dx, dy) = (x - o.dot(f.s), y - o.dot(f.t));
            let cr2 = c.radius * c.radius;
            if dx * dx + dy * dy <= cr2 {
                pdf += each / (pi * cr2);
            }
        }
        pdf
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_rng::{mean_and_se, uniforms};

    const CENTER: Vec3 = Vec3::new(1.0, 2.0, -3.0);
    const RADIUS: f32 = 8.0;

    /// Three casters: two that overlap, one partly outside the scene's
    /// disk (a mesh's bounding sphere can reach past the scene's).
    fn casters() -> [Caster; 3] {
        [
            Caster {
                center: CENTER + Vec3::new(0.5, 0.4, 0.0),
                radius: 0.4,
            },
            Caster {
                center: CENTER + Vec3::new(0.9, 0.4, 0.3),
                radius: 0.6,
            },
            Caster {
                center: CENTER + Vec3::new(-7.8, 0.0, 1.0),
                radius: 0.5,
            },
        ]
    }

    fn extent(casters: &[Caster]) -> SceneExtent<'_> {
        SceneExtent {
            shapes: &[],
            center: CENTER,
            radius: RADIUS,
            casters,
        }
    }

    fn directions() -> [Vec3; 3] {
        [
            Vec3::new(0.0, -1.0, 0.0),
            Vec3::new(-0.5265, -0.5736, -0.6275).normalize(),
            Vec3::new(0.3, 0.2, 0.93).normalize(),
        ]
    }

    #[test]
    fn the_density_integrates_to_one() {
        // Uniform points over a square that holds every disk.
        let c = casters();
        let half = RADIUS + 1.0;
        let mut u = uniforms(3);
        for caster_list in [&c[..], &[]] {
            let e = extent(caster_list);
            for d in directions() {
                let f = Frame::from_normal(d);
                let x: Vec<f64> = (0..400_000)
                    .map(|_| {
                        let (a, b) = ((2.0 * u() - 1.0) * half, (2.0 * u() - 1.0) * half);
                        let p = CENTER + f.s * a + f.t * b + d * 3.0;
                        e.disk_pdf(d, p) as f64 * (2.0 * half as f64).powi(2)
                    })
                    .collect();
                let (m, se) = mean_and_se(&x);
                assert!((m - 1.0).abs() < 4.0 * se, "∫pdf = {m} ± {se} along {d:?}");
            }
        }
    }

    #[test]
    fn samples_follow_the_density_they_report() {
        // E[g/pdf] over the samples is ∫g: for g the indicator of a region,
        // its area. Regions: the scene's disk, a disk around the
        // overlapping casters, and the caster that reaches outside.
        let c = casters();
        let e = extent(&c);
        let mut u = uniforms(7);
        for d in directions() {
            let f = Frame::from_normal(d);
            let at = |q: Vec3| {
                let o = q - CENTER;
                (o.dot(f.s), o.dot(f.t))
            };
            let (c0x, c0y) = at(c[0].center);
            let (c2x, c2y) = at(c[2].center);
            let regions: [&dyn Fn(f32, f32) -> bool; 3] = [
                &|x, y| x * x + y * y <= RADIUS * RADIUS,
                &|x, y| (x - c0x).powi(2) + (y - c0y).powi(2) <= 1.0,
                &|x, y| (x - c2x).powi(2) + (y - c2y).powi(2) <= 0.25,
            ];
            let areas = [
                std::f64::consts::PI * (RADIUS as f64).powi(2),
                std::f64::consts::PI,
                std::f64::consts::PI * 0.25,
            ];
            let n = 200_000;
            let mut sums: [Vec<f64>; 3] = Default::default();
            let mut mismatched = 0;
            for _ in 0..n {
                let (p, pdf) = e.sample_disk(d, [u(), u()]);
                assert!(((p - CENTER).dot(d) + RADIUS).abs() < 1e-4 * RADIUS);
                let again = e.disk_pdf(d, p);
                if (again - pdf).abs() > 1e-3 * pdf {
                    mismatched += 1;
                }
                let (x, y) = at(p);
                for (k, inside) in regions.iter().enumerate() {
                    let g = if pdf > 0.0 && inside(x, y) {
                        1.0 / pdf as f64
                    } else {
                        0.0
                    };
                    sums[k].push(g);
                }
            }
            // Points on a disk's rim may round to either side.
            assert!(mismatched <= n / 10_000, "{mismatched} densities differ");
            for k in 0..3 {
                let (m, se) = mean_and_se(&sums[k]);
                assert!(
                    (m - areas[k]).abs() < 4.0 * se,
                    "region {k} along {d:?}: {m} ± {se}, area {}",
                    areas[k]
                );
            }
        }
    }

    #[test]
    fn without_casters_the_disk_is_uniform() {
        let e = extent(&[]);
        let mut u = uniforms(11);
        let d = directions()[1];
        for _ in 0..1000 {
            let (p, pdf) = e.sample_disk(d, [u(), u()]);
            let uniform = 1.0 / (std::f32::consts::PI * RADIUS * RADIUS);
            assert_eq!(pdf, uniform);
            assert_eq!(e.disk_pdf(d, p), uniform);
        }
    }

    #[test]
    fn casters_are_the_largest_delta_shapes() {
        let ball = |r: f32| Caster {
            center: Vec3::ZERO,
            radius: r,
        };
        let mut shapes: Vec<(Caster, bool)> = (0..40).map(|i| (ball(i as f32), true)).collect();
        shapes.push((ball(100.0), false));
        shapes.push((ball(f32::NAN), true));
        let c = Caster::select(shapes);
        assert_eq!(c.len(), MAX_CASTERS);
        assert_eq!(c[0].radius, 39.0);
        assert!(c.iter().all(|c| c.radius > 0.0 && c.radius < 40.0));
    }
}
