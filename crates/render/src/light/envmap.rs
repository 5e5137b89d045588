//! An environment map (Mitsuba's `envmap`): an equirectangular RGB image
//! at infinity, each texel upsampled to an illuminant spectrum (Jakob &
//! Hanika 2019 times the colour space's white), interpolated bilinearly
//! as Mitsuba 3 does (unit spectrum and scale blended apart, see
//! `Bitmap::bilinear_scale_split`) and importance-sampled by power.
//!
//! Mapping, as Mitsuba 3 (checked against 3.9.1): in the light's frame a
//! direction d = (sin θ sin φ, cos θ, −sin θ cos φ) has u = φ / 2π and
//! v = θ / π, +y up. Texel columns are centred at u = (x + ½)/W and wrap;
//! rows at v = y/(H − 1), so the first and last rows are the poles.

use std::f32::consts::PI;
use std::sync::Arc;

use rayon::prelude::*;
use scotopia_color::{
    ColorError, RgbSpace, SampledSpectrum, SampledWavelengths, Spectrum, SpectrumKind, Tabulated,
    LAMBDA_MAX, LAMBDA_MIN,
};

use super::{spectral_power, LightSample, Power};
use crate::math::{Transform, Vec3};
use crate::sampling::distribution::Distribution2D;
use crate::texture::Bitmap;

/// Wavelength step of the tabulated total spectrum, nm.
const POWER_STEP: f32 = 5.0;

#[derive(Debug, Clone, PartialEq)]
pub struct EnvMapLight {
    texels: Arc<Bitmap>,
    pub scale: f32,
    world_from_light: Transform,
    light_from_world: Transform,
    /// Over the W × (H − 1) cells between texel centres, offset by half a
    /// texel in u: each cell's mean corner value times sin θ.
    distribution: Distribution2D,
    /// ∫ L(ω, λ) dω over the sphere, W·m⁻²·nm⁻¹ (scale included).
    total: Spectrum,
}

/// Direction in the light's frame for (u, v), and sin θ.
#[inline]
fn direction(u: f32, v: f32) -> (Vec3, f32) {
    let (theta, phi) = (v * PI, u * 2.0 * PI);
    let (st, ct) = theta.sin_cos();
    let (sp, cp) = phi.sin_cos();
    (Vec3::new(st * sp, ct, -st * cp), st)
}

/// (u, v) of a unit direction in the light's frame.
#[inline]
fn coordinates(d: Vec3) -> [f32; 2] {
    let u = d.x.atan2(-d.z) / (2.0 * PI);
    [u - u.floor(), d.y.clamp(-1.0, 1.0).acos() / PI]
}

impl EnvMapLight {
    /// `rgb`: linear RGB radiance in `space`, row-major, top row (+y) first.
    pub fn new(
        width: usize,
        height: usize,
        rgb: &[[f32; 3]],
        space: RgbSpace,
        scale: f32,
        world_from_light: Transform,
    ) -> Result<Self, ColorError> {
        if width == 0 || height == 0 || rgb.len() != width * height {
            return Err(ColorError::OutOfRange(format!(
                "a {width}×{height} environment map needs {} texels, got {}",
                width * height,
                rgb.len()
            )));
        }
        if !(scale.is_finite() && scale >= 0.0) {
            return Err(ColorError::OutOfRange(format!(
                "environment map scale must be non-negative, got {scale}"
            )));
        }
        // One row cannot be interpolated between poles: repeat it.
        let (height, rgb) = if height == 1 {
            (2, [rgb, rgb].concat())
        } else {
            (height, rgb.to_vec())
        };
        let texels = Bitmap::from_rgb(width, height, &rgb, space, SpectrumKind::Illuminant)?;
        let value = |x: usize, y: usize| {
            let c = rgb[y * width + x].map(|v| if v.is_finite() { v.max(0.0) } else { 0.0 });
            (c[0] + c[1] + c[2]) / 3.0
        };
        let cells: Vec<f32> = (0..height - 1)
            .flat_map(|y| {
                let sin = ((y as f32 + 0.5) / (height - 1) as f32 * PI).sin();
                (0..width).map(move |x| (x, y, sin))
            })
            .map(|(x, y, sin)| {
                let x1 = (x + 1) % width;
                0.25 * (value(x, y) + value(x1, y) + value(x, y + 1) + value(x1, y + 1)) * sin
            })
            .collect();
        let total = total_spectrum(&texels, scale);
        Ok(Self {
            texels: Arc::new(texels),
            scale,
            light_from_world: world_from_light.inverse(),
            world_from_light,
            distribution: Distribution2D::new(&cells, width),
            total,
        })
    }

    /// Radiance arriving from world direction `d` (towards the light).
    pub fn radiance<const K: usize>(
        &self,
        wl: &SampledWavelengths<K>,
        d: Vec3,
    ) -> SampledSpectrum<K> {
        let local = self.light_from_world.vector(d).normalize();
        let [u, v] = coordinates(local);
        let (w, h) = (self.texels.width(), self.texels.height());
        let px = u * w as f32 - 0.5;
        let fx = px.floor();
        let x0 = (fx as i64).rem_euclid(w as i64) as usize;
        let py = v * (h - 1) as f32;
        let y0 = (py.floor() as usize).min(h - 2);
        let a = [px - fx, (py - y0 as f32).clamp(0.0, 1.0)];
        self.texels
            .bilinear_scale_split(wl, [x0, (x0 + 1) % w], [y0, y0 + 1], a)
            * self.scale
    }

    /// Density per solid angle of `sample_li` choosing world direction `d`.
    pub fn pdf_li(&self, d: Vec3) -> f32 {
        let local = self.light_from_world.vector(d).normalize();
        let [u, v] = coordinates(local);
        let sin = (v * PI).sin();
        if sin <= 0.0 {
            return 0.0;
        }
        let w = self.texels.width() as f32;
        let s = u - 0.5 / w;
        self.distribution.pdf([s - s.floor(), v]) / (2.0 * PI * PI * sin)
    }

    pub fn sample_li<const K: usize>(
        &self,
        wl: &SampledWavelengths<K>,
        u: [f32; 2],
    ) -> Option<LightSample<K>> {
        let ([s, v], pdf_uv) = self.distribution.sample(u)?;
        let w = self.texels.width() as f32;
        let uu = s + 0.5 / w;
        let (local, sin) = direction(uu - uu.floor(), v);
        if sin <= 0.0 || pdf_uv <= 0.0 {
            return None;
        }
        let wi = self.world_from_light.vector(local).normalize();
        Some(LightSample {
            n: Vec3::ZERO,
            wi,
            distance: f32::INFINITY,
            radiance: self.radiance(wl, wi),
            // (u, v) ↦ ω has Jacobian 2π² sin θ.
            pdf: pdf_uv / (2.0 * PI * PI * sin),
            delta: false,
        })
    }

    /// ∫ L dω per wavelength.
    pub fn total_spectrum(&self) -> &Spectrum {
        &self.total
    }

    /// Φ = π R² ∫∫ L dω dλ through the scene's bounding sphere.
    pub fn power(&self, scene_radius: f32) -> Power {
        let r = scene_radius as f64;
        spectral_power(&self.total).scaled(std::f64::consts::PI * r * r)
    }
}

/// Σ over texels of S(λ) times the texel's solid angle: a band of rows
/// (v within half a row of its centre, clipped at the poles) by 2π/W.
fn total_spectrum(texels: &Bitmap, scale: f32) -> Spectrum {
    let (w, h) = (texels.width(), texels.height());
    let n = ((LAMBDA_MAX - LAMBDA_MIN) / POWER_STEP) as usize + 1;
    let lambdas: Vec<f32> = (0..n).map(|i| LAMBDA_MIN + POWER_STEP * i as f32).collect();
    let solid = |y: usize| {
        let edge = |v: f32| (v.clamp(0.0, 1.0) * PI).cos();
        let (a, b) = (y as f32 - 0.5, y as f32 + 0.5);
        let band = edge(a / (h - 1) as f32) - edge(b / (h - 1) as f32);
        2.0 * PI / w as f32 * band
    };
    let sums: Vec<f64> = (0..h)
        .into_par_iter()
        .map(|y| {
            let mut row = vec![0.0f64; n];
            for (c, ls) in lambdas.chunks(4).enumerate() {
                let mut l4 = [ls[0]; 4];
                l4[..ls.len()].copy_from_slice(ls);
                let wl = SampledWavelengths::new(l4, [1.0; 4]);
                let (t, white) = texels.prepare(&wl);
                for x in 0..w {
                    let v = texels.texel(x, y, &t, &white);
                    for (r, v) in row[c * 4..c * 4 + ls.len()].iter_mut().zip(v.0) {
                        *r += v as f64;
                    }
                }
            }
            let s = solid(y) as f64;
            row.iter_mut().for_each(|r| *r *= s);
            row
        })
        .reduce(
            || vec![0.0; n],
            |mut a, b| {
                a.iter_mut().zip(b).for_each(|(x, y)| *x += y);
                a
            },
        );
    let values = sums.iter().map(|v| (*v * scale as f64) as f32).collect();
    Tabulated::new(lambdas, values)
        .map(Spectrum::from)
        .unwrap_or(Spectrum::Constant(0.0))
}
