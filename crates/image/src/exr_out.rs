//! OpenEXR output: named 32-bit float channels with header attributes,
//! written atomically (a temporary file renamed over the target).

use std::path::Path;

use exr::prelude::*;
use std::result::Result;

use crate::output_file::{write_output, OutputOptions};
use crate::ImageError;

/// A header attribute's value.
#[derive(Debug, Clone, PartialEq)]
pub enum Meta {
    Text(String),
    F32(f32),
    I32(i32),
}

/// Writes `channels` (name, row-major values, top row first) of a
/// `width` × `height` image with `metadata` in the header.
pub fn write_exr(
    path: &Path,
    width: usize,
    height: usize,
    channels: Vec<(String, Vec<f32>)>,
    metadata: &[(&str, Meta)],
) -> Result<(), ImageError> {
    let fail = |message: String| ImageError::Exr {
        path: path.display().to_string(),
        message,
    };
    if let Some((name, _)) = channels.iter().find(|(_, v)| v.len() != width * height) {
        return Err(fail(format!(
            "channel {name} does not have {width}×{height} values"
        )));
    }
    let list: SmallVec<[AnyChannel<FlatSamples>; 4]> = channels
        .into_iter()
        .map(|(name, values)| AnyChannel::new(name.as_str(), FlatSamples::F32(values)))
        .collect();
    let mut attributes = LayerAttributes::default();
    for (key, value) in metadata {
        let v = match value {
            Meta::Text(t) => AttributeValue::Text(Text::new_or_panic(sanitise(t))),
            Meta::F32(f) => AttributeValue::F32(*f),
            Meta::I32(i) => AttributeValue::I32(*i),
        };
        attributes
            .other
            .insert(Text::new_or_panic(sanitise(key)), v);
    }
    // RLE, one scanline per block: rendered float noise leaves deflate
    // (ZIP) little to find (files 0–6 % smaller than RLE's on the bundled
    // scenes) while decoding it doubled `display`'s read of a 1920×1080
    // image (+15 ms) and encoding it took ~10× RLE's time; RLE still packs
    // black and constant runs, decodes at copy speed, and every OpenEXR
    // reader has it (README, benchmarks).
    let encoding = Encoding {
        compression: Compression::RLE,
        blocks: Blocks::ScanLines,
        line_order: LineOrder::Increasing,
    };
    let layer = Layer::new(
        (width, height),
        attributes,
        encoding,
        AnyChannels::sort(list),
    );
    let image = Image::from_layer(layer);
    let io = |e: exr::error::Error| match e {
        exr::error::Error::Io(e) => e,
        other => std::io::Error::other(other.to_string()),
    };
    write_output(path, OutputOptions::OUTPUT, |out| {
        if out.seekable() {
            image.write().to_unbuffered(out).map_err(io)
        } else {
            // The encoder seeks back to its offset table: a FIFO cannot.
            let mut memory = std::io::Cursor::new(Vec::new());
            image.write().to_unbuffered(&mut memory).map_err(io)?;
            std::io::Write::write_all(out, memory.get_ref())
        }
    })
    .map_err(|cause| ImageError::Io {
        path: path.display().to_string(),
        cause,
    })
}

/// EXR text is 8-bit: characters outside Latin-1 become '?'.
fn sanitise(s: &str) -> String {
    s.chars()
        .map(|c| if (c as u32) < 256 { c } else { '?' })
        .collect()
}

/// An OpenEXR image read back: channels by name, header attributes as text.
#[derive(Debug, Clone, PartialEq)]
pub struct ExrImage {
    pub width: usize,
    pub height: usize,
    pub channels: Vec<(String, Vec<f32>)>,
    pub metadata: Vec<(String, String)>,
}

/// Reads every channel of the first layer as f32, with the header's
/// other attributes as text (for tests and tools).
pub fn read_exr(path: &Path) -> Result<ExrImage, ImageError> {
    let fail = |message: String| ImageError::Exr {
        path: path.display().to_string(),
        message,
    };
    read_exr_headers(path)?;
    // Only the first layer's blocks are decompressed (on the crate's rayon
    // pool, one block per task); f32 channels are moved out, not copied.
    let layer = read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .first_valid_layer()
        .all_attributes()
        .from_file(path)
        .map_err(|e| fail(e.to_string()))?
        .layer_data;
    let (w, h) = (layer.size.width(), layer.size.height());
    let meta = layer
        .attributes
        .other
        .iter()
        .map(|(k, v)| {
            let v = match v {
                AttributeValue::Text(t) => t.to_string(),
                AttributeValue::F32(f) => f.to_string(),
                AttributeValue::I32(i) => i.to_string(),
                other => format!("{other:?}"),
            };
            (k.to_string(), v)
        })
        .collect();
    let channels = layer
        .channel_data
        .list
        .into_iter()
        .map(|c| {
            let values = match c.sample_data {
                FlatSamples::F32(v) => v,
                other => other.values_as_f32().collect(),
            };
            (c.name.to_string(), values)
        })
        .collect();
    Ok(ExrImage {
        width: w,
        height: h,
        channels,
        metadata: meta,
    })
}

/// Reads an EXR's headers and checks the sizes they declare (data windows
/// × channels) before any pixel is read, so a forged window is an error,
/// not an abort.
pub(crate) fn read_exr_headers(path: &Path) -> Result<exr::meta::MetaData, ImageError> {
    let meta = exr::meta::MetaData::read_from_file(path, false).map_err(|e| ImageError::Exr {
        path: path.display().to_string(),
        message: e.to_string(),
    })?;
    let too_large = |cause| ImageError::TooLarge {
        path: path.display().to_string(),
        cause: Box::new(cause),
    };
    let mut total: Option<u64> = Some(0);
    for h in &meta.headers {
        let (w, ht) = (h.layer_size.width() as u64, h.layer_size.height() as u64);
        let channels = h.channels.list.len() as u64;
        // Each sample is stored (up to 4 bytes) and converted to an f32.
        crate::limits::check_image("its data window", w, ht, 8 * channels.max(1))
            .map_err(too_large)?;
        total = total.and_then(|t| t.checked_add(w * ht * channels));
    }
    crate::limits::check_buffer("its layers together", total, 8).map_err(too_large)?;
    Ok(meta)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_forged_data_window_is_an_error_naming_the_limit() {
        let dir = std::env::temp_dir().join(format!("scotopia-exr-forged-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("forged.exr");
        write_exr(&path, 2, 2, vec![("Y".into(), vec![1.0; 4])], &[]).unwrap();
        // Rewrite the data window's maximum corner to 1e9 - 1 on both axes.
        let mut bytes = std::fs::read(&path).unwrap();
        let key = b"dataWindow\0box2i\0";
        let at = bytes.windows(key.len()).position(|w| w == key).unwrap() + key.len() + 4;
        for k in [8, 12] {
            bytes[at + k..at + k + 4].copy_from_slice(&999_999_999i32.to_le_bytes());
        }
        std::fs::write(&path, bytes).unwrap();
        let e = read_exr(&path).unwrap_err().to_string();
        assert!(e.contains("forged.exr"), "{e}");
        assert!(e.contains("1000000000 × 1000000000 pixels"), "{e}");
        assert!(e.contains("the limit is"), "{e}");
    }

    #[test]
    fn every_bit_pattern_survives_a_write_and_read() {
        let dir = std::env::temp_dir().join(format!("scotopia-exr-bits-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("bits.exr");
        // 37 × 23 (odd sizes) of hashed bit patterns — NaNs with payloads,
        // infinities, subnormals, −0 — with runs of zeros and of one value
        // for RLE to pack.
        let (w, h) = (37, 23);
        let bits = |c: u32| -> Vec<f32> {
            let mut v: Vec<f32> = (0..(w * h) as u32)
                .map(|i| match i % 7 {
                    0 | 1 => 0.0,
                    2 => 1.5,
                    _ => f32::from_bits((i ^ c).wrapping_mul(0x9E37_79B9).rotate_left(c)),
                })
                .collect();
            let special = [
                f32::from_bits(0x7fc0_1234),
                -0.0,
                f32::NEG_INFINITY,
                f32::from_bits(1),
            ];
            v[..4].copy_from_slice(&special);
            v
        };
        let channels: Vec<(String, Vec<f32>)> = ["X", "Y", "Z", "V"]
            .iter()
            .zip(1..)
            .map(|(n, c)| (n.to_string(), bits(c)))
            .collect();
        write_exr(&path, w, h, channels.clone(), &[]).unwrap();
        let back = read_exr(&path).unwrap();
        assert_eq!((back.width, back.height), (w, h));
        for (name, values) in &channels {
            let read = &back.channels.iter().find(|c| &c.0 == name).unwrap().1;
            let as_bits = |v: &[f32]| v.iter().map(|f| f.to_bits()).collect::<Vec<u32>>();
            assert_eq!(as_bits(read), as_bits(values), "channel {name}");
        }
    }

    #[test]
    fn channels_and_metadata_round_trip() {
        let dir = std::env::temp_dir().join(format!("scotopia-exr-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("t.exr");
        let chan = |s: f32| (0..6).map(|i| i as f32 * s).collect::<Vec<f32>>();
        write_exr(
            &path,
            3,
            2,
            vec![
                ("X".into(), chan(1.0)),
                ("Y".into(), chan(2.0)),
                ("V".into(), chan(0.5)),
            ],
            &[
                ("spp", Meta::I32(16)),
                ("fovX", Meta::F32(40.0)),
                ("scene", Meta::Text("a.xml".into())),
            ],
        )
        .unwrap();
        let ExrImage {
            width: w,
            height: h,
            channels,
            metadata: meta,
        } = read_exr(&path).unwrap();
        assert_eq!((w, h), (3, 2));
        let y = channels.iter().find(|c| c.0 == "Y").unwrap();
        assert_eq!(y.1, chan(2.0));
        assert!(meta.contains(&("spp".into(), "16".into())));
        assert!(meta.contains(&("scene".into(), "a.xml".into())));
        // No temporary file is left behind.
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 1);
        assert!(write_exr(&path, 3, 2, vec![("X".into(), vec![0.0; 5])], &[]).is_err());
    }
}
