//! Named materials: conductors with measured complex indices (`Au`, `Ag`,
//! `Cu`, `Al`, `Cr`) and dielectrics with Sellmeier dispersion (`bk7`,
//! `sf11`, `f2`, `fused silica`, `diamond`, `water`). Where Mitsuba uses a
//! constant for a name, scotopia uses the real spectral curve.

mod conductor;
mod glass;

pub use conductor::{named_conductor, CONDUCTOR_NAMES};
pub use glass::{named_glass, sellmeier_index, GLASS_NAMES};
