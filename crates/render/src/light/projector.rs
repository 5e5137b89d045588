//! Mitsuba's `projector`: a perspective camera run backwards, projecting
//! an irradiance texture into the scene from a point.
//!
//! In direction d, θ from the optical axis, landing on texture coordinate
//! uv, the intensity is I(d) = π s E(uv) / cos³θ (Mitsuba 3's
//! `projector.cpp`, `sample_direction`): so the plane one unit in front,
//! facing the projector, receives irradiance π s E(uv) at uv.
//! Light paths start uniformly over the image: direction density
//! 1/(A cos³θ) with A the image's area on that plane (as the camera's rays,
//! `camera::importance`).

use scotopia_color::{SampledSpectrum, SampledWavelengths, Spectrum};

use super::simple::point_sample;
use super::{spectral_power, LightSample, Power};
use crate::camera::Camera;
use crate::math::Vec3;
use crate::texture::Texture;

#[derive(Debug, Clone, PartialEq)]
pub struct ProjectorLight {
    /// The projection: a camera at the projector over the texture's pixels.
    pub camera: Camera,
    pub position: Vec3,
    /// Spectral irradiance E(uv), W·m⁻²·nm⁻¹ (Mitsuba's `irradiance`).
    pub irradiance: Texture,
    /// Mitsuba's `scale`.
    pub scale: f32,
    /// E averaged over the texture: what wavelengths are drawn from.
    mean: Spectrum,
}

impl ProjectorLight {
    pub fn new(camera: Camera, irradiance: Texture, scale: f32) -> Self {
        let position = camera.world_from_camera.point(Vec3::ZERO);
        // E averaged over a 32 × 32 grid of the image.
        let n = 32;
        let grid: Vec<[f32; 2]> = (0..n * n)
            .map(|k| [(k % n) as f32 + 0.5, (k / n) as f32 + 0.5].map(|x| x / n as f32))
            .collect();
        let mean = irradiance.mean_spectrum(&grid);
        Self {
            camera,
            position,
            irradiance,
            scale,
            mean,
        }
    }

    /// Spectral intensity in world direction `d` (unit).
    pub fn intensity_towards<const K: usize>(
        &self,
        wl: &SampledWavelengths<K>,
        d: Vec3,
    ) -> SampledSpectrum<K> {
        let Some((raster, cos)) = self.camera.raster_towards(d) else {
            return SampledSpectrum::splat(0.0);
        };
        let uv = [
            raster[0] / self.camera.width as f32,
            raster[1] / self.camera.height as f32,
        ];
        self.irradiance.eval(wl, uv) * (std::f32::consts::PI * self.scale / (cos * cos * cos))
    }

    pub fn sample_li<const K: usize>(
        &self,
        wl: &SampledWavelengths<K>,
        p: Vec3,
    ) -> Option<LightSample<K>> {
        point_sample(self.position, p, |d| self.intensity_towards(wl, d))
    }

    /// A direction uniform over the image (`u` ∈ [0, 1)²) and its density
    /// per solid angle, 1/(A cos³θ).
    pub fn sample_direction(&self, u: [f32; 2]) -> (Vec3, f32) {
        let film = [
            u[0] * self.camera.width as f32,
            u[1] * self.camera.height as f32,
        ];
        let d = self.camera.generate_ray(film, [0.5, 0.5]).d;
        (d, self.pdf_direction(d))
    }

    pub fn pdf_direction(&self, d: Vec3) -> f32 {
        self.camera.pdf_direction(self.position, d)
    }

    /// Φ = ∫ I dω = π s ∫ E dA over the image on the plane z = 1.
    pub fn power(&self) -> Power {
        let area = self.camera.film_plane_area() as f64;
        spectral_power(&self.mean).scaled(std::f64::consts::PI * self.scale as f64 * area)
    }

    pub fn spectrum(&self) -> &Spectrum {
        &self.mean
    }
}
