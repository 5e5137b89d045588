//! scotopia-render: the spectral renderer. A [`scene::Scene`] (which
//! `scotopia-scene` builds from a file) is rendered by an integrator onto
//! the [`film::Film`]: per pixel, absolute X, Y, Z (cd/m²) and V′
//! (scotopic cd/m²) from paths that carry clusters of wavelengths; `output`
//! writes it as an OpenEXR.
//!
//! The modules, from the bottom layer up: each imports only from modules
//! listed before it, and no two import each other, directly or round a
//! loop (`cli/tests/layers.rs` checks the loops):
//!
//! - `math` (vectors, rays, transforms, bounding boxes) and `simd` (wide
//!   kernels chosen at run time);
//! - `sampling`: the Owen-scrambled Sobol sampler, warps, tabulated
//!   distributions and densities over wavelength;
//! - `geometry` (shapes, their hits and surfaces, texture lookup points)
//!   and `film` (pixel sums, the reconstruction filter, checkpoints);
//! - `texture`, `accel` (the BVH, the aggregate of all shapes, instances),
//!   `camera` (cameras, the irradiance meter) and `medium` (participating
//!   media);
//! - `bsdf` (surfaces, fluorescent ones among them) and `light` (emitters,
//!   luminaires among them);
//! - `guiding`: the light field learned while rendering, that bounces
//!   draw their directions from;
//! - `wavelength`: the strategies that choose a path's wavelengths (SWC,
//!   hero, single);
//! - `scene`: what a scene holds, ready to render;
//! - `integrator`: the path, volume path and bidirectional path tracers,
//!   the wavefront tracer, the receivers that measure illuminance, their
//!   options and the pass driver (checkpoints, shards, time limits);
//! - `output`: the EXR and its metadata.

pub mod accel;
pub mod bsdf;
pub mod camera;
pub mod film;
pub mod geometry;
pub mod guiding;
pub mod integrator;
pub mod light;
pub mod math;
pub mod medium;
pub mod output;
pub mod sampling;
pub mod scene;
pub mod simd;
#[cfg(test)]
mod test_rng;
pub mod texture;
pub mod wavelength;
