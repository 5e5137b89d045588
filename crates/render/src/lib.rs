//! scotopia-render: geometry, acceleration, cameras, BSDFs, lights,
//! wavelength sampling, integrators and the film. So far: the math, the
//! shapes, the BVH, the camera, the BSDFs and the lights.

pub mod accel;
pub mod bsdf;
pub mod camera;
pub mod film;
pub mod geometry;
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
