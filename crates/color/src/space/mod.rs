//! Colour spaces: linear RGB spaces from primaries, chromatic adaptation,
//! CIELAB and CIEDE2000, Oklab and OkLCh, display transfer functions.

mod adaptation;
mod ciede2000;
mod cielab;
mod matrix;
mod oklab;
mod rgb;
mod transfer;

pub use adaptation::{adaptation_matrix, Cat};
pub use ciede2000::delta_e_2000;
pub use cielab::{lab_to_lch, lab_to_xyz, lch_to_lab, xyy_to_xyz, xyz_to_lab, xyz_to_xyy};
pub use matrix::Mat3;
pub use oklab::{delta_e_ok, oklab_to_oklch, oklab_to_xyz, oklch_to_oklab, xyz_to_oklab};
pub use rgb::{xy_to_xyz, RgbColorSpace, RgbSpace};
pub use transfer::{srgb_decode, srgb_encode};
