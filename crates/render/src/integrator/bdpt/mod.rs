//! Bidirectional path tracing (Veach 1997, ch. 10; Veach & Guibas 1995)
//! with stratified wavelength clusters and fluorescence: a light subpath
//! and a camera subpath per camera sample, every connection strategy
//! (s, t) — light tracing (t = 1) splatted onto the film — combined by
//! multiple importance sampling (power heuristic).
//!
//! Wavelengths: the light subpath carries the SWC cluster and a light
//! chosen for it (`light_choice`); the camera subpath carries the same
//! cluster, or with fluorescence one drawn from the wavelengths along the
//! light subpath. Dispersion collapses the cluster on either subpath.
//!
//! Participating media (`media`): free flights on both subpaths make
//! medium vertices scattered by the phase function, and connections carry
//! the transmittance between their endpoints.

mod clusters;
mod connect;
mod guided;
mod media;
mod mis;
mod vertex;
mod walk;

use scotopia_color::photometry::estimate_xyzv;
use scotopia_color::{SampledSpectrum, SampledWavelengths};

use super::light_choice::ClusterChoice;
use super::renderer::{SampleStart, Scratchpad};
use super::select::Bidirectional;
use super::{CameraSample, Renderer};
use crate::sampling::sobol::Sampler;
use clusters::camera_cluster;
use connect::{Contribution, Draw, Subpaths};
use vertex::{Kind, Vertex};

/// A light-tracing contribution: where it lands on the film and what.
#[derive(Debug, Clone, Copy)]
pub struct Splat<const K: usize> {
    pub raster: [f32; 2],
    pub xyzv: [f32; 4],
    pub radiance: SampledSpectrum<K>,
    pub wl: SampledWavelengths<K>,
}

/// Buffers reused from sample to sample (one set per worker).
#[derive(Default)]
pub struct Scratch<const K: usize> {
    light: Vec<Vertex<K>>,
    camera: Vec<Vertex<K>>,
    choice: ClusterChoice,
}

impl Renderer<'_> {
    pub(super) fn has_infinite_lights(&self) -> bool {
        !self.infinite.is_empty()
    }

    /// One bidirectional sample of `pixel`: the camera-side estimate (or
    /// `None` when not finite) and, pushed on `splats`, the light-tracing
    /// contributions to whichever pixels they reach.
    pub(super) fn sample_pixel_bdpt<const K: usize>(
        &self,
        bidirectional: &Bidirectional,
        sampler: &mut Sampler,
        pixel: [u32; 2],
        index: u32,
        to: Scratchpad<'_, K>,
    ) -> Option<CameraSample<K>> {
        let Scratchpad {
            scratch,
            splats,
            counts,
            records,
        } = to;
        let SampleStart {
            film,
            lens,
            wl: first,
            spare: u_runs,
        } = self.start_sample::<K>(sampler, pixel, index);
        let u_rotate = sampler.get_1d();
        self.lights.for_cluster(&first, &mut scratch.choice);

        // The subpaths: Mitsuba's max_depth counts segments, so a camera
        // subpath has at most max_depth + 1 vertices and a light subpath
        // max_depth (t ≥ 1).
        let max_depth = self.scene.integrator.max_depth;
        let (max_camera, max_light) = if max_depth < 0 {
            (usize::MAX, usize::MAX)
        } else {
            (max_depth as usize + 1, max_depth as usize)
        };
        let (camera_ray, lens_point) = self.scene.camera.generate_ray_from_lens(film, lens);
        let mut rng = sampler.stream();
        let mut draw = Draw {
            sampler,
            rng: &mut rng,
            rays: &mut counts.rays,
            media: bidirectional.media,
        };
        let mut light_wl = first;
        let light_collapsed = self.light_subpath(
            &mut draw,
            lens_point,
            &mut light_wl,
            &scratch.choice,
            max_light,
            &mut scratch.light,
        );
        let (wl, lanes) = camera_cluster(&first, &scratch.light, u_runs, u_rotate);
        // Outside a fisheye's circle the camera subpath is its lens point
        // alone: only light tracing (t = 1) reaches the film from there.
        let max_camera = if self.scene.camera.sees(film) {
            max_camera
        } else {
            1
        };
        let camera_collapsed = self.camera_subpath(
            &mut draw,
            &wl,
            camera_ray,
            lens_point,
            max_camera,
            &mut scratch.camera,
        );

        // Every strategy (s, t) with t ≥ 1 and s + t − 1 ≤ max_depth.
        let sub = Subpaths {
            light: &scratch.light,
            camera: &scratch.camera,
            wl: &wl,
            lanes: &lanes,
            choice: &scratch.choice,
            unweighted: bidirectional.only.is_some(),
            by_point: self.lights.by_point(),
        };
        // While guiding learns: the light vertex's record (`guided`), the
        // light its direction brought to the camera.
        let slot = sub
            .light
            .first()
            .filter(|y0| y0.kind == Kind::Light)
            .and_then(|y0| {
                let light = self.scene.lights.get(y0.index as usize)?;
                self.emission_slot(light, y0.p, -y0.wi)
            });
        let mut found = 0.0f32;
        let mut radiance = SampledSpectrum::<K>::splat(0.0);
        for t in 1..=sub.camera.len() {
            for s in 0..=sub.light.len().max(1) {
                let depth = s + t - 1;
                if depth < 1 || (max_depth >= 0 && depth > max_depth as usize) {
                    continue;
                }
                if s == 0 && t < 2 {
                    continue;
                }
                if bidirectional.only.is_some_and(|o| o != [s, t]) {
                    continue;
                }
                // s = 1 with t ≥ 2 samples its own light point; otherwise
                // the light subpath must reach s vertices.
                if s > sub.light.len() && !(s == 1 && t >= 2) {
                    continue;
                }
                let Some(Contribution { l, raster }) = self.strategy(&sub, s, t, &mut draw) else {
                    continue;
                };
                if slot.is_some() && s >= 2 {
                    found += l.0.iter().sum::<f32>();
                }
                match raster {
                    None => radiance += l,
                    Some(raster) => {
                        let xyzv = estimate_xyzv(&l, &wl);
                        if xyzv.iter().all(|v| v.is_finite()) {
                            splats.push(Splat {
                                raster,
                                xyzv,
                                radiance: l,
                                wl,
                            });
                        } else {
                            counts.dropped_splats += 1;
                        }
                    }
                }
            }
        }
        if let Some(slot) = slot.filter(|_| found.is_finite()) {
            records.push((slot, found.max(0.0)));
        }
        let xyzv = estimate_xyzv(&radiance, &wl);
        let finite = xyzv.iter().all(|v| v.is_finite()) && radiance.0.iter().all(|v| v.is_finite());
        finite.then_some(CameraSample {
            xyzv,
            radiance,
            wl,
            collapsed: K > 1 && (light_collapsed || camera_collapsed),
            seen: None,
        })
    }
}
