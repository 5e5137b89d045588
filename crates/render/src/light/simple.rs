//! Point, spot and directional lights, and the constant environment.

use scotopia_color::{SampledSpectrum, SampledWavelengths, Spectrum};

use super::{spectral_power, LightSample, Power};
use crate::math::{Frame, Vec3};
use crate::sampling::warp::{square_to_uniform_sphere, UNIFORM_SPHERE_PDF};
use crate::texture::Texture;

/// Unit direction, distance and squared distance from `p` to `position`;
/// `None` when they coincide.
#[inline]
fn towards(position: Vec3, p: Vec3) -> Option<(Vec3, f32, f32)> {
    let d = position - p;
    let dist2 = d.length_squared();
    if dist2 == 0.0 {
        return None;
    }
    let dist = dist2.sqrt();
    Some((d / dist, dist, dist2))
}

/// Incident light at `p` from a point-like light at `position` (a delta
/// distribution): the direction towards it and I(d)/distance², with
/// `intensity` given the direction d light leaves the light in. `None`
/// when the points coincide or nothing is emitted towards `p`.
#[inline]
pub(super) fn point_sample<const K: usize>(
    position: Vec3,
    p: Vec3,
    intensity: impl FnOnce(Vec3) -> SampledSpectrum<K>,
) -> Option<LightSample<K>> {
    let (wi, dist, dist2) = towards(position, p)?;
    let i = intensity(-wi);
    if i.is_zero() {
        return None;
    }
    Some(LightSample {
        n: Vec3::ZERO,
        wi,
        distance: dist,
        radiance: i / dist2,
        pdf: 1.0,
        delta: true,
    })
}

/// Isotropic point light of spectral intensity I.
#[derive(Debug, Clone, PartialEq)]
pub struct PointLight {
    pub position: Vec3,
    pub intensity: Spectrum,
}

impl PointLight {
    pub fn sample_li<const K: usize>(
        &self,
        wl: &SampledWavelengths<K>,
        p: Vec3,
    ) -> Option<LightSample<K>> {
        point_sample(self.position, p, |_| self.intensity.sample(wl))
    }

    /// Φ = 4π ∫ I dλ.
    pub fn power(&self) -> Power {
        spectral_power(&self.intensity).scaled(4.0 * std::f64::consts::PI)
    }
}

/// A spot light (Mitsuba's `spot`): intensity I along its axis, full out to
/// `beam_width`, falling linearly in angle to zero at `cutoff_angle`,
/// optionally times a texture projected over the cone.
#[derive(Debug, Clone, PartialEq)]
pub struct SpotLight {
    pub position: Vec3,
    /// The axis; the light shines along `frame.n`. With a texture, `s` and
    /// `t` are the emitter's own x and y axes (its `to_world`).
    pub frame: Frame,
    pub intensity: Spectrum,
    pub cutoff: f32,
    pub beam_width: f32,
    /// Mitsuba's `texture`: a factor over the cone, read at
    /// uv = ½ + ½ (x, y) / (z tan cutoff) of the local direction.
    pub texture: Option<Texture>,
}

impl SpotLight {
    /// `cutoff_deg` and `beam_width_deg` as in Mitsuba (defaults 20° and ¾ of it).
    pub fn new(
        position: Vec3,
        axis: Vec3,
        intensity: Spectrum,
        cutoff_deg: f32,
        beam_width_deg: f32,
    ) -> Self {
        Self {
            position,
            frame: Frame::from_normal(axis.normalize()),
            intensity,
            cutoff: cutoff_deg.to_radians(),
            beam_width: beam_width_deg.min(cutoff_deg).to_radians(),
            texture: None,
        }
    }

    /// The same light projecting `texture`, oriented by `frame` (whose
    /// `n` must be the axis).
    pub fn with_texture(self, frame: Frame, texture: Texture) -> Self {
        Self {
            frame,
            texture: Some(texture),
            ..self
        }
    }

    /// The texture's factor in local direction `local` (1 without one),
    /// mapped as Mitsuba's `direction_to_uv`.
    pub fn texture_factor<const K: usize>(
        &self,
        wl: &SampledWavelengths<K>,
        local: Vec3,
    ) -> SampledSpectrum<K> {
        match &self.texture {
            None => SampledSpectrum::splat(1.0),
            Some(t) => {
                let k = 0.5 / (local.z * self.cutoff.tan());
                t.eval(wl, [0.5 + local.x * k, 0.5 + local.y * k])
            }
        }
    }

    /// Spectral intensity in world direction `d` (unit): I × texture ×
    /// falloff.
    pub fn intensity_towards<const K: usize>(
        &self,
        wl: &SampledWavelengths<K>,
        d: Vec3,
    ) -> SampledSpectrum<K> {
        let local = self.frame.to_local(d);
        let f = self.falloff(local.z);
        if f == 0.0 {
            return SampledSpectrum::splat(0.0);
        }
        self.intensity.sample(wl) * self.texture_factor(wl, local) * f
    }

    /// The angular falloff in [0, 1] at angle θ from the axis.
    pub fn falloff(&self, cos_theta: f32) -> f32 {
        let theta = cos_theta.clamp(-1.0, 1.0).acos();
        if theta >= self.cutoff {
            0.0
        } else if theta <= self.beam_width {
            1.0
        } else {
            (self.cutoff - theta) / (self.cutoff - self.beam_width)
        }
    }

    pub fn sample_li<const K: usize>(
        &self,
        wl: &SampledWavelengths<K>,
        p: Vec3,
    ) -> Option<LightSample<K>> {
        point_sample(self.position, p, |d| self.intensity_towards(wl, d))
    }

    /// Φ = 2π ∫ falloff(θ) sin θ dθ · ∫ I dλ: the full cone 2π(1 − cos θ_b)
    /// plus the linear ramp, integrated exactly by parts.
    pub fn power(&self) -> Power {
        let (b, c) = (self.beam_width as f64, self.cutoff as f64);
        let ramp = if c > b {
            // ∫_b^c (c − θ)/(c − b) sin θ dθ = cos b − (sin c − sin b)/(c − b)
            b.cos() - (c.sin() - b.sin()) / (c - b)
        } else {
            0.0
        };
        let solid = 2.0 * std::f64::consts::PI * (1.0 - b.cos() + ramp);
        // With a texture, its mean scales the power (light choice only).
        let mean = self.texture.as_ref().map_or(1.0, |t| t.mean() as f64);
        spectral_power(&self.intensity).scaled(solid * mean)
    }
}

/// Parallel light arriving along `direction` with spectral irradiance E.
#[derive(Debug, Clone, PartialEq)]
pub struct DirectionalLight {
    /// The direction light travels (unit).
    pub direction: Vec3,
    pub irradiance: Spectrum,
}

impl DirectionalLight {
    pub fn sample_li<const K: usize>(&self, wl: &SampledWavelengths<K>) -> Option<LightSample<K>> {
        Some(LightSample {
            n: Vec3::ZERO,
            wi: -self.direction,
            distance: f32::INFINITY,
            radiance: self.irradiance.sample(wl),
            pdf: 1.0,
            delta: true,
        })
    }

    /// Φ = E π R² over the scene's bounding disk.
    pub fn power(&self, scene_radius: f32) -> Power {
        let r = scene_radius as f64;
        spectral_power(&self.irradiance).scaled(std::f64::consts::PI * r * r)
    }
}

/// The same radiance from every direction at infinity.
#[derive(Debug, Clone, PartialEq)]
pub struct ConstantLight {
    pub radiance: Spectrum,
}

impl ConstantLight {
    pub fn sample_li<const K: usize>(
        &self,
        wl: &SampledWavelengths<K>,
        u: [f32; 2],
    ) -> Option<LightSample<K>> {
        Some(LightSample {
            n: Vec3::ZERO,
            wi: square_to_uniform_sphere(u),
            distance: f32::INFINITY,
            radiance: self.radiance.sample(wl),
            pdf: UNIFORM_SPHERE_PDF,
            delta: false,
        })
    }

    /// Density of a direction (uniform).
    pub fn pdf_li(&self) -> f32 {
        UNIFORM_SPHERE_PDF
    }

    /// Φ = π · 4πR² · ∫ L dλ: the radiance through the scene's bounding sphere.
    pub fn power(&self, scene_radius: f32) -> Power {
        let r = scene_radius as f64;
        spectral_power(&self.radiance)
            .scaled(4.0 * std::f64::consts::PI * std::f64::consts::PI * r * r)
    }
}
