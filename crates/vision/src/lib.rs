//! The vision pipeline: from an absolute X, Y, Z, V′ image to what a person
//! would see of it on a display. Stages, each its own module: the visual
//! mode (`mode`), the observer (`observer`), glare, multiscale adaptation
//! (`multiscale`), the night-vision shift (`night`) and scotopic
//! acuity (`acuity`), tone operators (`tonemap`), gamut mapping (`gamut`),
//! code values (`encode`); `pipeline` runs them in order, on pixels
//! screened for non-finite and absurd values (`screen`).

pub mod acuity;
pub mod encode;
pub mod false_colour;
pub mod gamut;
pub mod glare;
pub mod mode;
pub mod multiscale;
pub mod night;
pub mod observer;
pub mod output;
pub mod pipeline;
pub mod ratings;
pub mod resample;
pub mod screen;
pub mod tonemap;
pub mod wide_math;

pub use observer::Observer;
pub use pipeline::{
    display, display_observed, display_owned, DisplayParams, Displayed, Report, Stage, ToneOperator,
};
