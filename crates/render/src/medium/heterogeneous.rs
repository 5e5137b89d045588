//! A heterogeneous medium (Mitsuba 3's `heterogeneous`): σ_t and the
//! albedo are fields (`volume::Field`: a grid or a constant), σ_t times
//! `scale`, and the medium fills the unit cube of σ_t's volume as its
//! `to_world` places it (outside that box σ_t is 0; Mitsuba clips rays to
//! the box's world-space bounding box, the same box unless it is rotated).
//!
//! Free flights are delta-tracked and transmittance ratio-tracked against
//! a grey majorant σ̄ ≥ σ_t,k for every wavelength of the cluster, taken
//! per super-voxel (`majorant`): Woodcock et al. 1965; Novák et al. 2014,
//! "Residual Ratio Tracking" (ratio tracking, their eq. 6); pbrt-v4
//! §14.2.2 for spectral tracking with the cluster's densities.

use scotopia_color::spectrum::normalised_lambda;
use scotopia_color::{SampledSpectrum, SampledWavelengths};

use super::majorant::Majorants;
use super::volume::Field;
use super::{densities_from_logs, MediumEvent, Phase};
use crate::math::{Aabb, Ray, Transform, Vec3};
use crate::sampling::splitmix::SplitMix;

#[derive(Debug, Clone, PartialEq)]
pub struct Heterogeneous {
    sigma_t: Field,
    albedo: Field,
    scale: f32,
    pub phase: Phase,
    majorants: Majorants,
}

/// Ratio tracking's Russian roulette (unbiased: survivors are divided by
/// the survival probability): below this largest transmittance, a walk
/// goes on with probability `RR_SURVIVE`.
const RR_BELOW: f32 = 0.05;
const RR_SURVIVE: f32 = 0.25;

impl Heterogeneous {
    /// σ_t's field times `scale` (finite, not negative) and the albedo's.
    pub fn new(sigma_t: Field, albedo: Field, scale: f32, phase: Phase) -> Self {
        let majorants = Majorants::of(&sigma_t);
        Self {
            sigma_t,
            albedo,
            scale,
            phase,
            majorants,
        }
    }

    pub fn sigma_t_field(&self) -> &Field {
        &self.sigma_t
    }

    pub fn albedo_field(&self) -> &Field {
        &self.albedo
    }

    pub fn scale(&self) -> f32 {
        self.scale
    }

    pub fn majorants(&self) -> &Majorants {
        &self.majorants
    }

    /// World to the medium's unit cube.
    pub fn to_local(&self) -> &Transform {
        self.sigma_t.to_local()
    }

    /// The world-space bounding box of the medium's box.
    pub fn world_bounds(&self) -> Aabb {
        let to_world = self.to_local().inverse();
        let corners: Vec<Vec3> = (0..8)
            .map(|i| {
                let c = |bit: usize| if i & bit == 0 { 0.0 } else { 1.0 };
                to_world.point(Vec3::new(c(1), c(2), c(4)))
            })
            .collect();
        Aabb::from_points(&corners)
    }

    /// σ_t (scaled) at world point `p`: 0 outside the medium's box.
    pub fn sigma_t<const K: usize>(
        &self,
        p: Vec3,
        wl: &SampledWavelengths<K>,
    ) -> SampledSpectrum<K> {
        let l = self.to_local().point(p);
        let inside = [l.x, l.y, l.z].iter().all(|v| (0.0..=1.0).contains(v));
        if !inside {
            return SampledSpectrum::splat(0.0);
        }
        self.sigma_t.eval(p, wl).map(|s| (s * self.scale).max(0.0))
    }

    /// The albedo at world point `p`, clamped to [0, 1].
    pub fn albedo<const K: usize>(
        &self,
        p: Vec3,
        wl: &SampledWavelengths<K>,
    ) -> SampledSpectrum<K> {
        self.albedo.eval(p, wl).map(|a| a.clamp(0.0, 1.0))
    }

    /// The medium's view of `ray` up to `t_max`: the ray in the unit
    /// cube's space (same parameter t), the part [t0, t1] inside the cube,
    /// and a function of local points giving σ_t per wavelength with the
    /// factor turning super-voxel bounds into majorants; `None` when the
    /// ray misses the box.
    fn setup<const K: usize>(
        &self,
        ray: &Ray,
        t_max: f32,
        wl: &SampledWavelengths<K>,
    ) -> Option<Walk<'_, K>> {
        let to_local = self.to_local();
        let (o, d) = (to_local.point(ray.o), to_local.vector(ray.d));
        let (mut t0, mut t1) = (0.0f32, t_max);
        for (oa, da) in [(o.x, d.x), (o.y, d.y), (o.z, d.z)] {
            if da == 0.0 {
                if !(0.0..=1.0).contains(&oa) {
                    return None;
                }
                continue;
            }
            let (a, b) = ((0.0 - oa) / da, (1.0 - oa) / da);
            t0 = t0.max(a.min(b));
            t1 = t1.min(a.max(b));
        }
        if t0.is_nan() || t1.is_nan() || t0 >= t1 {
            return None;
        }
        let (constant, bound) = match &self.sigma_t {
            Field::Constant { value, .. } => {
                let s = value.sample(wl).map(|s| (s * self.scale).max(0.0));
                (Some(s), s.max_value())
            }
            Field::Grid(_) => (None, self.scale),
        };
        Some(Walk {
            medium: self,
            o,
            d,
            t0,
            t1,
            constant,
            bound,
            lambdas: wl.lambdas().map(normalised_lambda),
        })
    }

    /// Delta tracking (Woodcock et al. 1965): tentative collisions at the
    /// majorant's rate, each real with probability σ_t,0/σ̄ for the
    /// cluster's first wavelength. Every wavelength k's density of the
    /// walk, up to the factors common to all (the exponential flights at
    /// the grey σ̄), is Π_null (σ̄ − σ_t,k)/σ̄ times σ_t,k/σ̄ at a real
    /// collision; its own weight is the albedo there, 1 where it passed.
    pub fn sample_event<const K: usize>(
        &self,
        ray: &Ray,
        t_max: f32,
        wl: &SampledWavelengths<K>,
        u: f32,
        rng: &mut SplitMix,
    ) -> MediumEvent<K> {
        let passed = |logs: [f32; K]| MediumEvent {
            t: t_max,
            scattered: false,
            own: SampledSpectrum::splat(1.0),
            density: densities_from_logs(logs),
        };
        let Some(walk) = self.setup(ray, t_max, wl) else {
            return passed([0.0; K]);
        };
        let mut logs = [0.0f32; K];
        // Optical depth (at the majorant) left to the next tentative
        // collision.
        let mut depth = -(1.0 - u).ln();
        let mut hit = None;
        walk.medium
            .majorants
            .walk(walk.o, walk.d, walk.t0, walk.t1, |ta, tb, bound, _| {
                let sbar = bound * walk.bound;
                if sbar.is_nan() || sbar <= 0.0 {
                    return true;
                }
                walk.collisions((ta, tb, sbar), &mut depth, rng, |t, st, rng| {
                    if rng.next_f32() * sbar < st[0] {
                        for k in 0..K {
                            logs[k] += (st[k] / sbar).ln();
                        }
                        hit = Some(t);
                        return false;
                    }
                    for k in 0..K {
                        logs[k] += ((sbar - st[k]) / sbar).ln();
                    }
                    true
                })
            });
        match hit {
            Some(t) => MediumEvent {
                t,
                scattered: true,
                own: self.albedo(ray.at(t), wl),
                density: densities_from_logs(logs),
            },
            None => passed(logs),
        }
    }

    /// Ratio tracking (Novák et al. 2014, eq. 6): at tentative collisions
    /// drawn at the majorant's rate, every wavelength's estimate is
    /// multiplied by 1 − σ_t,k/σ̄; unbiased per wavelength.
    pub fn transmittance<const K: usize>(
        &self,
        ray: &Ray,
        t_max: f32,
        wl: &SampledWavelengths<K>,
        rng: &mut SplitMix,
    ) -> SampledSpectrum<K> {
        let Some(walk) = self.setup(ray, t_max, wl) else {
            return SampledSpectrum::splat(1.0);
        };
        if let Some(c) = walk.constant {
            // The same σ_t everywhere in the box: Beer–Lambert, exactly.
            let length = walk.t1 - walk.t0;
            return c.map(|s| if s > 0.0 { (-s * length).exp() } else { 1.0 });
        }
        let mut tr = [1.0f32; K];
        let mut depth = -(1.0 - rng.next_f32()).ln();
        walk.medium.majorants.walk(
            walk.o,
            walk.d,
            walk.t0,
            walk.t1,
            |ta, tb, bound, uniform| {
                let sbar = bound * walk.bound;
                if sbar.is_nan() || sbar <= 0.0 {
                    return true;
                }
                if uniform {
                    // σ_t = σ̄ throughout: Beer–Lambert, exactly.
                    let tr_seg = (-sbar * (tb - ta)).exp();
                    tr = tr.map(|v| v * tr_seg);
                    return tr_seg > 0.0;
                }
                walk.collisions((ta, tb, sbar), &mut depth, rng, |_, st, rng| {
                    for k in 0..K {
                        tr[k] *= 1.0 - st[k] / sbar;
                    }
                    let top = tr.iter().copied().fold(0.0, f32::max);
                    if top <= 0.0 {
                        return false;
                    }
                    if top < RR_BELOW {
                        if rng.next_f32() >= RR_SURVIVE {
                            tr = [0.0; K];
                            return false;
                        }
                        tr = tr.map(|v| v / RR_SURVIVE);
                    }
                    true
                })
            },
        );
        SampledSpectrum(tr)
    }
}

/// One ray's walk through the medium's unit cube.
struct Walk<'a, const K: usize> {
    medium: &'a Heterogeneous,
    o: Vec3,
    d: Vec3,
    t0: f32,
    t1: f32,
    /// σ_t per wavelength when it is constant.
    constant: Option<SampledSpectrum<K>>,
    /// Multiplies a super-voxel's bound into a majorant.
    bound: f32,
    lambdas: [f32; K],
}

impl<const K: usize> Walk<'_, K> {
    /// The tentative collisions in [ta, tb) at majorant `sbar`: `depth` is
    /// the optical depth (at the majorant) left to the next one, drawn
    /// anew from `rng` after each; `collide(t, σ_t, rng)` decides there
    /// and says whether the walk goes on. Whether it went on to `tb`.
    fn collisions(
        &self,
        (ta, tb, sbar): (f32, f32, f32),
        depth: &mut f32,
        rng: &mut SplitMix,
        mut collide: impl FnMut(f32, [f32; K], &mut SplitMix) -> bool,
    ) -> bool {
        let mut t = ta;
        loop {
            let step = *depth / sbar;
            if step >= tb - t {
                *depth -= (tb - t) * sbar;
                return true;
            }
            t += step;
            if !collide(t, self.sigma_t(t, sbar), rng) {
                return false;
            }
            *depth = -(1.0 - rng.next_f32()).ln();
        }
    }

    /// σ_t per wavelength at parameter `t`, at most `sbar` (the majorant
    /// bounds it but for rounding).
    #[inline]
    fn sigma_t(&self, t: f32, sbar: f32) -> [f32; K] {
        let s = match (&self.constant, &self.medium.sigma_t) {
            (Some(c), _) => c.0,
            (None, Field::Grid(g)) => g
                .eval_local(self.o + self.d * t, &self.lambdas)
                .map(|v| v * self.medium.scale),
            (None, Field::Constant { .. }) => [0.0; K],
        };
        s.map(|v| v.clamp(0.0, sbar))
    }
}

#[cfg(test)]
mod tests;
