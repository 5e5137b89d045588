//! Sample warping.

pub mod distribution;
pub mod sobol;
pub mod warp;
