//! BSDFs, spectral throughout: every value is evaluated on the path's
//! wavelength cluster.
//!
//! Conventions (Mitsuba's): directions are in the local shading frame
//! (z = normal) and both point away from the surface — `wi` towards where
//! the path came from, `wo` the sampled continuation. `eval` returns
//! f(wi, wo)·|cos θ_o| (the cosine included), `sample` returns the weight
//! eval/pdf, so delta lobes need no infinite values. `at` is where the
//! BSDF is evaluated ([`ShadingPoint`]): the hit's texture coordinates,
//! where textured parameters are looked up, and the surface's local
//! geometry, which normal and bump maps perturb. A bare `[f32; 2]` of
//! texture coordinates converts to a flat point.

mod blend;
mod bump_map;
mod conductor;
mod dielectric;
mod diffuse;
mod fluorescent;
mod fresnel;
mod mask;
mod microfacet;
mod normal_map;
mod null;
mod pass;
mod perturbed;
use perturbed::Perturbs;
mod plastic;
mod polarized_plastic;
mod principled;
mod road;
mod rough_dielectric;
mod rough_plastic;
mod shading;

pub use blend::Blend;
pub use bump_map::BumpMap;
pub use conductor::Conductor;
pub use dielectric::{Dielectric, Ior, ThinDielectric};
pub use diffuse::Diffuse;
pub use fluorescent::{Donaldson, Fluorescent, Reradiation, Separable};
pub use fresnel::{fresnel_conductor, fresnel_dielectric};
pub use mask::Mask;
pub use microfacet::{
    MicrofacetDistribution, MicrofacetKind, Roughness, TexturedRoughness, MIN_ALPHA,
};
pub use normal_map::NormalMap;
pub use null::Null;
pub use plastic::{diffuse_fresnel_reflectance, Plastic};
pub use polarized_plastic::PolarizedPlastic;
pub use principled::{
    mitsuba_wavelength_pdf, specular_to_eta, Principled, PrincipledThin, SamplingRates,
    ThinSamplingRates,
};
pub use road::RoadSurface;
pub use rough_dielectric::RoughDielectric;
pub use rough_plastic::RoughPlastic;
pub use shading::ShadingPoint;

use scotopia_color::{SampledSpectrum, SampledWavelengths};

use crate::math::Vec3;
use crate::texture::TexPoint;

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

impl<const K: usize> BsdfSample<K> {
    /// A direction `wo` drawn from a mixture of strategies whose density
    /// there is `q`, where the BSDF's value (the cosine included) is `f`:
    /// its weight f/q; `None` where it carries nothing or q is no density.
    pub fn mixed(wo: Vec3, f: SampledSpectrum<K>, q: f32) -> Option<Self> {
        (q > 0.0 && q.is_finite() && !f.is_zero()).then(|| Self {
            wo,
            weight: f * (1.0 / q),
            pdf: q,
            delta: false,
            collapse: false,
        })
    }

    /// Whether the sample went straight on through a null lobe (`null`,
    /// a mask's hole, a thin dielectric's slab) from local direction
    /// `wi`: no scattering, which volume tracers pass through.
    #[inline]
    pub fn passes_through(&self, wi: Vec3) -> bool {
        self.delta && self.wo == -wi
    }
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
    /// No scattering: light passes straight through (Mitsuba's `null`).
    Null(Null),
    /// The inner BSDF with probability `opacity`, else null.
    Mask(Box<Mask>),
    /// A mixture of two BSDFs (Mitsuba's `blendbsdf`).
    Blend(Box<Blend>),
    /// The inner BSDF in a frame read from a normal map.
    NormalMap(Box<NormalMap>),
    /// The inner BSDF in a frame tilted by a height texture.
    BumpMap(Box<BumpMap>),
    /// Mitsuba's `pplastic` read without polarisation.
    PolarizedPlastic(PolarizedPlastic),
    /// Mitsuba's `principled` (Disney) BSDF.
    Principled(Box<Principled>),
    /// Mitsuba's `principledthin`: the principled model on a thin sheet.
    PrincipledThin(Box<PrincipledThin>),
    /// A CIE road surface by its r-table (scotopia's `roadsurface`).
    Road(Box<RoadSurface>),
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
        at: impl Into<ShadingPoint>,
        wi: Vec3,
        wo: Vec3,
        mode: Transport,
    ) -> SampledSpectrum<K> {
        let at: ShadingPoint = at.into();
        let uv = at.tex();
        match self {
            Bsdf::Diffuse(b) => b.eval(wl, uv, wi, wo),
            Bsdf::Conductor(b) => b.eval(wl, uv, wi, wo),
            Bsdf::Dielectric(_) | Bsdf::ThinDielectric(_) => SampledSpectrum::splat(0.0),
            Bsdf::RoughDielectric(b) => b.eval(wl, uv, wi, wo, mode),
            Bsdf::Plastic(b) => b.eval(wl, uv, wi, wo),
            Bsdf::RoughPlastic(b) => b.eval(wl, uv, wi, wo),
            Bsdf::Fluorescent(b) => b.eval(wi, wo),
            Bsdf::TwoSided(inner) => {
                let (at, wi, wo) = two_sided(at, wi, wo);
                inner.eval(wl, at, wi, wo, mode)
            }
            Bsdf::Null(_) => SampledSpectrum::splat(0.0),
            Bsdf::Mask(b) => b.eval(wl, at, wi, wo, mode),
            Bsdf::Blend(b) => b.eval(wl, at, wi, wo, mode),
            Bsdf::NormalMap(b) => b.eval(wl, at, wi, wo, mode),
            Bsdf::BumpMap(b) => b.eval(wl, at, wi, wo, mode),
            Bsdf::PolarizedPlastic(b) => b.eval(wl, uv, wi, wo),
            Bsdf::Principled(b) => b.eval(wl, uv, wi, wo, mode),
            Bsdf::PrincipledThin(b) => b.eval(wl, uv, wi, wo),
            Bsdf::Road(b) => b.eval(wl, wi, wo, mode),
        }
    }

    /// [`Bsdf::pdf_at`] at texture coordinates (0, 0) of a flat surface:
    /// the density of every BSDF whose sampling does not depend on the
    /// point (all but `mask`, `blendbsdf`, `normalmap`, `bumpmap` with
    /// textures, textured roughness, `principled`); the tracers use
    /// `pdf_at`.
    pub fn pdf<const K: usize>(&self, wl: &SampledWavelengths<K>, wi: Vec3, wo: Vec3) -> f32 {
        self.pdf_at(wl, [0.0, 0.0], wi, wo)
    }

    /// Density of `sample` at `at` producing `wo` by its non-delta lobes
    /// (zero for pure delta BSDFs); for a dispersive lobe, the first
    /// wavelength's.
    pub fn pdf_at<const K: usize>(
        &self,
        wl: &SampledWavelengths<K>,
        at: impl Into<ShadingPoint>,
        wi: Vec3,
        wo: Vec3,
    ) -> f32 {
        let at: ShadingPoint = at.into();
        match self {
            Bsdf::Diffuse(b) => b.pdf(wi, wo),
            Bsdf::Road(b) => b.pdf(wi, wo),
            Bsdf::Conductor(b) => b.pdf(at.tex(), wi, wo),
            Bsdf::Dielectric(_) | Bsdf::ThinDielectric(_) => 0.0,
            Bsdf::RoughDielectric(b) => b.pdf(wl, at.tex(), wi, wo),
            Bsdf::Plastic(b) => b.pdf(wi, wo),
            Bsdf::RoughPlastic(b) => b.pdf(wi, wo),
            Bsdf::Fluorescent(b) => b.pdf(wi, wo),
            Bsdf::TwoSided(inner) => {
                let (at, wi, wo) = two_sided(at, wi, wo);
                inner.pdf_at(wl, at, wi, wo)
            }
            Bsdf::Null(_) => 0.0,
            Bsdf::Mask(b) => b.pdf(wl, at, wi, wo),
            Bsdf::Blend(b) => b.pdf(wl, at, wi, wo),
            Bsdf::NormalMap(b) => b.pdf(wl, at, wi, wo),
            Bsdf::BumpMap(b) => b.pdf(wl, at, wi, wo),
            Bsdf::PolarizedPlastic(b) => b.pdf(at.tex(), wi, wo),
            Bsdf::Principled(b) => b.pdf(at.tex(), wi, wo),
            Bsdf::PrincipledThin(b) => b.pdf(at.tex(), wi, wo),
        }
    }

    /// Samples a continuation: `u_lobe` picks a lobe, `u` the direction.
    pub fn sample<const K: usize>(
        &self,
        wl: &SampledWavelengths<K>,
        at: impl Into<ShadingPoint>,
        wi: Vec3,
        u_lobe: f32,
        u: [f32; 2],
        mode: Transport,
    ) -> Option<BsdfSample<K>> {
        let at: ShadingPoint = at.into();
        let uv = at.tex();
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
                let (at, wi) = if flip {
                    (at.mirrored(), Vec3::new(wi.x, wi.y, -wi.z))
                } else {
                    (at, wi)
                };
                let mut s = inner.sample(wl, at, wi, u_lobe, u, mode)?;
                if flip {
                    s.wo.z = -s.wo.z;
                }
                Some(s)
            }
            Bsdf::Null(b) => Some(b.sample(wl, uv, wi)),
            Bsdf::Mask(b) => b.sample(wl, at, wi, u_lobe, u, mode),
            Bsdf::Blend(b) => b.sample(wl, at, wi, u_lobe, u, mode),
            Bsdf::NormalMap(b) => b.sample(wl, at, wi, u_lobe, u, mode),
            Bsdf::BumpMap(b) => b.sample(wl, at, wi, u_lobe, u, mode),
            Bsdf::PolarizedPlastic(b) => b.sample(wl, uv, wi, u_lobe, u),
            Bsdf::Principled(b) => b.sample(wl, uv, wi, u_lobe, u, mode),
            Bsdf::PrincipledThin(b) => b.sample(wl, uv, wi, u_lobe, u),
            Bsdf::Road(b) => b.sample(wl, wi, u, mode),
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
        uv: impl Into<TexPoint>,
        u: f32,
    ) -> Option<SampledSpectrum<K>> {
        let uv: TexPoint = uv.into();
        match self {
            Bsdf::Fluorescent(b) => Some(b.reradiate(wl, uv, u)),
            Bsdf::TwoSided(inner) => inner.reradiate(wl, uv, u),
            Bsdf::NormalMap(b) => b.inner.reradiate(wl, uv, u),
            Bsdf::BumpMap(b) => b.inner.reradiate(wl, uv, u),
            _ => None,
        }
    }

    /// The fluorescent BSDF inside, if any.
    pub fn fluorescent(&self) -> Option<&Fluorescent> {
        match self {
            Bsdf::Fluorescent(f) => Some(f),
            Bsdf::TwoSided(inner) => inner.fluorescent(),
            Bsdf::NormalMap(b) => b.inner.fluorescent(),
            Bsdf::BumpMap(b) => b.inner.fluorescent(),
            // The loader refuses fluorescence under a mask or a blend,
            // whose other part would take its re-emission.
            _ => None,
        }
    }

    /// Whether every lobe is a delta (no `eval`, no light sampling).
    pub fn is_delta(&self) -> bool {
        match self {
            Bsdf::Diffuse(_) | Bsdf::Fluorescent(_) | Bsdf::Road(_) => false,
            Bsdf::Conductor(c) => c.is_smooth(),
            Bsdf::Dielectric(_) | Bsdf::ThinDielectric(_) => true,
            Bsdf::RoughDielectric(_) | Bsdf::Plastic(_) | Bsdf::RoughPlastic(_) => false,
            Bsdf::TwoSided(inner) => inner.is_delta(),
            Bsdf::Null(_) => true,
            Bsdf::Mask(b) => b.inner.is_delta(),
            Bsdf::Blend(b) => b.first.is_delta() && b.second.is_delta(),
            Bsdf::NormalMap(b) => b.inner.is_delta(),
            Bsdf::BumpMap(b) => b.inner.is_delta(),
            Bsdf::PolarizedPlastic(_) | Bsdf::Principled(_) | Bsdf::PrincipledThin(_) => false,
        }
    }
}

impl Bsdf {
    /// Whether light leaving this surface goes only where delta lobes send
    /// it (a mirror, smooth glass; `null` passes light on unchanged): the
    /// caustics it casts are found by light subpaths alone.
    pub fn casts_caustics(&self) -> bool {
        self.is_delta() && !matches!(self, Bsdf::Null(_))
    }
}

/// The point and both directions moved to the upper side when `wi` is
/// below.
#[inline]
fn two_sided(at: ShadingPoint, wi: Vec3, wo: Vec3) -> (ShadingPoint, Vec3, Vec3) {
    if wi.z < 0.0 {
        (
            at.mirrored(),
            Vec3::new(wi.x, wi.y, -wi.z),
            Vec3::new(wo.x, wo.y, -wo.z),
        )
    } else {
        (at, wi, wo)
    }
}
