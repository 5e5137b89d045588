//! BSDFs, spectral throughout: every value is evaluated on the path's
//! wavelength cluster.
//!
//! Conventions (Mitsuba's): directions are in the local shading frame
//! (z = normal) and both point away from the surface — `wi` towards where
//! the path came from, `wo` the sampled continuation. `eval` returns
//! f(wi, wo)·|cos θ_o| (the cosine included), `sample` returns the weight
//! eval/pdf, so delta lobes need no infinite values. `uv` are the hit's
//! texture coordinates, where textured parameters are looked up.

mod conductor;
mod dielectric;
mod diffuse;
mod fluorescent;
mod fresnel;
mod microfacet;
mod plastic;
mod rough_dielectric;
mod rough_plastic;

pub use conductor::Conductor;
pub use dielectric::{Dielectric, Ior, ThinDielectric};
pub use diffuse::Diffuse;
pub use fluorescent::{Donaldson, Fluorescent, Reradiation, Separable};
pub use fresnel::{fresnel_conductor, fresnel_dielectric};
pub use microfacet::{MicrofacetDistribution, MicrofacetKind, MIN_ALPHA};
pub use plastic::{diffuse_fresnel_reflectance, Plastic};
pub use rough_dielectric::RoughDielectric;
pub use rough_plastic::RoughPlastic;

use scotopia_color::{SampledSpectrum, SampledWavelengths};

use crate::math::Vec3;

/// What the path carries: radiance (from the camera) or importance (from a
/// light). Refraction scales radiance by 1/η² but not importance.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Transport {
    Radiance,
    Importance,
}

/// A sampled continuation of a path.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BsdfSample<const K: usize> {
    pub wo: Vec3,
    /// f·|cos θ_o| / pdf per wavelength.
    pub weight: SampledSpectrum<K>,
    /// Density per solid angle (1 for delta lobes, as a marker).
    pub pdf: f32,
    /// A delta lobe (mirror, smooth refraction): no MIS with lights.
    pub delta: bool,
    /// The direction depends on wavelength (dispersion): the cluster must
    /// collapse to its first wavelength, whose direction this is.
    pub collapse: bool,
}

/// The closed set of BSDFs.
#[derive(Debug, Clone, PartialEq)]
pub enum Bsdf {
    Diffuse(Diffuse),
    Conductor(Conductor),
    Dielectric(Dielectric),
    ThinDielectric(ThinDielectric),
    RoughDielectric(RoughDielectric),
    Plastic(Plastic),
    RoughPlastic(RoughPlastic),
    /// Lambertian with fluorescence: changes the path's wavelengths
    /// ([`Bsdf::reradiate`]) before scattering.
    Fluorescent(Fluorescent),
    /// The inner BSDF on both sides (Mitsuba's `twosided`).
    TwoSided(Box<Bsdf>),
}

/// Mirror `w` about the normal (0, 0, 1).
#[inline]
pub(crate) fn reflect(w: Vec3) -> Vec3 {
    Vec3::new(-w.x, -w.y, w.z)
}

/// Mirror `w` about the unit vector `m`.
#[inline]
pub(crate) fn reflect_about(w: Vec3, m: Vec3) -> Vec3 {
    m * (2.0 * w.dot(m)) - w
}

impl Bsdf {
    /// f(wi, wo)·|cos θ_o|; zero for delta lobes.
    pub fn eval<const K: usize>(
        &self,
        wl: &SampledWavelengths<K>,
        uv: [f32; 2],
        wi: Vec3,
        wo: Vec3,
        mode: Transport,
    ) -> SampledSpectrum<K> {
        match self {
            Bsdf::Diffuse(b) => b.eval(wl, uv, wi, wo),
            Bsdf::Conductor(b) => b.eval(wl, uv, wi, wo),
            Bsdf::Dielectric(_) | Bsdf::ThinDielectric(_) => SampledSpectrum::splat(0.0),
            Bsdf::RoughDielectric(b) => b.eval(wl, uv, wi, wo, mode),
            Bsdf::Plastic(b) => b.eval(wl, uv, wi, wo),
            Bsdf::RoughPlastic(b) => b.eval(wl, uv, wi, wo),
            Bsdf::Fluorescent(b) => b.eval(wi, wo),
            Bsdf::TwoSided(inner) => {
                let (wi, wo) = two_sided(wi, wo);
                inner.eval(wl, uv, wi, wo, mode)
            }
        }
    }

    /// Density of `sample` producing `wo` by its non-delta lobes (zero for
    /// pure delta BSDFs); for a dispersive lobe, the first wavelength's.
    pub fn pdf<const K: usize>(&self, wl: &SampledWavelengths<K>, wi: Vec3, wo: Vec3) -> f32 {
        match self {
            Bsdf::Diffuse(b) => b.pdf(wi, wo),
            Bsdf::Conductor(b) => b.pdf(wi, wo),
            Bsdf::Dielectric(_) | Bsdf::ThinDielectric(_) => 0.0,
            Bsdf::RoughDielectric(b) => b.pdf(wl, wi, wo),
            Bsdf::Plastic(b) => b.pdf(wi, wo),
            Bsdf::RoughPlastic(b) => b.pdf(wi, wo),
            Bsdf::Fluorescent(b) => b.pdf(wi, wo),
            Bsdf::TwoSided(inner) => {
                let (wi, wo) = two_sided(wi, wo);
                inner.pdf(wl, wi, wo)
            }
        }
    }

    /// Samples a continuation: `u_lobe` picks a lobe, `u` the direction.
    pub fn sample<const K: usize>(
        &self,
        wl: &SampledWavelengths<K>,
        uv: [f32; 2],
        wi: Vec3,
        u_lobe: f32,
        u: [f32; 2],
        mode: Transport,
    ) -> Option<BsdfSample<K>> {
        match self {
            Bsdf::Diffuse(b) => b.sample(wl, uv, wi, u),
            Bsdf::Conductor(b) => b.sample(wl, uv, wi, u),
            Bsdf::Dielectric(b) => b.sample(wl, uv, wi, u_lobe, mode),
            Bsdf::ThinDielectric(b) => b.sample(wl, uv, wi, u_lobe),
            Bsdf::RoughDielectric(b) => b.sample(wl, uv, wi, u_lobe, u, mode),
            Bsdf::Plastic(b) => b.sample(wl, uv, wi, u_lobe, u),
            Bsdf::RoughPlastic(b) => b.sample(wl, uv, wi, u_lobe, u),
            Bsdf::Fluorescent(b) => b.sample(wi, u),
            Bsdf::TwoSided(inner) => {
                let flip = wi.z < 0.0;
                let wi = if flip {
                    Vec3::new(wi.x, wi.y, -wi.z)
                } else {
                    wi
                };
                let mut s = inner.sample(wl, uv, wi, u_lobe, u, mode)?;
                if flip {
                    s.wo.z = -s.wo.z;
                }
                Some(s)
            }
        }
    }

    /// For a wavelength-changing (fluorescent) BSDF: moves the members of
    /// `wl` that are re-emitted light to the wavelengths they were
    /// absorbed at, and returns the factor the throughput takes (see
    /// [`Fluorescent::reradiate`]); `None` for every other BSDF. Called
    /// once per vertex, before light sampling and `sample`, whose values
    /// are then those of the surface's directional part alone.
    pub fn reradiate<const K: usize>(
        &self,
        wl: &mut SampledWavelengths<K>,
        uv: [f32; 2],
        u: f32,
    ) -> Option<SampledSpectrum<K>> {
        match self {
            Bsdf::Fluorescent(b) => Some(b.reradiate(wl, uv, u)),
            Bsdf::TwoSided(inner) => inner.reradiate(wl, uv, u),
            _ => None,
        }
    }

    /// The fluorescent BSDF inside, if any.
    pub fn fluorescent(&self) -> Option<&Fluorescent> {
        match self {
            Bsdf::Fluorescent(f) => Some(f),
            Bsdf::TwoSided(inner) => inner.fluorescent(),
            _ => None,
        }
    }

    /// Whether every lobe is a delta (no `eval`, no light sampling).
    pub fn is_delta(&self) -> bool {
        match self {
            Bsdf::Diffuse(_) | Bsdf::Fluorescent(_) => false,
            Bsdf::Conductor(c) => c.is_smooth(),
            Bsdf::Dielectric(_) | Bsdf::ThinDielectric(_) => true,
            Bsdf::RoughDielectric(_) | Bsdf::Plastic(_) | Bsdf::RoughPlastic(_) => false,
            Bsdf::TwoSided(inner) => inner.is_delta(),
        }
    }
}

/// Both directions moved to the upper side when `wi` is below.
#[inline]
fn two_sided(wi: Vec3, wo: Vec3) -> (Vec3, Vec3) {
    if wi.z < 0.0 {
        (Vec3::new(wi.x, wi.y, -wi.z), Vec3::new(wo.x, wo.y, -wo.z))
    } else {
        (wi, wo)
    }
}
