//! The wavefront (batched) path tracer. Each rayon task takes one film row
//! and traces its camera samples a batch at a time: every path in flight
//! is a [`PathState`] in one array, and the tracer runs stages over the
//! whole array — intersect every ray, shade every hit (grouped by
//! material, so one BSDF's code runs over consecutive paths), trace every
//! shadow ray, then retire the finished paths and refill their slots with
//! new camera samples, so the batch stays full as paths die (where a
//! megakernel's lanes would idle).
//!
//! Each stage calls the per-path steps the scalar tracer is made of
//! (`Renderer::start_path`, `bounce`, `escape`, `finish` in `path.rs`),
//! with each path's own sampler, so a path's random numbers depend only on
//! (seed, pixel, sample index, dimension) and its estimate is the scalar
//! tracer's to the bit. The samples of a pixel are added to the film in
//! index order, so the image is the scalar tracer's image, bit for bit, on
//! any number of threads (tested). The stages are where SIMD kernels go,
//! one at a time, each checked against this reference; their boundaries
//! and the batch's layout are what a GPU back end would keep.

mod generate;
mod intersect;
mod lanes;
mod retire;
mod shade;
mod shadow;

use super::path::CameraSample;
use super::Renderer;
use crate::simd::Level;
pub(super) use generate::RowWork;
use lanes::{Scratch, BATCH};

/// The estimates of the row's work items, in item order (`None`: not
/// finite). Adds the rays traced to `rays`.
pub(super) fn trace_row<const K: usize>(
    r: &Renderer,
    work: RowWork,
    rays: &mut u64,
) -> Vec<Option<CameraSample<K>>> {
    let total = work.items();
    let level = Level::current();
    let mut results: Vec<Option<CameraSample<K>>> = (0..total).map(|_| None).collect();
    let mut scratch = Scratch::default();
    let (mut lanes, mut free, mut next) = (Vec::with_capacity(BATCH), Vec::new(), 0);
    *rays += generate::refill::<K>(
        r,
        &work,
        level,
        &mut lanes,
        &mut free,
        &mut next,
        &mut scratch,
    );
    let mut order = Vec::with_capacity(BATCH);
    let mut by_material = shade::MaterialOrder::new(r.scene.materials.len());
    let geometry = &r.scene.geometry;
    while !lanes.is_empty() {
        *rays += intersect::intersect(geometry, &mut lanes);
        *rays += shade::shade(
            r,
            level,
            &mut lanes,
            &mut by_material,
            &mut order,
            &mut scratch,
        );
        *rays += shadow::shadow(geometry, &mut lanes);
        retire::retire(&lanes, &mut free, &mut results);
        *rays += generate::refill(
            r,
            &work,
            level,
            &mut lanes,
            &mut free,
            &mut next,
            &mut scratch,
        );
    }
    results
}
