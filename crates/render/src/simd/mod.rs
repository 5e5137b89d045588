//! Wide SIMD chosen at run time, through the `pulp` crate: its kernels are
//! safe code, compiled once per instruction set inside a function with
//! those target features enabled, and the unsafety of calling such a
//! function stays inside pulp (the workspace forbids `unsafe`).
//!
//! A [`Level`] names an instruction set; [`Level::current`] is the one the
//! process uses (the best the CPU has, or `SCOTOPIA_SIMD`), and
//! [`Level::run`] runs a [`Kernel`] at a level: its plain scalar code at
//! [`Level::Scalar`], its wide code, generic over [`Wide`], otherwise.
//! Kernels must give the same results at every level where the scalar
//! code is the reference (the tests compare them).

mod lanes8;
mod level;
mod wide;

pub use lanes8::{Lanes8, Scalar8};
pub use level::{Kernel, Level, SimdError, ENV_VAR};
pub use wide::{first_lane, Wide};
