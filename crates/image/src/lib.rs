//! Images in and out of scotopia: the XYZV′ image read for the vision
//! pipeline, OpenEXR and PNG (8/16-bit, sRGB or PQ) writing (atomic),
//! PNG/JPEG/EXR reading for textures, spectrum plots.

pub mod exr_out;
pub mod fisheye;
pub mod limits;
pub mod output_file;
mod plain_file;
pub mod plot;
pub mod png_out;
pub mod preview;
pub mod radiance;
pub mod read;
pub mod sheet;
mod tmp_file;
pub mod xyzv;

pub use exr_out::{read_exr, write_exr, ExrImage, Meta};
pub use limits::{check_buffer, check_image, TooLarge};
pub use output_file::{check_outputs, write_atomic, write_output, OutputFile, OutputOptions};
pub use plain_file::open_plain;
pub use plot::{display_colour, plot_spectrum};
pub use png_out::{
    encode_png, encode_png_stored, write_png, write_png_rgb8, ImageError, PngColour, PngSamples,
};
pub use preview::preview_srgb8;
pub use read::{read_rgb, Encoding, RgbImage};
pub use sheet::{sheet, Panel};
pub use xyzv::{read_xyzv, RgbInput, XyzvImage};
