//! Sample warping.

pub mod distribution;
pub mod warp;
