//! Lights as the start of a light path (Veach 1997, §10.2; pbrt-v4 §12.1):
//! a point and direction of emission drawn with densities per unit area
//! and per solid angle. Delta distributions (the point of a point or spot
//! light, the direction of a directional light) have density 1 as a
//! marker, as in `LightSample`. Lights at infinity emit from a disk of the
//! scene's bounding radius R facing the direction they shine in, placed
//! outside the scene, from points drawn partly towards the shapes that
//! cast caustics (`emit_disk`): a density per unit area of the disk that
//! depends on the point.

use scotopia_color::{SampledSpectrum, SampledWavelengths};

use super::{Light, SceneExtent};
use crate::math::{Frame, Vec3};
use crate::sampling::warp::{
    cosine_hemisphere_pdf, square_to_cosine_hemisphere, square_to_uniform_cone,
    square_to_uniform_sphere, uniform_cone_pdf, UNIFORM_SPHERE_PDF,
};

/// A sampled emission.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Emission<const K: usize> {
    pub p: Vec3,
    /// The emitting surface's normal (area lights), else `None`.
    pub n: Option<Vec3>,
    /// Texture coordinates of the emitting point (area lights; else 0).
    pub uv: [f32; 2],
    /// Unit direction the light leaves in.
    pub d: Vec3,
    /// Radiance (area, infinite), intensity (point, spot) or irradiance
    /// (directional) leaving in `d`.
    pub le: SampledSpectrum<K>,
    pub pdf_pos: f32,
    pub pdf_dir: f32,
}

impl<const K: usize> Emission<K> {
    /// Emission from a point-like light at `p` in direction `d` (its
    /// position a delta distribution: density 1 as the marker).
    fn from_point(p: Vec3, d: Vec3, le: SampledSpectrum<K>, pdf_dir: f32) -> Self {
        Self {
            p,
            n: None,
            uv: [0.0; 2],
            d,
            le,
            pdf_pos: 1.0,
            pdf_dir,
        }
    }
}

/// Densities of a light emitting from a point in a direction.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EmissionPdf {
    pub pos: f32,
    pub dir: f32,
}

impl Light {
    /// Whether the light's position is a delta distribution (nothing can
    /// hit it) or its direction is (nothing can be connected to it by a
    /// chosen direction): such lights end light paths only by `sample_li`.
    pub fn is_delta_position(&self) -> bool {
        matches!(
            self,
            Light::Point(_) | Light::Spot(_) | Light::Projector(_) | Light::Goniometric(_)
        )
    }

    pub fn is_delta_direction(&self) -> bool {
        matches!(self, Light::Directional(_))
    }

    /// Draws an emission: `u_select` chooses a mesh triangle, `u_pos` the
    /// point, `u_dir` the direction.
    pub fn sample_le<const K: usize>(
        &self,
        scene: &SceneExtent,
        wl: &SampledWavelengths<K>,
        u_select: f32,
        u_pos: [f32; 2],
        u_dir: [f32; 2],
    ) -> Option<Emission<K>> {
        match self {
            Light::Point(l) => {
                let d = square_to_uniform_sphere(u_dir);
                Some(Emission::from_point(
                    l.position,
                    d,
                    l.intensity.sample(wl),
                    UNIFORM_SPHERE_PDF,
                ))
            }
            Light::Spot(l) => {
                let one_minus_cos = 1.0 - l.cutoff.cos();
                let (local, pdf_dir) = (
                    square_to_uniform_cone(u_dir, one_minus_cos),
                    uniform_cone_pdf(one_minus_cos),
                );
                let d = l.frame.to_world(local);
                (l.falloff(local.z) > 0.0).then(|| {
                    Emission::from_point(l.position, d, l.intensity_towards(wl, d), pdf_dir)
                })
            }
            Light::Projector(l) => {
                let (d, pdf_dir) = l.sample_direction(u_dir);
                (pdf_dir > 0.0).then(|| {
                    Emission::from_point(l.position, d, l.intensity_towards(wl, d), pdf_dir)
                })
            }
            Light::Goniometric(l) => {
                let (d, pdf_dir) = l.sample_direction(u_dir)?;
                Some(Emission::from_point(
                    l.position,
                    d,
                    l.intensity_towards(wl, d),
                    pdf_dir,
                ))
            }
            Light::Directional(l) => {
                let (p, pdf_pos) = scene.sample_disk(l.direction, u_pos);
                Some(Emission {
                    p,
                    n: None,
                    uv: [0.0; 2],
                    d: l.direction,
                    le: l.irradiance.sample(wl),
                    pdf_pos,
                    pdf_dir: 1.0,
                })
            }
            Light::Area(l) => {
                let shape = scene.shapes.get(l.shape as usize)?;
                let s = shape.sample_area(l.triangles(), u_select, u_pos)?;
                let local = square_to_cosine_hemisphere(u_dir);
                let pdf_dir = cosine_hemisphere_pdf(local.z);
                let d = Frame::from_normal(s.n).to_world(local);
                (pdf_dir > 0.0 && l.area() > 0.0).then(|| Emission {
                    p: s.p,
                    n: Some(s.n),
                    uv: s.uv,
                    d,
                    le: l.radiance.eval(wl, s.uv),
                    pdf_pos: 1.0 / l.area(),
                    pdf_dir,
                })
            }
            Light::Constant(_) | Light::EnvMap(_) => {
                let ls = self.sample_li(scene, wl, Vec3::ZERO, 0.0, u_dir)?;
                let d = -ls.wi;
                let (p, pdf_pos) = scene.sample_disk(d, u_pos);
                Some(Emission {
                    p,
                    n: None,
                    uv: [0.0; 2],
                    d,
                    le: ls.radiance,
                    pdf_pos,
                    pdf_dir: ls.pdf,
                })
            }
        }
    }

    /// Radiance (area lights, from texture point `uv` on a surface of
    /// normal `n`) or intensity (point-like lights) leaving in direction
    /// `d`; zero for lights at infinity and directional lights, whose
    /// emission is not drawn by direction.
    pub fn emitted_towards<const K: usize>(
        &self,
        wl: &SampledWavelengths<K>,
        uv: [f32; 2],
        n: Vec3,
        d: Vec3,
    ) -> SampledSpectrum<K> {
        match self {
            Light::Area(a) => a.radiance(wl, uv, n, d),
            Light::Point(p) => p.intensity.sample(wl),
            Light::Spot(s) => s.intensity_towards(wl, d),
            Light::Projector(p) => p.intensity_towards(wl, d),
            Light::Goniometric(g) => g.intensity_towards(wl, d),
            _ => SampledSpectrum::splat(0.0),
        }
    }

    /// Densities of `sample_le` emitting from `p` (normal `n` for area
    /// lights) in direction `d`. For lights at infinity `d` is the
    /// direction light travels and `pos` the disk's density where the line
    /// through `p` along `d` meets it (`p` may be any point of that line,
    /// the receiving one included).
    pub fn pdf_le(&self, scene: &SceneExtent, p: Vec3, n: Vec3, d: Vec3) -> EmissionPdf {
        match self {
            Light::Point(_) => EmissionPdf {
                pos: 1.0,
                dir: UNIFORM_SPHERE_PDF,
            },
            Light::Spot(l) => {
                let cos_max = l.cutoff.cos();
                let inside = d.dot(l.frame.n) >= cos_max;
                EmissionPdf {
                    pos: 1.0,
                    dir: if inside {
                        uniform_cone_pdf(1.0 - cos_max)
                    } else {
                        0.0
                    },
                }
            }
            Light::Projector(l) => EmissionPdf {
                pos: 1.0,
                dir: l.pdf_direction(d),
            },
            Light::Goniometric(l) => EmissionPdf {
                pos: 1.0,
                dir: l.pdf_direction(d),
            },
            Light::Directional(l) => EmissionPdf {
                pos: scene.disk_pdf(l.direction, p),
                dir: 1.0,
            },
            Light::Area(l) => EmissionPdf {
                pos: if l.area() > 0.0 { 1.0 / l.area() } else { 0.0 },
                dir: cosine_hemisphere_pdf(n.dot(d)),
            },
            Light::Constant(_) | Light::EnvMap(_) => EmissionPdf {
                pos: scene.disk_pdf(d, p),
                dir: self.pdf_li_at_infinity(-d),
            },
        }
    }
}
