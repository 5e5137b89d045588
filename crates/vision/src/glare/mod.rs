//! Glare (Spencer et al. 1995): the eye's point-spread function applied to
//! the light a display cannot reproduce.

pub mod psf;
