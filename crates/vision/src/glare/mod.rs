//! Glare: the eye's point-spread function (CIE 146:2002's disability
//! glare with the observer's age and pigmentation, Spencer et al. 1995's
//! lenticular halo) applied, in absolute units, to the light the display
//! will not reproduce.

mod apply;
mod fft2;
mod kernel;
pub mod psf;

pub use apply::{apply_glare, GlareParams, GlareReport, Reproduced};
