//! Area lights: a shape emitting radiance L from the side its normal
//! points to (Mitsuba's `area`). Next-event estimation samples a sphere
//! by the cone of directions it fills (from outside it) and every other
//! shape uniformly by area.

use scotopia_color::{SampledSpectrum, SampledWavelengths, Spectrum};

use super::{spectral_power, LightSample, Power};
use crate::geometry::{Shape, Sphere, SurfacePoint};
use crate::math::Vec3;
use crate::sampling::distribution::Distribution1D;

#[derive(Debug, Clone, PartialEq)]
pub struct AreaLight {
    /// Index of the emitting shape in the scene's shape list.
    pub shape: u32,
    pub radiance: Spectrum,
    /// Triangle areas of a mesh emitter.
    cdf: Option<Distribution1D>,
    area: f32,
    /// A sphere emitter, sampled by the cone it fills.
    sphere: Option<Sphere>,
}

impl AreaLight {
    pub fn new(shape_index: u32, shape: &Shape, radiance: Spectrum) -> Self {
        let cdf = match shape {
            Shape::Mesh(m) => Some(Distribution1D::new(
                (0..m.triangle_count()).map(|f| m.face_area(f)).collect(),
            )),
            _ => None,
        };
        Self {
            shape: shape_index,
            radiance,
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

    /// Emitted radiance leaving a point with normal `n` in direction `w`.
    pub fn radiance<const K: usize>(
        &self,
        wl: &SampledWavelengths<K>,
        n: Vec3,
        w: Vec3,
    ) -> SampledSpectrum<K> {
        if n.dot(w) > 0.0 {
            self.radiance.sample(wl)
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
            radiance: self.radiance.sample(wl),
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

    /// Φ = π A ∫ L dλ for a one-sided Lambertian emitter.
    pub fn power(&self) -> Power {
        spectral_power(&self.radiance).scaled(std::f64::consts::PI * self.area as f64)
    }
}
