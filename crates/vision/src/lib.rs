//! The vision pipeline: from an absolute X, Y, Z, V′ image to what a person
//! would see of it on a display. Stages, each its own module: the visual
//! mode (`mode`), glare, multiscale adaptation, the night-vision shift
//! (`night`), tone operators (`tonemap`), gamut mapping (`gamut`).

pub mod gamut;
pub mod glare;
pub mod mode;
pub mod night;
pub mod tonemap;
