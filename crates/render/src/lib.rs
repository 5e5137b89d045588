//! scotopia-render: geometry, acceleration, cameras, BSDFs, lights,
//! wavelength sampling, integrators and the film. So far: the math, the
//! shapes and the BVH.

pub mod accel;
pub mod geometry;
pub mod math;
