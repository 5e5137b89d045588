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

mod batch;

pub(super) use batch::trace_row;
