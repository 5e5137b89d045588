//! PNG output, written atomically: to a temporary file beside the target,
//! then renamed, so a failed run never leaves a half-written image.

use std::path::Path;

use crate::output_file::{write_output, OutputOptions};

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
    let name = path.display().to_string();
    check_count(&name, width, height, samples)?;
    let io = |cause| ImageError::Io {
        path: name.clone(),
        cause,
    };
    let mut encoded = Ok(());
    write_output(path, OutputOptions::OUTPUT, |out| {
        encode_to(out, width, height, samples, colour, true).map_err(|e| match e {
            png::EncodingError::IoError(e) => e,
            e => {
                // Not the file's fault: said as the encoder's error.
                encoded = Err(e.to_string());
                std::io::Error::other("not encoded")
            }
        })
    })
    .map_err(|cause| match encoded {
        Err(message) => ImageError::Png {
            path: name.clone(),
            message,
        },
        Ok(()) => io(cause),
    })
}

/// The bytes of the PNG file [`write_png`] would write (for a server's
/// response); `name` is what errors call the image.
pub fn encode_png(
    name: &str,
    width: u32,
    height: u32,
    samples: PngSamples,
    colour: PngColour,
) -> Result<Vec<u8>, ImageError> {
    encode_png_with(name, width, height, samples, colour, true)
}

/// [`encode_png`] with the samples stored uncompressed: for a response
/// over the loopback, where compressing a full-HD image (~20 ms on one
/// core) costs more than sending the bytes.
pub fn encode_png_stored(
    name: &str,
    width: u32,
    height: u32,
    samples: PngSamples,
    colour: PngColour,
) -> Result<Vec<u8>, ImageError> {
    encode_png_with(name, width, height, samples, colour, false)
}

fn encode_png_with(
    name: &str,
    width: u32,
    height: u32,
    samples: PngSamples,
    colour: PngColour,
    compress: bool,
) -> Result<Vec<u8>, ImageError> {
    check_count(name, width, height, samples)?;
    let mut bytes = Vec::new();
    encode_to(&mut bytes, width, height, samples, colour, compress).map_err(|e| {
        ImageError::Png {
            path: name.into(),
            message: e.to_string(),
        }
    })?;
    Ok(bytes)
}

fn check_count(name: &str, width: u32, height: u32, samples: PngSamples) -> Result<(), ImageError> {
    let count = match samples {
        PngSamples::Rgb8(v) => v.len(),
        PngSamples::Rgb16(v) => v.len(),
    };
    if count != (width as usize) * (height as usize) * 3 {
        return Err(ImageError::Invalid(format!(
            "{name}: {count} samples for a {width}×{height} RGB image"
        )));
    }
    Ok(())
}

fn encode_to<W: std::io::Write>(
    out: W,
    width: u32,
    height: u32,
    samples: PngSamples,
    colour: PngColour,
    compress: bool,
) -> Result<(), png::EncodingError> {
    let (bytes, depth): (std::borrow::Cow<[u8]>, _) = match samples {
        PngSamples::Rgb8(v) => (v.into(), png::BitDepth::Eight),
        PngSamples::Rgb16(v) => {
            // PNG stores 16-bit samples big-endian.
            let mut bytes = vec![0u8; 2 * v.len()];
            for (b, s) in bytes.chunks_exact_mut(2).zip(v) {
                b.copy_from_slice(&s.to_be_bytes());
            }
            (bytes.into(), png::BitDepth::Sixteen)
        }
    };
    let compression = if compress && worth_compressing(width, height, depth, &bytes) {
        // fdeflate with an adaptive row filter: on a dithered
        // 1920×1080 night image ~25× faster than the default (zlib
        // level 6) for files ~1.2× larger (1.07× at 16 bits); README,
        // benchmarks.
        png::Compression::Fast
    } else {
        png::Compression::NoCompression
    };
    let mut encoder = png::Encoder::new(out, width, height);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(depth);
    encoder.set_compression(compression);
    if colour == PngColour::SRGB {
        encoder.set_source_srgb(png::SrgbRenderingIntent::Perceptual);
    }
    let mut writer = encoder.write_header()?;
    // Matrix 0 (RGB), full range.
    writer.write_chunk(png::chunk::cICP, &[colour.primaries, colour.transfer, 0, 1])?;
    writer.write_image_data(&bytes)?;
    writer.finish()
}

/// Whether fdeflate makes the image's rows (`bytes`) clearly smaller than
/// storing them, judged on a few bands of rows. The `png` crate falls back to
/// stored blocks when fast compression comes out larger, which it does on
/// 8-bit dithered night images (their lowest bits are noise): a full-HD
/// image was then compressed in vain, ~50 ms on one core, for the same
/// file. Bands through the image (an eighth of it at most) are encoded
/// both ways and compared; the picture is the same either way.
fn worth_compressing(width: u32, height: u32, depth: png::BitDepth, bytes: &[u8]) -> bool {
    const BANDS: usize = 4;
    const BAND_ROWS: usize = 16;
    let h = height as usize;
    let row = bytes.len() / h.max(1);
    if h < 8 * BAND_ROWS {
        return true;
    }
    let encoded_size = |rows: &[u8], compression| -> usize {
        let mut out = Vec::new();
        let mut encoder = png::Encoder::new(&mut out, width, (rows.len() / row) as u32);
        encoder.set_color(png::ColorType::Rgb);
        encoder.set_depth(depth);
        encoder.set_compression(compression);
        let written = encoder
            .write_header()
            .and_then(|mut w| w.write_image_data(rows));
        // An error here only ends the estimate: compress as before.
        if written.is_err() {
            return 0;
        }
        out.len()
    };
    let (mut fast, mut stored) = (0, 0);
    for b in 0..BANDS {
        let y = (2 * b + 1) * h / (2 * BANDS) - BAND_ROWS / 2;
        let rows = &bytes[y * row..(y + BAND_ROWS) * row];
        fast += encoded_size(rows, png::Compression::Fast);
        stored += encoded_size(rows, png::Compression::NoCompression);
    }
    // A tenth smaller at least: a file a few per cent larger is not worth
    // 50 ms, and the bands' estimate errs (night street: 0.96 on them,
    // over 1 on the whole image).
    10 * fast < 9 * stored
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Decodes `path` with the `png` crate: (width, height, bit depth, bytes).
    fn decode(path: &Path) -> (u32, u32, png::BitDepth, Vec<u8>) {
        let decoder =
            png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()));
        let mut reader = decoder.read_info().unwrap();
        let mut buf = vec![0; reader.output_buffer_size().unwrap()];
        let info = reader.next_frame(&mut buf).unwrap();
        buf.truncate(info.buffer_size());
        (info.width, info.height, info.bit_depth, buf)
    }

    #[test]
    fn pngs_decode_to_exactly_the_samples_written() {
        let dir = std::env::temp_dir().join(format!("scotopia-png-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        // Odd sizes; smooth gradients, flat runs and hashed noise, so every
        // row filter and both literal and match paths of the compressor
        // are exercised.
        let (w, h) = (97u32, 61u32);
        let sample = |i: u32| -> u32 {
            let (x, y) = (i / 3 % w, i / 3 / w);
            match y % 3 {
                0 => x * 2 + y,
                1 => 200,
                _ => i.wrapping_mul(0x9E37_79B9).rotate_left(7),
            }
        };
        let n = w * h * 3;
        let rgb8: Vec<u8> = (0..n).map(|i| sample(i) as u8).collect();
        let path = dir.join("eight.png");
        write_png(&path, w, h, PngSamples::Rgb8(&rgb8), PngColour::SRGB).unwrap();
        assert_eq!(decode(&path), (w, h, png::BitDepth::Eight, rgb8));

        let rgb16: Vec<u16> = (0..n).map(|i| sample(i).wrapping_mul(131) as u16).collect();
        let path = dir.join("sixteen.png");
        write_png(
            &path,
            w,
            h,
            PngSamples::Rgb16(&rgb16),
            PngColour::REC2100_PQ,
        )
        .unwrap();
        let (dw, dh, depth, bytes) = decode(&path);
        let back: Vec<u16> = bytes
            .chunks_exact(2)
            .map(|b| u16::from_be_bytes([b[0], b[1]]))
            .collect();
        assert_eq!((dw, dh, depth, back), (w, h, png::BitDepth::Sixteen, rgb16));
        // Only the two images are left: no temporary file behind.
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 2);
    }

    #[test]
    fn noise_is_stored_and_smooth_images_are_compressed() {
        let (w, h) = (64u32, 160u32);
        let n = (w * h * 3) as u64;
        let noise: Vec<u8> = (0..n)
            .map(|i| (i.wrapping_mul(0x9E37_79B9_7F4A_7C15) >> 56) as u8)
            .collect();
        assert!(!worth_compressing(w, h, png::BitDepth::Eight, &noise));
        let ramp: Vec<u8> = (0..n).map(|i| (i / 3 % w as u64) as u8).collect();
        assert!(worth_compressing(w, h, png::BitDepth::Eight, &ramp));
        // Both decode to the samples written.
        let dir = std::env::temp_dir().join(format!("scotopia-png-n-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        for (name, rgb) in [("noise.png", noise), ("ramp.png", ramp)] {
            let path = dir.join(name);
            write_png(&path, w, h, PngSamples::Rgb8(&rgb), PngColour::SRGB).unwrap();
            assert_eq!(decode(&path), (w, h, png::BitDepth::Eight, rgb));
        }
    }
}
