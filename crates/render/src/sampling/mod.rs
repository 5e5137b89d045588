//! Sample warping.

pub mod warp;
