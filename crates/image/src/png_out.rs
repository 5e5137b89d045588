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
    if rgb.len() != (width * height * 3) as usize {
        return Err(ImageError::Invalid(format!(
            "{}: {} bytes for a {width}×{height} RGB image",
            path.display(),
            rgb.len()
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
        encoder.set_depth(png::BitDepth::Eight);
        encoder.set_source_srgb(png::SrgbRenderingIntent::Perceptual);
        let mut writer = encoder.write_header().map_err(png_err)?;
        writer.write_image_data(rgb).map_err(png_err)?;
        writer.finish().map_err(png_err)?;
        std::fs::rename(&tmp, path).map_err(io)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}
