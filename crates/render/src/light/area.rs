//! Area lights: a shape emitting radiance L(uv) from the side its normal
//! points to (Mitsuba's `area`); L is a texture, looked up at the texture
//! coordinates of the emitting point, whether a ray hit it or a sample
//! chose it. Next-event estimation samples a sphere by the cone of
//! directions it fills (from outside it) and every other shape uniformly
//! by area. (Mitsuba 3 importance-samples a spatially varying radiance in
//! uv instead; both are unbiased, they differ in variance only.)
//!
//! Wavelengths are drawn from, and the power is reported by, L averaged
//! over the surface by area: over 4096 points spread uniformly over it by
//! the same area sampling (a constant L is its own mean).

use scotopia_color::{SampledSpectrum, SampledWavelengths, Spectrum};

use super::{spectral_power, LightSample, Power};
use crate::geometry::{Shape, Sphere, SurfacePoint};
use crate::math::Vec3;
use crate::sampling::distribution::Distribution1D;
use crate::texture::Texture;

/// Points over the surface the mean radiance is taken at.
const MEAN_POINTS: usize = 4096;

#[derive(Debug, Clone, PartialEq)]
pub struct AreaLight {
    /// Index of the emitting shape in the scene's shape list.
    pub shape: u32,
    /// Spectral radiance over the surface, W·sr⁻¹·m⁻²·nm⁻¹ (set by `new`,
    /// which takes its mean).
    pub radiance: Texture,
    /// The radiance averaged over the surface by area.
    mean: Spectrum,
    /// Triangle areas of a mesh emitter.
    cdf: Option<Distribution1D>,
    area: f32,
    /// A sphere emitter, sampled by the cone it fills.
    sphere: Option<Sphere>,
}

impl AreaLight {
    /// `radiance`: a spectrum or a texture.
    pub fn new(shape_index: u32, shape: &Shape, radiance: impl Into<Texture>) -> Self {
        let radiance = radiance.into();
        let cdf = shape.area_table();
        let mean = radiance.mean_spectrum(&surface_uvs(shape, cdf.as_ref(), &radiance));
        Self {
            shape: shape_index,
            radiance,
            mean,
            area: shape.area(),
            cdf,
            sphere: match shape {
                Shape::Sphere(s) => Some(*s),
                _ => None,
            },
        }
    }

    /// The mesh's triangle-area table (for `Shape::sample_area`).
    pub fn triangles(&self) -> Option<&Distribution1D> {
        self.cdf.as_ref()
    }

    pub fn area(&self) -> f32 {
        self.area
    }

    /// The radiance averaged over the surface: what wavelengths are drawn
    /// from for this light.
    pub fn mean_radiance(&self) -> &Spectrum {
        &self.mean
    }

    /// Emitted radiance leaving the point at texture coordinates `uv`, with
    /// normal `n`, in direction `w`.
    #[inline]
    pub fn radiance<const K: usize>(
        &self,
        wl: &SampledWavelengths<K>,
        uv: [f32; 2],
        n: Vec3,
        w: Vec3,
    ) -> SampledSpectrum<K> {
        if n.dot(w) > 0.0 {
            self.radiance.eval(wl, uv)
        } else {
            SampledSpectrum::splat(0.0)
        }
    }

    pub fn sample_li<const K: usize>(
        &self,
        shapes: &[Shape],
        wl: &SampledWavelengths<K>,
        p: Vec3,
        u_select: f32,
        u: [f32; 2],
    ) -> Option<LightSample<K>> {
        let shape = shapes.get(self.shape as usize)?;
        // The point and its density per unit area, or per steradian.
        let (s, cone_pdf): (SurfacePoint, Option<f32>) =
            match self.sphere.and_then(|sp| sp.sample_seen(p, u)) {
                Some((s, pdf)) => (s, Some(pdf)),
                None => (shape.sample_area(self.cdf.as_ref(), u_select, u)?, None),
            };
        let d = s.p - p;
        let dist2 = d.length_squared();
        let dist = dist2.sqrt();
        let wi = d / dist;
        let cos_l = -wi.dot(s.n);
        if cos_l <= 0.0 || dist2 == 0.0 || self.area <= 0.0 {
            return None;
        }
        // Area density 1/A converted to solid angle: d² / (A cos θ_l).
        Some(LightSample {
            n: s.n,
            wi,
            distance: dist,
            radiance: self.radiance.eval(wl, s.uv),
            pdf: cone_pdf.unwrap_or(dist2 / (self.area * cos_l)),
            delta: false,
        })
    }

    /// Density per solid angle of reaching `p_light` (normal `n_light`) from
    /// `p` by `sample_li`.
    pub fn pdf_li(&self, p: Vec3, p_light: Vec3, n_light: Vec3) -> f32 {
        if let Some(pdf) = self.sphere.and_then(|s| s.seen_pdf(p)) {
            // Only the near side is reached from outside; its emission
            // faces p.
            return if (p - p_light).dot(n_light) > 0.0 {
                pdf
            } else {
                0.0
            };
        }
        let d = p_light - p;
        let dist2 = d.length_squared();
        let cos_l = -(d / dist2.sqrt()).dot(n_light);
        if cos_l <= 0.0 || self.area <= 0.0 {
            return 0.0;
        }
        dist2 / (self.area * cos_l)
    }

    /// Φ = π A ∫ L̄ dλ for a one-sided Lambertian emitter, L̄ the mean
    /// radiance over its area.
    pub fn power(&self) -> Power {
        spectral_power(&self.mean).scaled(std::f64::consts::PI * self.area as f64)
    }
}

/// Texture coordinates of `MEAN_POINTS` points spread uniformly over the
/// shape's area (a rank-1 lattice in the sampling square, stratified
/// triangle choice); none when the radiance is constant.
fn surface_uvs(shape: &Shape, cdf: Option<&Distribution1D>, radiance: &Texture) -> Vec<[f32; 2]> {
    if !radiance.is_varying() {
        return Vec::new();
    }
    // The R2 sequence's generator (Roberts 2018, "The unreasonable
    // effectiveness of quasirandom sequences"): 1/φ₂ and 1/φ₂², φ₂ the
    // plastic number.
    const G: [f64; 2] = [0.754_877_666_246_692_7, 0.569_840_290_998_053_2];
    (0..MEAN_POINTS)
        .filter_map(|k| {
            let u = G.map(|g| ((0.5 + g * k as f64).fract()) as f32);
            let u_select = (k as f32 + 0.5) / MEAN_POINTS as f32;
            shape.sample_area(cdf, u_select, u).map(|s| s.uv)
        })
        .collect()
}
