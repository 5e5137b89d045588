//! Reading RGB images (PNG, JPEG, OpenEXR) for textures and environment
//! maps, through the `image` crate.

use std::path::Path;

use scotopia_color::space::srgb_decode;

use crate::ImageError;

/// How the stored values relate to light.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Encoding {
    /// Integer formats (PNG, JPEG): sRGB-encoded.
    Srgb,
    /// Floating-point formats (OpenEXR): linear.
    Linear,
}

/// An RGB image of f32 values in [0, 1] (integer formats) or any range
/// (float formats), row-major, top row first.
#[derive(Debug, Clone, PartialEq)]
pub struct RgbImage {
    pub width: usize,
    pub height: usize,
    pub pixels: Vec<[f32; 3]>,
    pub encoding: Encoding,
}

impl RgbImage {
    /// The pixels with the sRGB transfer function undone (a no-op for
    /// linear images).
    pub fn into_linear(mut self) -> Self {
        if self.encoding == Encoding::Srgb {
            for p in &mut self.pixels {
                *p = p.map(|v| srgb_decode(v as f64) as f32);
            }
            self.encoding = Encoding::Linear;
        }
        self
    }
}

/// Reads `path`, dropping alpha; grey images become RGB.
pub fn read_rgb(path: &Path) -> Result<RgbImage, ImageError> {
    let fail = |message: String| ImageError::Read {
        path: path.display().to_string(),
        message,
    };
    let open = || {
        image::ImageReader::open(path)
            .map_err(|cause| ImageError::Io {
                path: path.display().to_string(),
                cause,
            })?
            .with_guessed_format()
            .map_err(|e| fail(e.to_string()))
    };
    // The size the header declares, checked before decoding: the decoded
    // image, its float copy and the pixels returned.
    let (w, h) = open()?.into_dimensions().map_err(|e| fail(e.to_string()))?;
    crate::limits::check_image("the image", w as u64, h as u64, 40).map_err(|cause| {
        ImageError::TooLarge {
            path: path.display().to_string(),
            cause: Box::new(cause),
        }
    })?;
    let reader = open()?;
    let img = reader.decode().map_err(|e| fail(e.to_string()))?;
    let float = matches!(
        img.color(),
        image::ColorType::Rgb32F | image::ColorType::Rgba32F
    );
    let (width, height) = (img.width() as usize, img.height() as usize);
    if width == 0 || height == 0 {
        return Err(fail("the image is empty".into()));
    }
    let rgb = img.into_rgb32f();
    let pixels = rgb.pixels().map(|p| p.0).collect();
    Ok(RgbImage {
        width,
        height,
        pixels,
        encoding: if float {
            Encoding::Linear
        } else {
            Encoding::Srgb
        },
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tmp(name: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("scotopia-read-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        dir.join(name)
    }

    #[test]
    fn png_round_trip_and_srgb_decoding() {
        let path = tmp("a.png");
        // 2×1: white, mid grey (sRGB 188 ≈ linear 0.5).
        crate::write_png_rgb8(&path, 2, 1, &[255, 255, 255, 188, 188, 188]).unwrap();
        let img = read_rgb(&path).unwrap();
        assert_eq!(
            (img.width, img.height, img.encoding),
            (2, 1, Encoding::Srgb)
        );
        let lin = img.into_linear();
        assert_eq!(lin.pixels[0], [1.0; 3]);
        assert!(
            (lin.pixels[1][0] - 0.5029).abs() < 1e-3,
            "{:?}",
            lin.pixels[1]
        );
    }

    #[test]
    fn radiance_hdr_images_read_as_linear() {
        // Mitsuba scenes' environment maps are often Radiance .hdr files.
        let path = tmp("sky.hdr");
        let pixels = [
            image::Rgb([2.5f32, 0.5, 0.125]),
            image::Rgb([0.0, 1.0, 8.0]),
        ];
        let file = std::io::BufWriter::new(std::fs::File::create(&path).unwrap());
        image::codecs::hdr::HdrEncoder::new(file)
            .encode(&pixels, 2, 1)
            .unwrap();
        let img = read_rgb(&path).unwrap();
        assert_eq!(
            (img.width, img.height, img.encoding),
            (2, 1, Encoding::Linear)
        );
        // RGBE keeps 8 bits of mantissa per channel.
        for (got, want) in img.pixels.iter().zip(pixels) {
            for c in 0..3 {
                assert!(
                    (got[c] - want.0[c]).abs() <= 0.01 * want.0[c].max(0.1),
                    "{got:?}"
                );
            }
        }
    }

    #[test]
    fn a_png_declaring_a_huge_size_is_an_error_before_decoding() {
        let path = tmp("huge.png");
        {
            let file = std::fs::File::create(&path).unwrap();
            let mut enc = png::Encoder::new(file, 100_000, 100_000);
            enc.set_color(png::ColorType::Rgb);
            // The header and one short data chunk: the size is what is
            // checked, before any data is decoded.
            let mut w = enc.write_header().unwrap();
            w.write_chunk(png::chunk::IDAT, &[0x78, 0x9c, 0x03, 0, 0, 0, 0, 1])
                .unwrap();
        }
        let e = read_rgb(&path).unwrap_err().to_string();
        assert!(e.contains("huge.png"), "{e}");
        assert!(e.contains("100000 × 100000 pixels"), "{e}");
        assert!(e.contains("the limit is"), "{e}");
    }

    #[test]
    fn bad_files_are_errors_naming_the_file() {
        let path = tmp("broken.png");
        std::fs::write(&path, b"\x89PNG\r\n\x1a\nnot really").unwrap();
        let e = read_rgb(&path).unwrap_err().to_string();
        assert!(e.contains("broken.png"), "{e}");
        let e = read_rgb(&tmp("missing.exr")).unwrap_err().to_string();
        assert!(e.contains("missing.exr"), "{e}");
    }
}
