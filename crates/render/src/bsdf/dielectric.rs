//! Smooth dielectric interfaces: a single interface (Mitsuba's
//! `dielectric`) and a thin slab (`thindielectric`). The index may depend
//! on wavelength; then a refracted direction belongs to one wavelength and
//! the cluster collapses to it.

use scotopia_color::{SampledSpectrum, SampledWavelengths, Spectrum};

use super::{fresnel_dielectric, reflect, BsdfSample, Transport};
use crate::math::Vec3;
use crate::texture::{TexPoint, Texture};

/// η(λ) = interior / exterior index per wavelength, and whether it varies.
#[derive(Debug, Clone, PartialEq)]
pub struct Ior {
    pub interior: Spectrum,
    pub exterior: Spectrum,
}

impl Ior {
    /// Whether the relative index changes with wavelength.
    pub fn dispersive(&self) -> bool {
        !matches!(
            (&self.interior, &self.exterior),
            (Spectrum::Constant(_), Spectrum::Constant(_))
        )
    }

    #[inline]
    pub(crate) fn eta<const K: usize>(&self, wl: &SampledWavelengths<K>) -> SampledSpectrum<K> {
        self.interior.sample(wl) / self.exterior.sample(wl)
    }
}

#[derive(Debug, Clone, PartialEq)]
pub struct Dielectric {
    pub ior: Ior,
    pub specular_reflectance: Texture,
    pub specular_transmittance: Texture,
}

/// Chooses reflection with probability F of the first wavelength; each
/// wavelength's weight is its own F (or 1 − F) over that probability.
fn choose<const K: usize>(f: &SampledSpectrum<K>, u: f32) -> (bool, SampledSpectrum<K>) {
    let p = f[0];
    if u < p {
        (true, *f / p)
    } else {
        (false, (SampledSpectrum::splat(1.0) - *f) / (1.0 - p))
    }
}

impl Dielectric {
    pub fn sample<const K: usize>(
        &self,
        wl: &SampledWavelengths<K>,
        uv: TexPoint,
        wi: Vec3,
        u: f32,
        mode: Transport,
    ) -> Option<BsdfSample<K>> {
        if wi.z == 0.0 {
            return None;
        }
        let eta = self.ior.eta(wl);
        let mut cos_t = 0.0;
        let mut eta_it = 1.0;
        let f = SampledSpectrum::from_fn(|i| {
            let (f, ct, e) = fresnel_dielectric(wi.z, eta[i]);
            if i == 0 {
                (cos_t, eta_it) = (ct, e);
            }
            f
        });
        let (reflected, weight) = choose(&f, u);
        if reflected {
            return Some(BsdfSample {
                wo: reflect(wi),
                weight: weight * self.specular_reflectance.eval(wl, uv),
                pdf: 1.0,
                delta: true,
                collapse: false,
            });
        }
        // Snell's law for the first wavelength.
        let eta_ti = 1.0 / eta_it;
        let wo = Vec3::new(-eta_ti * wi.x, -eta_ti * wi.y, cos_t);
        // Radiance changes by (η_t/η_i)² across the interface (Veach 1997,
        // §5.2); the camera path carries its inverse. Importance does not.
        let scale = match mode {
            Transport::Radiance => eta_ti * eta_ti,
            Transport::Importance => 1.0,
        };
        Some(BsdfSample {
            wo,
            weight: weight * self.specular_transmittance.eval(wl, uv) * scale,
            pdf: 1.0,
            delta: true,
            collapse: self.ior.dispersive(),
        })
    }
}

/// A thin slab: reflection with the sum of all internal bounces, and
/// straight-through transmission (no refraction: the slab's two faces undo
/// each other), so even a dispersive index does not split directions.
#[derive(Debug, Clone, PartialEq)]
pub struct ThinDielectric {
    pub ior: Ior,
    pub specular_reflectance: Texture,
    pub specular_transmittance: Texture,
}

impl ThinDielectric {
    /// The slab's reflectance at incidence cosine `cos`: R' = R + T²R /
    /// (1 − R²) for T = 1 − R, the geometric series of inter-reflections
    /// (Mitsuba's thindielectric).
    pub(super) fn reflectance<const K: usize>(
        &self,
        wl: &SampledWavelengths<K>,
        cos: f32,
    ) -> SampledSpectrum<K> {
        let eta = self.ior.eta(wl);
        SampledSpectrum::from_fn(|i| {
            let r = fresnel_dielectric(cos, eta[i]).0;
            if r < 1.0 {
                r + (1.0 - r) * (1.0 - r) * r / (1.0 - r * r)
            } else {
                r
            }
        })
    }

    /// What passes straight through (the slab's null lobe: Mitsuba's
    /// volume path tracers let shadow rays through it).
    pub(super) fn transmission<const K: usize>(
        &self,
        wl: &SampledWavelengths<K>,
        uv: TexPoint,
        cos: f32,
    ) -> SampledSpectrum<K> {
        self.reflectance(wl, cos).map(|r| 1.0 - r) * self.specular_transmittance.eval(wl, uv)
    }

    pub fn sample<const K: usize>(
        &self,
        wl: &SampledWavelengths<K>,
        uv: TexPoint,
        wi: Vec3,
        u: f32,
    ) -> Option<BsdfSample<K>> {
        if wi.z == 0.0 {
            return None;
        }
        let r = self.reflectance(wl, wi.z.abs());
        let (reflected, weight) = choose(&r, u);
        Some(if reflected {
            BsdfSample {
                wo: reflect(wi),
                weight: weight * self.specular_reflectance.eval(wl, uv),
                pdf: 1.0,
                delta: true,
                collapse: false,
            }
        } else {
            BsdfSample {
                wo: -wi,
                weight: weight * self.specular_transmittance.eval(wl, uv),
                pdf: 1.0,
                delta: true,
                collapse: false,
            }
        })
    }
}
