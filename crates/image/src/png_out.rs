//! PNG output, written atomically: to a temporary file beside the target,
//! then renamed, so a failed run never leaves a half-written image.

use std::fs::File;
use std::io::BufWriter;
use std::path::Path;

use crate::tmp_file::tmp_path;

/// Errors reading or writing images.
#[derive(Debug, thiserror::Error)]
pub enum ImageError {
    /// (The I/O error is part of the message, not a separate cause, so
    /// reports do not print it twice.)
    #[error("{path}: {cause}")]
    Io { path: String, cause: std::io::Error },
    #[error("{path}: PNG encoding failed: {message}")]
    Png { path: String, message: String },
    #[error("{path}: OpenEXR: {message}")]
    Exr { path: String, message: String },
    #[error("{path}: cannot read the image: {message}")]
    Read { path: String, message: String },
    #[error("{0}")]
    Invalid(String),
    #[error("{path}: {cause}")]
    TooLarge {
        path: String,
        cause: Box<crate::limits::TooLarge>,
    },
}

/// Writes 8-bit sRGB pixels (row-major RGB triples) as a PNG with an sRGB chunk.
pub fn write_png_rgb8(path: &Path, width: u32, height: u32, rgb: &[u8]) -> Result<(), ImageError> {
    write_png(path, width, height, PngSamples::Rgb8(rgb), PngColour::SRGB)
}

/// RGB samples for a PNG, row-major triples.
#[derive(Debug, Clone, Copy)]
pub enum PngSamples<'a> {
    Rgb8(&'a [u8]),
    Rgb16(&'a [u16]),
}

/// What the code values mean, as ITU-T H.273 code points written in a
/// cICP chunk (PNG 3rd edition), so viewers know; sRGB also gets its sRGB
/// chunk for older readers.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PngColour {
    /// ColourPrimaries: 1 BT.709/sRGB, 9 BT.2020, 12 P3-D65.
    pub primaries: u8,
    /// TransferCharacteristics: 13 sRGB, 16 PQ (SMPTE ST 2084).
    pub transfer: u8,
}

impl PngColour {
    pub const SRGB: Self = Self {
        primaries: 1,
        transfer: 13,
    };
    pub const DISPLAY_P3: Self = Self {
        primaries: 12,
        transfer: 13,
    };
    pub const REC2020_SRGB: Self = Self {
        primaries: 9,
        transfer: 13,
    };
    pub const REC2100_PQ: Self = Self {
        primaries: 9,
        transfer: 16,
    };
}

/// Writes an RGB PNG of 8 or 16 bits with its colour-space chunk, atomically.
pub fn write_png(
    path: &Path,
    width: u32,
    height: u32,
    samples: PngSamples,
    colour: PngColour,
) -> Result<(), ImageError> {
    let count = match samples {
        PngSamples::Rgb8(v) => v.len(),
        PngSamples::Rgb16(v) => v.len(),
    };
    if count != (width as usize) * (height as usize) * 3 {
        return Err(ImageError::Invalid(format!(
            "{}: {count} samples for a {width}×{height} RGB image",
            path.display()
        )));
    }
    let name = path.display().to_string();
    let io = |cause| ImageError::Io {
        path: name.clone(),
        cause,
    };
    let png_err = |e: png::EncodingError| ImageError::Png {
        path: name.clone(),
        message: e.to_string(),
    };
    let tmp = tmp_path(path);
    let result = (|| {
        let file = File::create(&tmp).map_err(io)?;
        let mut encoder = png::Encoder::new(BufWriter::new(file), width, height);
        encoder.set_color(png::ColorType::Rgb);
        let bytes: std::borrow::Cow<[u8]> = match samples {
            PngSamples::Rgb8(v) => {
                encoder.set_depth(png::BitDepth::Eight);
                v.into()
            }
            PngSamples::Rgb16(v) => {
                encoder.set_depth(png::BitDepth::Sixteen);
                // PNG stores 16-bit samples big-endian.
                v.iter()
                    .flat_map(|s| s.to_be_bytes())
                    .collect::<Vec<u8>>()
                    .into()
            }
        };
        if colour == PngColour::SRGB {
            encoder.set_source_srgb(png::SrgbRenderingIntent::Perceptual);
        }
        let mut writer = encoder.write_header().map_err(png_err)?;
        // Matrix 0 (RGB), full range.
        writer
            .write_chunk(png::chunk::cICP, &[colour.primaries, colour.transfer, 0, 1])
            .map_err(png_err)?;
        writer.write_image_data(&bytes).map_err(png_err)?;
        writer.finish().map_err(png_err)?;
        std::fs::rename(&tmp, path).map_err(io)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}
