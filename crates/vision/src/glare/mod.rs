//! Glare (Spencer et al. 1995): the eye's point-spread function applied to
//! the light a display cannot reproduce.

mod apply;
mod fft2;
mod kernel;
pub mod psf;

pub use apply::{apply_glare, GlareParams};
