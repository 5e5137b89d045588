//! Participating media in the bidirectional tracer (issue 25), after
//! pbrt-v3's BDPT with media (Pharr, Jakob & Humphreys 2016, §16.3).
//!
//! **Vertices.** Both subpaths draw free flights in the medium they travel
//! in (`Medium::sample_event`); a scattering event is a `Kind::Medium`
//! vertex whose "BSDF" is the phase function (value = density, no cosine).
//! Null surfaces (a medium's boundary, `null`, a thin dielectric's
//! straight-through lobe) are not vertices: the walk passes them and
//! switches medium, as the path tracer does.
//!
//! **Connections** (s, t ≥ 1, light tracing t = 1, the light point of
//! s = 1) are weighted by the transmittance of the media and null surfaces
//! between their endpoints (`Renderer::through_media`), starting in the
//! medium on the segment's side of the first endpoint
//! (`Renderer::medium_towards`).
//!
//! **MIS.** The strategies' densities are the directional ones converted
//! to area measure (no cosine at a medium vertex, `Vertex::convert`); the
//! probabilities of the free flights (and of passing null lobes) are left
//! out of every strategy's density alike, as pbrt-v3 does: each weight is
//! still one function of the path, the same whichever strategy built it,
//! so the weights sum to 1 and the estimator stays unbiased.
//!
//! **The light's medium.** Mitsuba declares a medium for shapes (either
//! side) and the sensor, never for a point-like light. An area light on a
//! shape that bounds media emits into the medium on the emitted
//! direction's side. Otherwise the light sits in the medium that the
//! sensor's medium implies at its position: the one reached walking the
//! straight segment from the lens point to the light, switching at every
//! medium boundary crossed (`Renderer::medium_at`). A light at infinity
//! that this walk leaves inside a medium is not reached at all (the path
//! tracer, whose flights in an unbounded medium never escape, agrees).
//!
//! **Chromatic media.** A free flight is drawn for the cluster's first
//! member. Where the live members' densities of the event agree (grey σ_t,
//! whatever the albedo) every member keeps its own estimate. Where they
//! differ the subpath's cluster collapses to its first member (times K),
//! as at a dispersive refraction: the flight is then exact importance
//! sampling for the one wavelength left, and the first member being
//! uniform over the cluster keeps the estimate unbiased. A path whose two
//! subpaths both collapsed counts that factor K once (`Vertex::collapsed`).

use scotopia_color::{SampledSpectrum, SampledWavelengths};

use super::vertex::{Kind, Vertex};
use crate::bsdf::Transport;
use crate::integrator::direct::spawn;
use crate::integrator::Renderer;
use crate::light::Light;
use crate::math::{Ray, Vec3};
use crate::medium::MediumEvent;

/// Largest relative spread of the live members' densities of one event for
/// which the medium counts as grey there.
const GREY: f32 = 1e-4;

/// Most medium boundaries `Renderer::medium_at` crosses.
const MAX_CROSSINGS: usize = 256;

/// Takes free-flight event `e` into a subpath's throughput `beta`,
/// collapsing the cluster where the members' densities differ (see the
/// module notes); whether the subpath still carries light.
pub(super) fn take_event<const K: usize>(
    beta: &mut SampledSpectrum<K>,
    e: &MediumEvent<K>,
    collapsed: &mut bool,
) -> bool {
    let live = if *collapsed { 1 } else { K };
    let d0 = e.density.0[0];
    let grey = e.density.0[..live]
        .iter()
        .all(|&d| (d - d0).abs() <= GREY * d0);
    if grey {
        if d0.is_nan() || d0 <= 0.0 {
            *beta = SampledSpectrum::splat(0.0);
            return false;
        }
        // f_k / p_0 = own_k · p_k / p_0: each member's estimate under the
        // first member's sampling (the ratio is 1 up to GREY).
        let b = *beta;
        *beta = SampledSpectrum::from_fn(|k| {
            if k < live {
                b.0[k] * e.own.0[k] * e.density.0[k] / d0
            } else {
                0.0
            }
        });
    } else {
        *collapsed = true;
        let b0 = beta.0[0] * e.own.0[0] * K as f32;
        *beta = SampledSpectrum::from_fn(|k| if k == 0 { b0 } else { 0.0 });
    }
    !beta.is_zero() && beta.max_value().is_finite()
}

impl Renderer<'_> {
    /// The medium a ray leaving vertex `v` in direction `d` travels in.
    pub(super) fn medium_towards<const K: usize>(&self, v: &Vertex<K>, d: Vec3) -> Option<u32> {
        let shape = match v.kind {
            Kind::Surface => Some(v.index),
            Kind::Light => match self.scene.lights.get(v.index as usize) {
                Some(Light::Area(a)) => Some(a.shape),
                _ => None,
            },
            _ => None,
        };
        match shape.and_then(|s| self.shape_media(s)) {
            Some(sides) => sides.target(d, v.ng),
            None => v.medium,
        }
    }

    /// The medium at `to` implied by `medium` at `from`: the one reached
    /// along the straight segment, switching at every shape that bounds
    /// media (whatever its BSDF).
    pub(super) fn medium_at(
        &self,
        from: Vec3,
        mut medium: Option<u32>,
        to: Vec3,
        rays: &mut u64,
    ) -> Option<u32> {
        let geometry = &self.scene.geometry;
        let d = to - from;
        let dist = d.length();
        if !(dist > 0.0 && dist.is_finite()) {
            return medium;
        }
        let dir = d / dist;
        let mut ray = Ray::new(from, dir);
        ray.t_max = dist;
        for _ in 0..MAX_CROSSINGS {
            *rays += 1;
            let Some(hit) = geometry.intersect(&ray) else {
                return medium;
            };
            let surface = geometry.surface(&hit, &ray);
            let ng = surface.n_geometric;
            if let Some(sides) = self.shape_media(hit.shape) {
                medium = sides.target(dir, ng);
            }
            ray = spawn(surface.p, ng, dir, geometry.offset_unit());
            let left = (to - ray.o).dot(dir);
            if left <= 0.0 {
                return medium;
            }
            ray.t_max = left;
        }
        medium
    }

    /// Whether a connection can be made at `v`: a scattering vertex whose
    /// scattering is not a delta.
    pub(super) fn connectible<const K: usize>(&self, v: &Vertex<K>) -> bool {
        match v.kind {
            Kind::Surface => !self.bsdf_at(v).is_delta(),
            Kind::Medium => true,
            _ => false,
        }
    }

    /// What scattering vertex `v` sends from its `wi` into unit `d` (BSDF
    /// times cosine, with the shading-normal correction for importance, or
    /// the phase function), and apart from it the elastic factor of a
    /// fluorescent BSDF (1 elsewhere).
    pub(super) fn scatter_f<const K: usize>(
        &self,
        v: &Vertex<K>,
        wl: &SampledWavelengths<K>,
        d: Vec3,
        mode: Transport,
    ) -> (SampledSpectrum<K>, SampledSpectrum<K>) {
        let one = SampledSpectrum::splat(1.0);
        match v.kind {
            Kind::Medium => {
                let phase = self.scene.media[v.index as usize].phase();
                (SampledSpectrum::splat(phase.eval(v.wi, d)), one)
            }
            Kind::Surface => {
                let bsdf = self.bsdf_at(v);
                let (frame, at) = v.shading();
                let mut f = bsdf.eval(wl, at, frame.to_local(v.wi), frame.to_local(d), mode);
                if mode == Transport::Importance {
                    f *= super::vertex::shading_correction(v.ng, v.ns, v.wi, d);
                }
                (f, super::connect::elastic(bsdf, wl, v.tex))
            }
            _ => (SampledSpectrum::splat(0.0), one),
        }
    }

    /// Density per solid angle with which scattering vertex `v` sends
    /// light arriving from `from` on into `to` (unit vectors away from v).
    pub(super) fn scatter_pdf<const K: usize>(
        &self,
        v: &Vertex<K>,
        wl: &SampledWavelengths<K>,
        from: Vec3,
        to: Vec3,
    ) -> f32 {
        match v.kind {
            Kind::Medium => self.scene.media[v.index as usize].phase().eval(from, to),
            Kind::Surface => {
                let (frame, at) = v.shading();
                self.bsdf_at(v)
                    .pdf_at(wl, at, frame.to_local(from), frame.to_local(to))
            }
            _ => 0.0,
        }
    }
}
