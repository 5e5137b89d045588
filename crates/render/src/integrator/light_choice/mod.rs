//! Which light a path samples: the one choice every integrator consults.
//! By radiant power (SWC's choice of the light that draws a cluster), at a
//! point by power over squared distance (the path tracers' next-event
//! estimation, below), and for a cluster by the posterior of the light
//! that drew it (the bidirectional tracer's light subpaths, `cluster`).
//!
//! By radiant power alone, a point beside one lamp of three samples its
//! own lamp a third of the time and the far ones the rest, though they
//! give it a few percent of its light: its estimate is 3× its mean or
//! nearly 0. On the night street that made the dots on the walls: a wall
//! point's diffuse bounce that reaches the rough aluminium pole just below
//! a sodium globe (0.4 m away) finds a bright glossy reflection there only
//! when the pole's next-event estimation picks that globe.
//!
//! Here light i is chosen with probability
//! (1 − DEFENSIVE)·Iᵢ(x)/ΣI(x) + DEFENSIVE·Φᵢ/ΣΦ, with Iᵢ(x) = Φᵢ/max(d², r²)
//! the power over the squared distance from x to the centre of the
//! light's bounding sphere (radius r, so that no light counts for more
//! than at its own surface), and R² (the scene's bounding radius) for
//! lights at infinity: an irradiance up to a constant factor, which
//! ignores orientation and occlusion, hence the defensive share of the
//! power choice (which alone was unbiased and stays a component, so every
//! light that can contribute keeps a probability > 0). Both densities the
//! estimator uses — at the sampled light and, for MIS, when a BSDF-sampled
//! ray hits an emitter — come from the same function of the point.
//! Scenes with more than [`MAX_NEAR`] lights choose by the light
//! hierarchy instead (`light::LightHierarchy`, Conty Estevez & Kulla
//! 2018): the per-point table is O(lights), the tree's walk O(log lights),
//! and it also weighs each light's orientation and the point's normal.

mod cluster;

pub(crate) use cluster::ClusterChoice;

use crate::geometry::Shape;
use crate::light::{Light, LightHierarchy, SceneExtent};
use crate::math::Vec3;
use crate::sampling::distribution::Distribution1D;
use crate::wavelength::SpectralPdf;

/// Lights up to which the choice depends on the point.
pub const MAX_NEAR: usize = 16;

/// Share of the choice by power alone: scotopia's choice (enough that a
/// light hidden from the near ones' side keeps a tenth of its old rate).
pub const DEFENSIVE: f32 = 0.1;

/// Where a light's power comes from, for the distance term.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Reach {
    /// A bounding sphere.
    Near { center: Vec3, radius2: f32 },
    /// At infinity (directional, constant, map): the scene's radius.
    Far,
}

/// The scene's light choice.
#[derive(Debug, Clone)]
pub struct LightChoice {
    /// By radiant power alone.
    pub power: Distribution1D,
    /// Each light's probability in `power`.
    power_probability: Vec<f32>,
    /// Per light: its reach and power; empty when the choice is by power
    /// alone.
    near: Vec<(Reach, f32)>,
    radius2: f32,
    /// Each light's spectral density (`None`: it emits nothing), for the
    /// choice by cluster.
    spectra: Vec<Option<SpectralPdf>>,
    /// The choice at a point among more than [`MAX_NEAR`] lights.
    tree: Option<LightHierarchy>,
}

impl LightChoice {
    /// `power[i]`: light i's radiant power (W).
    pub fn new(lights: &[Light], power: &[f32], extent: &SceneExtent) -> Self {
        let global = Distribution1D::new(power.to_vec());
        let near = if lights.len() <= MAX_NEAR && lights.len() > 1 {
            lights
                .iter()
                .zip(power)
                .map(|(l, &w)| {
                    let w = if w.is_finite() && w > 0.0 { w } else { 0.0 };
                    (reach(l, extent.shapes), w)
                })
                .collect()
        } else {
            Vec::new()
        };
        Self {
            power_probability: (0..lights.len()).map(|i| global.probability(i)).collect(),
            power: global,
            near,
            radius2: extent.radius * extent.radius,
            spectra: lights
                .iter()
                .map(|l| SpectralPdf::new(l.spectrum()))
                .collect(),
            tree: (lights.len() > MAX_NEAR)
                .then(|| LightHierarchy::new(lights, extent.shapes, power, extent.radius)),
        }
    }

    /// The probabilities of choosing each light at `x`, in `out` (its
    /// first `lights` entries); false when the choice is by power alone.
    #[inline]
    fn at(&self, x: Vec3, out: &mut [f32; MAX_NEAR]) -> bool {
        if self.near.is_empty() || !x.is_finite() {
            return false;
        }
        let mut sum = 0.0f32;
        for (o, (reach, w)) in out.iter_mut().zip(&self.near) {
            let d2 = match reach {
                Reach::Near { center, radius2 } => (*center - x).length_squared().max(*radius2),
                Reach::Far => self.radius2,
            };
            *o = if d2 > 0.0 { w / d2 } else { 0.0 };
            sum += *o;
        }
        if !(sum > 0.0 && sum.is_finite()) {
            return false;
        }
        let keep = (1.0 - DEFENSIVE) / sum;
        for (i, o) in out.iter_mut().take(self.near.len()).enumerate() {
            *o = *o * keep + DEFENSIVE * self.power.probability(i);
        }
        true
    }

    /// Whether the choice at a point is the light hierarchy's (more than
    /// [`MAX_NEAR`] lights): the bidirectional tracer's next-event
    /// estimation then uses it too.
    pub fn by_point(&self) -> bool {
        self.tree.is_some()
    }

    /// A light for next-event estimation at `x` (normal `n`; `None` in a
    /// medium) with `u` ∈ [0, 1), and the probability it was chosen with.
    pub fn sample(&self, x: Vec3, n: Option<Vec3>, u: f32) -> Option<(usize, f32)> {
        if let Some(tree) = &self.tree {
            return tree.sample(x, n, u);
        }
        let mut p = [0.0; MAX_NEAR];
        if !self.at(x, &mut p) {
            return self.power.sample_discrete(u).map(|(i, q, _)| (i, q));
        }
        let n = self.near.len();
        let mut acc = 0.0f32;
        let mut last = None;
        for (i, &q) in p.iter().take(n).enumerate() {
            if q <= 0.0 {
                continue;
            }
            acc += q;
            last = Some((i, q));
            if u < acc {
                return last;
            }
        }
        // Rounding left u past the sum: the last light with weight.
        last
    }

    /// The probability that [`Self::sample`] at `x` (normal `n`) chooses
    /// light `i`.
    pub fn probability(&self, x: Vec3, n: Option<Vec3>, i: usize) -> f32 {
        if let Some(tree) = &self.tree {
            return tree.pmf(x, n, i);
        }
        let mut p = [0.0; MAX_NEAR];
        if self.at(x, &mut p) {
            p.get(i).copied().unwrap_or(0.0)
        } else {
            self.power.probability(i)
        }
    }
}

/// A light's bounding sphere (its position for point-like lights).
fn reach(light: &Light, shapes: &[Shape]) -> Reach {
    match light {
        Light::Area(a) => match shapes.get(a.shape as usize) {
            Some(Shape::Sphere(s)) => Reach::Near {
                center: s.center,
                radius2: s.radius * s.radius,
            },
            Some(shape) => {
                let b = (0..shape.primitive_count())
                    .map(|p| shape.bounds(p))
                    .reduce(|a, b| a.union(b));
                match b {
                    Some(b) if !b.is_empty() => Reach::Near {
                        center: b.centroid(),
                        radius2: 0.25 * b.extent().length_squared(),
                    },
                    _ => Reach::Far,
                }
            }
            None => Reach::Far,
        },
        // Point-like lights: their position.
        _ => match light.centre(shapes) {
            Some(center) => Reach::Near {
                center,
                radius2: 0.0,
            },
            None => Reach::Far,
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Sphere;
    use crate::light::{AreaLight, ConstantLight, PointLight};
    use scotopia_color::cie;

    fn d65() -> scotopia_color::Spectrum {
        cie::illuminant("d65").unwrap()
    }

    /// Two lamps 18 m apart, a sphere lamp between them, and a sky.
    fn scene() -> (Vec<Shape>, Vec<Light>, Vec<f32>) {
        let shapes = vec![Shape::Sphere(Sphere::new(Vec3::new(0.0, 5.0, 0.0), 0.15))];
        let lights = vec![
            Light::Point(PointLight {
                position: Vec3::new(-9.0, 6.0, 0.0),
                intensity: d65(),
            }),
            Light::Point(PointLight {
                position: Vec3::new(9.0, 6.0, 0.0),
                intensity: d65(),
            }),
            Light::Area(AreaLight::new(0, &shapes[0], d65())),
            Light::Constant(ConstantLight { radiance: d65() }),
        ];
        let power = vec![30.0, 30.0, 25.0, 0.5];
        (shapes, lights, power)
    }

    fn choice(shapes: &[Shape], lights: &[Light], power: &[f32]) -> LightChoice {
        let extent = SceneExtent {
            shapes,
            center: Vec3::ZERO,
            radius: 30.0,
            casters: &[],
        };
        LightChoice::new(lights, power, &extent)
    }

    #[test]
    fn the_near_lamp_is_chosen_and_every_light_keeps_a_share() {
        let (shapes, lights, power) = scene();
        let c = choice(&shapes, &lights, &power);
        let x = Vec3::new(-8.0, 5.5, 0.0);
        let p: Vec<f32> = (0..4).map(|i| c.probability(x, None, i)).collect();
        assert!((p.iter().sum::<f32>() - 1.0).abs() < 1e-5, "{p:?}");
        assert!(p[0] > 0.85, "{p:?}");
        for (i, &q) in p.iter().enumerate() {
            assert!(q >= DEFENSIVE * c.power.probability(i) * 0.999, "{p:?}");
        }
        // Beside the sphere lamp, no nearer than its surface counts.
        let y = Vec3::new(0.0, 5.0, 0.0);
        assert!(c.probability(y, None, 2) < 1.0 && c.probability(y, None, 2) > 0.85);
    }

    #[test]
    fn samples_come_with_the_probability_they_are_drawn_with() {
        let (shapes, lights, power) = scene();
        let c = choice(&shapes, &lights, &power);
        let x = Vec3::new(3.0, 1.0, 2.0);
        let n = 100_000;
        let mut counts = [0usize; 4];
        for k in 0..n {
            let u = (k as f32 + 0.5) / n as f32;
            let (i, q) = c.sample(x, None, u).unwrap();
            assert_eq!(q, c.probability(x, None, i));
            counts[i] += 1;
        }
        for (i, &m) in counts.iter().enumerate() {
            let expected = c.probability(x, None, i) as f64 * n as f64;
            // Stratified u: each count is within one or two of its share.
            assert!(
                (m as f64 - expected).abs() <= 2.0,
                "light {i}: {m} vs {expected}"
            );
        }
    }

    #[test]
    fn many_lights_are_chosen_by_the_hierarchy() {
        let lights: Vec<Light> = (0..MAX_NEAR + 1)
            .map(|i| {
                Light::Point(PointLight {
                    position: Vec3::new(i as f32, 0.0, 0.0),
                    intensity: d65(),
                })
            })
            .collect();
        let power: Vec<f32> = (0..lights.len()).map(|i| 1.0 + i as f32).collect();
        let c = choice(&[], &lights, &power);
        let tree = LightHierarchy::new(&lights, &[], &power, 30.0);
        let x = Vec3::new(0.1, 0.0, 0.0);
        let n = Some(Vec3::new(0.0, 1.0, 0.0));
        for i in 0..lights.len() {
            assert_eq!(c.probability(x, n, i), tree.pmf(x, n, i));
        }
        assert_eq!(c.sample(x, n, 0.3), tree.sample(x, n, 0.3));
        // Beside the first lamp, it is chosen far above its power's share.
        assert!(c.probability(x, n, 0) > 10.0 * c.power.probability(0));
    }
}
