//! Lights: point, spot, directional, area (on any shape), a constant
//! environment and an environment map. Each samples an incident direction
//! at a point, evaluates the density of directions found by BSDF sampling
//! (for MIS), and reports its total power, so that lights can be chosen in
//! proportion to it.
//!
//! Units: area and environment emitters give spectral radiance
//! (W·sr⁻¹·m⁻²·nm⁻¹); point and spot lights spectral intensity
//! (W·sr⁻¹·nm⁻¹); directional lights spectral irradiance (W·m⁻²·nm⁻¹).

mod area;
mod emit;
mod emit_disk;
mod envmap;
mod goniometric;
mod hierarchy;
mod power;
mod projector;
mod simple;

pub use area::AreaLight;
pub use emit::{Emission, EmissionPdf};
pub use emit_disk::{Caster, CASTER_SHARE, MAX_CASTERS};
pub use envmap::EnvMapLight;
pub use goniometric::{GoniometricLight, IntensityGrid};
pub use hierarchy::LightHierarchy;
pub use power::{spectral_power, Power};
pub use projector::ProjectorLight;
pub use simple::{ConstantLight, DirectionalLight, PointLight, SpotLight};

use scotopia_color::{SampledSpectrum, SampledWavelengths, Spectrum};

use crate::geometry::Shape;
use crate::math::{Aabb, Vec3};

/// An incident-light sample at a reference point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LightSample<const K: usize> {
    /// Unit direction from the reference point towards the light.
    pub wi: Vec3,
    /// Distance to the sampled point (∞ for directional and environment).
    pub distance: f32,
    /// Incident radiance (for delta lights: intensity/d² or irradiance).
    pub radiance: SampledSpectrum<K>,
    /// Density per solid angle; 1 for delta lights.
    pub pdf: f32,
    pub delta: bool,
    /// The light's surface normal at the sampled point (area lights;
    /// zero for the others).
    pub n: Vec3,
}

/// The closed set of lights.
#[derive(Debug, Clone, PartialEq)]
pub enum Light {
    Point(PointLight),
    Spot(SpotLight),
    /// Boxed: it carries a camera and a texture.
    Projector(Box<ProjectorLight>),
    /// A luminaire measured as I(γ, C) (IES, EULUMDAT).
    Goniometric(GoniometricLight),
    Directional(DirectionalLight),
    Area(AreaLight),
    Constant(ConstantLight),
    EnvMap(Box<EnvMapLight>),
}

/// The scene facts lights need: the shapes (for area lights), the
/// bounding sphere (for lights at infinity) and the shapes light subpaths
/// from infinity are aimed at (`emit_disk`; empty: none).
#[derive(Debug, Clone, Copy)]
pub struct SceneExtent<'a> {
    pub shapes: &'a [Shape],
    pub center: Vec3,
    pub radius: f32,
    pub casters: &'a [Caster],
}

impl Light {
    /// Where a light at a finite place is (its bounding box's centre for
    /// an area light), for sampling aimed at it; `None` at infinity.
    pub fn centre(&self, shapes: &[Shape]) -> Option<Vec3> {
        match self {
            Light::Point(l) => Some(l.position),
            Light::Spot(l) => Some(l.position),
            Light::Goniometric(l) => Some(l.position),
            Light::Projector(l) => Some(l.position),
            Light::Area(a) => {
                let shape = shapes.get(a.shape as usize)?;
                let b = (0..shape.primitive_count())
                    .fold(Aabb::EMPTY, |b, prim| b.union(shape.bounds(prim)));
                (!b.is_empty()).then(|| b.centroid())
            }
            Light::Directional(_) | Light::Constant(_) | Light::EnvMap(_) => None,
        }
    }

    /// Samples incident light at `p` with `u` ∈ [0, 1)² and `u_select`
    /// (choosing a triangle of a mesh emitter).
    pub fn sample_li<const K: usize>(
        &self,
        scene: &SceneExtent,
        wl: &SampledWavelengths<K>,
        p: Vec3,
        u_select: f32,
        u: [f32; 2],
    ) -> Option<LightSample<K>> {
        match self {
            Light::Point(l) => l.sample_li(wl, p),
            Light::Spot(l) => l.sample_li(wl, p),
            Light::Projector(l) => l.sample_li(wl, p),
            Light::Goniometric(l) => l.sample_li(wl, p),
            Light::Directional(l) => l.sample_li(wl),
            Light::Area(l) => l.sample_li(scene.shapes, wl, p, u_select, u),
            Light::Constant(l) => l.sample_li(wl, u),
            Light::EnvMap(l) => l.sample_li(wl, u),
        }
    }

    /// Whether the light is a delta distribution (not hit by rays).
    pub fn is_delta(&self) -> bool {
        matches!(
            self,
            Light::Point(_)
                | Light::Spot(_)
                | Light::Projector(_)
                | Light::Goniometric(_)
                | Light::Directional(_)
        )
    }

    /// Whether the light lies at infinity and is seen by escaping rays.
    pub fn is_infinite(&self) -> bool {
        matches!(self, Light::Constant(_) | Light::EnvMap(_))
    }

    /// Radiance an escaping ray finds in world direction `d` (zero for
    /// lights not at infinity).
    pub fn radiance_at_infinity<const K: usize>(
        &self,
        wl: &SampledWavelengths<K>,
        d: Vec3,
    ) -> SampledSpectrum<K> {
        match self {
            Light::Constant(l) => l.radiance.sample(wl),
            Light::EnvMap(l) => l.radiance(wl, d),
            _ => SampledSpectrum::splat(0.0),
        }
    }

    /// Density per solid angle of `sample_li` choosing the direction `d` to
    /// a light at infinity (zero for other lights).
    pub fn pdf_li_at_infinity(&self, d: Vec3) -> f32 {
        match self {
            Light::Constant(l) => l.pdf_li(),
            Light::EnvMap(l) => l.pdf_li(d),
            _ => 0.0,
        }
    }

    /// The spectral shape of the light's emission (its radiance, intensity,
    /// irradiance; for a textured area light or projector the mean over its
    /// surface or image; for a map the radiance integrated over
    /// directions): what wavelengths are drawn from for it. Any shape will
    /// do for an unbiased image (the estimate divides by the density it
    /// drew with, and the defensive share covers every wavelength); a
    /// close one lowers the noise.
    pub fn spectrum(&self) -> &Spectrum {
        match self {
            Light::Point(l) => &l.intensity,
            Light::Spot(l) => &l.intensity,
            Light::Projector(l) => l.spectrum(),
            Light::Goniometric(l) => &l.spectrum,
            Light::Directional(l) => &l.irradiance,
            Light::Area(l) => l.mean_radiance(),
            Light::Constant(l) => &l.radiance,
            Light::EnvMap(l) => l.total_spectrum(),
        }
    }

    /// Total emitted power.
    pub fn power(&self, scene: &SceneExtent) -> Power {
        match self {
            Light::Point(l) => l.power(),
            Light::Spot(l) => l.power(),
            Light::Projector(l) => l.power(),
            Light::Goniometric(l) => l.power(),
            Light::Directional(l) => l.power(scene.radius),
            Light::Area(l) => l.power(),
            Light::Constant(l) => l.power(scene.radius),
            Light::EnvMap(l) => l.power(scene.radius),
        }
    }
}
