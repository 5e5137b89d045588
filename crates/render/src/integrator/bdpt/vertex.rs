//! Path vertices of the bidirectional tracer and the densities stored on
//! them (Veach 1997, §10.2): each vertex keeps the area density with which
//! its own subpath generated it (`pdf_fwd`) and the one with which the
//! other subpath would have (`pdf_rev`), from which the weights of every
//! strategy follow as ratios (see `mis`).

use scotopia_color::SampledSpectrum;

use crate::bsdf::ShadingPoint;
use crate::math::{Frame, Vec3};
use crate::texture::TexPoint;

/// Longest subpath, vertices (fluorescence runs are indexed by `u8`).
pub(super) const MAX_VERTICES: usize = 250;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Kind {
    /// The lens point a camera subpath starts at.
    Camera,
    /// The point a light subpath starts at, on light `index`.
    Light,
    /// A point on a shape (`index`), where a BSDF scatters.
    Surface,
    /// Where a camera ray escaped: the lights at infinity, together.
    Infinite,
    /// A scattering event in medium `index` (`Scene::media`), where the
    /// phase function scatters: no surface, so no cosine in the density
    /// conversions (`convert`, `cos`).
    Medium,
}

#[derive(Debug, Clone, Copy)]
pub(super) struct Vertex<const K: usize> {
    pub kind: Kind,
    pub p: Vec3,
    /// Geometric and shading normals; zero where there is no surface.
    pub ng: Vec3,
    pub ns: Vec3,
    /// Where textures are looked up (surfaces).
    pub tex: TexPoint,
    /// ∂p/∂u and ∂p/∂v (surfaces), which orient the shading frame.
    pub dpdu: Vec3,
    pub dpdv: Vec3,
    /// The shape (surfaces) or the light (light vertices).
    pub index: u32,
    /// Unit direction towards the previous vertex of its subpath; for
    /// `Infinite`, towards the light (where the ray went).
    pub wi: Vec3,
    /// The subpath's throughput arriving here, per member.
    pub beta: SampledSpectrum<K>,
    /// Left by a delta lobe (or a delta light): cannot be connected.
    pub delta: bool,
    /// The light is at infinity (environment, directional): densities
    /// towards the next vertex are per unit area of the emitting disk.
    pub at_infinity: bool,
    pub pdf_fwd: f32,
    pub pdf_rev: f32,
    /// Light subpaths with fluorescence: per member, the vertex where the
    /// wavelength arriving here was emitted (0: by the light) and where the
    /// one leaving starts (this vertex if it re-emitted).
    pub run_in: [u8; K],
    pub run_out: [u8; K],
    /// Per member re-emitted here, the reradiation factor (times π) and
    /// the new wavelength.
    pub shift: SampledSpectrum<K>,
    pub lambda_out: [f32; K],
    /// Media (`Bidirectional::media`): the medium the vertex sits in — for
    /// a surface vertex the one its subpath arrived through, for a light
    /// the one around it; a surface bounding media replaces it on the side
    /// a direction leaves by (`Renderer::medium_towards`).
    pub medium: Option<u32>,
    /// The cluster collapsed to its first member on the way here: `beta`
    /// holds that member alone, times K (`media::take_event`).
    pub collapsed: bool,
}

impl<const K: usize> Vertex<K> {
    pub fn new(kind: Kind, p: Vec3, beta: SampledSpectrum<K>) -> Self {
        Self {
            kind,
            p,
            ng: Vec3::ZERO,
            ns: Vec3::ZERO,
            tex: TexPoint::default(),
            dpdu: Vec3::ZERO,
            dpdv: Vec3::ZERO,
            index: 0,
            wi: Vec3::ZERO,
            beta,
            delta: false,
            at_infinity: false,
            pdf_fwd: 0.0,
            pdf_rev: 0.0,
            run_in: [0; K],
            run_out: [0; K],
            shift: SampledSpectrum::splat(0.0),
            lambda_out: [0.0; K],
            medium: None,
            collapsed: false,
        }
    }

    /// The shading frame at a surface vertex and the point its BSDF sees.
    #[inline]
    pub fn shading(&self) -> (Frame, ShadingPoint) {
        ShadingPoint::at(self.tex, self.ns, self.ng, self.dpdu, self.dpdv)
    }

    pub fn on_surface(&self) -> bool {
        self.ng != Vec3::ZERO
    }

    /// |cos| between the vertex's geometric normal and unit `d` (1 where
    /// there is no surface).
    pub fn cos(&self, d: Vec3) -> f32 {
        if self.on_surface() {
            self.ng.dot(d).abs()
        } else {
            1.0
        }
    }

    /// A density of leaving this vertex towards `next` — per solid angle,
    /// or per unit disk area when this is a light at infinity — as a
    /// density per unit area at `next` (per solid angle if `next` is at
    /// infinity).
    pub fn convert(&self, pdf: f32, next: &Vertex<K>) -> f32 {
        if next.kind == Kind::Infinite || next.at_infinity {
            return pdf;
        }
        let d = next.p - self.p;
        let dist2 = d.length_squared();
        if dist2 == 0.0 {
            return 0.0;
        }
        let cos = next.cos(d / dist2.sqrt());
        if self.at_infinity {
            pdf * cos
        } else {
            pdf * cos / dist2
        }
    }
}

/// The factor that makes shading normals symmetric for light paths
/// (Veach 1997, §5.3, eq. 5.19): |wi·ns||wo·ng| / (|wi·ng||wo·ns|), with
/// `wi` towards where the light came from and `wo` where it goes.
#[inline]
pub(super) fn shading_correction(ng: Vec3, ns: Vec3, wi: Vec3, wo: Vec3) -> f32 {
    let den = wi.dot(ng).abs() * wo.dot(ns).abs();
    if den == 0.0 {
        0.0
    } else {
        wi.dot(ns).abs() * wo.dot(ng).abs() / den
    }
}
