//! Images in and out of scotopia: PNG writing (atomic), PNG/JPEG/EXR
//! reading for textures, spectrum plots. The
//! XYZV′ image type and OpenEXR I/O arrive with the renderer.

pub mod exr_out;
pub mod plot;
pub mod png_out;
pub mod preview;
pub mod read;

pub use exr_out::{read_exr, write_exr, ExrImage, Meta};
pub use plot::{display_colour, plot_spectrum};
pub use png_out::{write_png_rgb8, ImageError};
pub use preview::preview_srgb8;
pub use read::{read_rgb, Encoding, RgbImage};
