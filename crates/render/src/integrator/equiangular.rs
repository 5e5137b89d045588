//! Equi-angular sampling of scattering distances towards lights (Kulla &
//! Fajardo 2012, "Importance Sampling Techniques for Path Tracing in
//! Participating Media", §3), combined by MIS with free flights for the
//! direct light at scattering points.
//!
//! Free flights put scattering points where the medium's transmittance
//! does, so a ray passing a small bright lamp rarely scatters in the few
//! centimetres where the lamp fills much of the sky — and when it does, the
//! estimate is thousands of times the pixel's: the bright dots in a lamp's
//! halo, and in every pixel whose paths wander near one. Drawing the
//! distance t with density ∝ 1/(h² + (t − Δ)²) towards a lamp's centre
//! (h: the ray's distance from it) makes those points common and their
//! estimates small. For each segment in a homogeneous medium the tracer
//! makes one such extra scattering point and estimates its direct light
//! (next-event estimation there, as at free-flight points); the two
//! distance strategies are weighted by the power heuristic on their
//! densities per unit length. Both estimate the light at x_t by the same
//! next-event estimation, so its density cancels from the weights, which
//! with phase sampling's (unchanged) still sum to one.

use crate::math::{Ray, Vec3};

/// The lights equi-angular sampling aims at: every light with a position
/// (points, spots, luminaires, area lights by their bounding box's centre),
/// with its share of the scene's power.
#[derive(Debug, Clone, Default)]
pub struct Targets {
    /// (centre, power share).
    lights: Vec<(Vec3, f32)>,
    /// The least distance from a ray to a centre used (a small fraction of
    /// the scene), so a ray through a centre keeps a finite density.
    min_h: f32,
}

impl Targets {
    pub fn new(lights: Vec<(Vec3, f32)>, scene_radius: f32) -> Self {
        Self {
            lights: lights.into_iter().filter(|&(_, p)| p > 0.0).collect(),
            min_h: 1e-4 * scene_radius.max(1e-6),
        }
    }

    pub fn is_empty(&self) -> bool {
        self.lights.is_empty()
    }

    /// The lights with power, (centre, power share), and the least
    /// distance to a centre used: what halo sampling aims at too.
    pub fn lamps(&self) -> (&[(Vec3, f32)], f32) {
        (&self.lights, self.min_h)
    }

    /// Each target's choice weight for `ray` (power over squared distance
    /// from the ray's line), its Δ and h.
    fn geometry(&self, ray: &Ray) -> impl Iterator<Item = (f32, f32, f32)> + '_ {
        let (o, d) = (ray.o, ray.d);
        self.lights.iter().map(move |&(c, power)| {
            let oc = c - o;
            let delta = oc.dot(d);
            let h = (oc - d * delta).length().max(self.min_h);
            (power / (h * h), delta, h)
        })
    }

    /// A distance in [0, `t_max`) along `ray` (unit direction) and its
    /// density per unit length (the mixture over the targets), from two
    /// uniform numbers; `None` without targets.
    pub fn sample(&self, ray: &Ray, t_max: f32, u_pick: f32, u_t: f32) -> Option<(f32, f32)> {
        let total: f32 = self.geometry(ray).map(|g| g.0).sum();
        if !(total > 0.0 && total.is_finite()) {
            return None;
        }
        let mut pick = u_pick * total;
        let mut chosen = None;
        for g in self.geometry(ray) {
            chosen = Some(g);
            if pick < g.0 {
                break;
            }
            pick -= g.0;
        }
        let (_, delta, h) = chosen?;
        let (a, b) = angles(delta, h, t_max);
        let theta = a + u_t * (b - a);
        let t = (delta + h * theta.tan()).clamp(0.0, t_max);
        let pdf = self.pdf(ray, t_max, t);
        (t < t_max && pdf > 0.0 && pdf.is_finite()).then_some((t, pdf))
    }

    /// The mixture's density at distance `t` along `ray` (per unit length).
    pub fn pdf(&self, ray: &Ray, t_max: f32, t: f32) -> f32 {
        let total: f32 = self.geometry(ray).map(|g| g.0).sum();
        if !(total > 0.0 && total.is_finite()) {
            return 0.0;
        }
        self.geometry(ray)
            .map(|(w, delta, h)| {
                let (a, b) = angles(delta, h, t_max);
                let x = t - delta;
                w / total * h / ((b - a) * (h * h + x * x))
            })
            .sum()
    }
}

/// The angles, seen from the target, of the segment's ends (0 and t_max).
fn angles(delta: f32, h: f32, t_max: f32) -> (f32, f32) {
    let b = if t_max.is_finite() {
        (t_max - delta).atan2(h)
    } else {
        std::f32::consts::FRAC_PI_2
    };
    ((-delta).atan2(h), b)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_rng::uniforms;

    #[test]
    fn the_density_integrates_to_one_and_matches_the_samples() {
        let targets = Targets::new(
            vec![
                (Vec3::new(1.0, 0.5, 2.0), 3.0),
                (Vec3::new(-2.0, 0.1, 7.0), 1.0),
            ],
            10.0,
        );
        let ray = Ray::new(Vec3::ZERO, Vec3::new(0.0, 0.0, 1.0));
        for t_max in [5.0f32, 40.0, f32::INFINITY] {
            // ∫ pdf over [0, t_max) by the substitution t = tan(φ), φ
            // uniform (the density has 1/(1 + t²)-like tails).
            let n = 200_000;
            let top = if t_max.is_finite() {
                t_max.atan()
            } else {
                std::f32::consts::FRAC_PI_2
            };
            let sum: f64 = (0..n)
                .map(|i| {
                    let phi = (i as f32 + 0.5) / n as f32 * top;
                    let t = phi.tan();
                    (targets.pdf(&ray, t_max, t) * (1.0 + t * t)) as f64
                })
                .sum::<f64>()
                * top as f64
                / n as f64;
            assert!((sum - 1.0).abs() < 2e-3, "t_max {t_max}: {sum}");
            // Samples fall in [0, t_max) with the density's mass: the share
            // below 3 against ∫₀³ pdf.
            let mut u = uniforms(4);
            let m = 100_000;
            let below = (0..m)
                .filter_map(|_| targets.sample(&ray, t_max, u(), u()))
                .filter(|&(t, _)| t < 3.0)
                .count() as f64
                / m as f64;
            let k = 20_000;
            let mass: f64 = (0..k)
                .map(|i| targets.pdf(&ray, t_max, 3.0 * (i as f32 + 0.5) / k as f32) as f64)
                .sum::<f64>()
                * 3.0
                / k as f64;
            let se = (mass * (1.0 - mass) / m as f64).sqrt();
            assert!(
                (below - mass).abs() < 4.0 * se + 1e-4,
                "t_max {t_max}: {below} vs {mass}"
            );
        }
    }
}
