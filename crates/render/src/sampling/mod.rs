//! Sample warping.

pub mod distribution;
pub mod sobol;
pub mod sobol_batch;
pub mod sobol_pair;
pub mod splitmix;
pub mod warp;
