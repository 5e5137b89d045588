//! scotopia-render: geometry, acceleration, cameras, BSDFs, lights,
//! wavelength sampling, integrators and the film. So far: the math, the
//! shapes, the BVH and the camera.

pub mod accel;
pub mod camera;
pub mod geometry;
pub mod math;
pub mod sampling;
