//! PNG output, written atomically: to a temporary file beside the target,
//! then renamed, so a failed run never leaves a half-written image.

use std::fs::File;
use std::io::BufWriter;
use std::path::{Path, PathBuf};

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
}

/// A temporary file beside `path`, renamed over it when complete.
pub(crate) fn tmp_path(path: &Path) -> PathBuf {
    let mut name = path
        .file_name()
        .map(|n| n.to_os_string())
        .unwrap_or_default();
    name.push(format!(".tmp{}", std::process::id()));
    path.with_file_name(name)
}

/// Writes 8-bit sRGB pixels (row-major RGB triples) as a PNG with an sRGB chunk.
pub fn write_png_rgb8(path: &Path, width: u32, height: u32, rgb: &[u8]) -> Result<(), ImageError> {
    write_png(path, width, height, PngSamples::Rgb8(rgb), PngColour::Srgb)
}

/// RGB samples for a PNG, row-major triples.
#[derive(Debug, Clone, Copy)]
pub enum PngSamples<'a> {
    Rgb8(&'a [u8]),
    Rgb16(&'a [u16]),
}

/// What the code values mean, written into the file so viewers know.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PngColour {
    /// IEC 61966-2-1 sRGB: an sRGB chunk.
    Srgb,
    /// Rec. 2100 PQ with Rec. 2020 primaries: a cICP chunk (primaries 9,
    /// transfer 16, matrix 0, full range; ITU-T H.273).
    Rec2100Pq,
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
        if colour == PngColour::Srgb {
            encoder.set_source_srgb(png::SrgbRenderingIntent::Perceptual);
        }
        let mut writer = encoder.write_header().map_err(png_err)?;
        if colour == PngColour::Rec2100Pq {
            writer
                .write_chunk(png::chunk::cICP, &[9, 16, 0, 1])
                .map_err(png_err)?;
        }
        writer.write_image_data(&bytes).map_err(png_err)?;
        writer.finish().map_err(png_err)?;
        std::fs::rename(&tmp, path).map_err(io)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}
