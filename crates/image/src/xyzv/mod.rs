//! The XYZV′ image: absolute X, Y, Z (cd/m²) and V′ (scotopic cd/m²) per
//! pixel — the contract between the renderer and the vision pipeline — read
//! from an OpenEXR written by scotopia or by any other renderer; scotopia's
//! own layout through a faster reader (`exr_fast`).

mod exr_fast;

use std::path::Path;

use scotopia_color::photometry::estimate_scotopic;
use scotopia_color::RgbSpace;

use exr::prelude::*;
use rayon::prelude::*;
use std::result::Result;

use crate::exr_out::read_exr_headers;
use crate::ImageError;

/// An absolute XYZV′ image with what is known of its viewing geometry.
#[derive(Debug, Clone, PartialEq)]
pub struct XyzvImage {
    pub width: usize,
    pub height: usize,
    /// [X, Y, Z, V′], row-major, top row first.
    pub pixels: Vec<[f32; 4]>,
    /// Horizontal field of view in degrees, from the file's metadata.
    pub fov_horizontal: Option<f64>,
    /// What the pixels hold, from the file's `quantity` metadata
    /// (`radiance`, `illuminance` or `melanopic-edi`, as `scotopia render`
    /// writes it; with `melanopic-edi` the fourth value of a pixel is its
    /// channel mEDI, the melanopic EDI in lx, not V′).
    pub quantity: Option<String>,
    /// The picture's projection, from the file's `projection` metadata
    /// (`angular` or `equisolid` for a fisheye), if it says.
    pub projection: Option<String>,
    /// What was assumed to read the file (estimated V′, RGB conversion),
    /// for the user to be told.
    pub notes: Vec<String>,
}

/// How to read an RGB EXR, which carries no absolute scale.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RgbInput {
    /// cd/m² of luminance per unit of Y (`--units`).
    pub units: Option<f64>,
    /// The RGB primaries of the file (linear sRGB or ACEScg).
    pub space: RgbSpace,
}

impl Default for RgbInput {
    fn default() -> Self {
        Self {
            units: None,
            space: RgbSpace::Srgb,
        }
    }
}

/// Reads `path`: channels X, Y, Z and optionally V (V′; estimated from X,
/// Y, Z when missing), or R, G, B converted with `rgb`.
pub fn read_xyzv(path: &Path, rgb: RgbInput) -> Result<XyzvImage, ImageError> {
    let fail = |message: String| ImageError::Read {
        path: path.display().to_string(),
        message,
    };
    // The channels are chosen from the first layer's header; only they are
    // then read, straight into [X, Y, Z, V′] pixels.
    let meta = read_exr_headers(path)?;
    let header = meta
        .headers
        .first()
        .ok_or_else(|| fail("no layers".into()))?;
    if let Some(c) = header
        .channels
        .list
        .iter()
        .find(|c| c.sampling != Vec2(1, 1))
    {
        return Err(fail(format!(
            "channel {} is subsampled ({}×{}): only full-resolution channels can be read",
            c.name, c.sampling.0, c.sampling.1
        )));
    }
    let channel = |name: &str| {
        let suffix = format!(".{name}");
        header
            .channels
            .list
            .iter()
            .find(|c| c.name == *name || c.name.to_string().ends_with(&suffix))
            .map(|c| c.name.clone())
    };
    let quantity = match header.own_attributes.other.get(&Text::from("quantity")) {
        Some(AttributeValue::Text(t)) => Some(t.to_string()),
        _ => None,
    };
    let mut notes = Vec::new();
    // `render --quantity melanopic-edi` writes the melanopic EDI where V′
    // would be, named so that nothing takes it for V′.
    let fourth = match quantity.as_deref() {
        Some("melanopic-edi") => channel("mEDI"),
        _ => channel("V"),
    };
    let pixels = match (channel("X"), channel("Y"), channel("Z")) {
        (Some(x), Some(y), Some(z)) => {
            if rgb.units.is_some() {
                notes.push("--units ignored: an XYZ image is already absolute".into());
            }
            match fourth {
                Some(v) => {
                    let index = |n: &Text| header.channels.list.iter().position(|c| c.name == *n);
                    let fast = match [&x, &y, &z, &v].map(index) {
                        [Some(a), Some(b), Some(c), Some(d)] => {
                            exr_fast::read_own_layout(path, &meta, [a, b, c, d])
                        }
                        _ => None,
                    };
                    match fast {
                        Some(pixels) => pixels,
                        None => read_four(path, [x, y, z, v])?,
                    }
                }
                None => {
                    notes.push(
                        "no V channel: V′ estimated from X, Y, Z with Pattanaik et al. 1998's \
                         fit (exact for D65, ~13 % low for tungsten)"
                            .into(),
                    );
                    let mut pixels = read_three(path, [x, y, z])?;
                    for p in &mut pixels {
                        p[3] = estimate_scotopic([p[0], p[1], p[2]].map(f64::from)) as f32;
                    }
                    pixels
                }
            }
        }
        _ => {
            let (Some(r), Some(g), Some(b)) = (channel("R"), channel("G"), channel("B")) else {
                let names: Vec<String> = header
                    .channels
                    .list
                    .iter()
                    .map(|c| c.name.to_string())
                    .collect();
                return Err(fail(format!(
                    "needs channels X, Y, Z (and V) or R, G, B; it has {}",
                    names.join(", ")
                )));
            };
            let Some(units) = rgb.units else {
                return Err(fail(
                    "an RGB image has no absolute scale: give --units (cd/m² per unit of luminance)"
                        .into(),
                ));
            };
            if !(units.is_finite() && units > 0.0) {
                return Err(fail(format!(
                    "--units must be positive and finite, not {units}"
                )));
            }
            notes.push(format!(
                "RGB read as linear {} × {units} cd/m²; V′ estimated from X, Y, Z",
                rgb.space.name()
            ));
            let space = rgb.space.def();
            let mut pixels = read_three(path, [r, g, b])?;
            for p in &mut pixels {
                let xyz = space
                    .rgb_to_xyz([p[0], p[1], p[2]].map(f64::from))
                    .map(|v| v * units);
                let [x, y, z] = xyz.map(|v| v as f32);
                *p = [x, y, z, estimate_scotopic(xyz) as f32];
            }
            pixels
        }
    };
    // Non-finite values are kept as they are: the vision pipeline leaves
    // them out of its statistics and says so (reading them as black would
    // count them as black in the adaptation luminance).
    let fov_horizontal = header
        .own_attributes
        .other
        .get(&Text::from("fovHorizontalDegrees"))
        .and_then(|v| match v {
            // As its shortest decimal (60.000004, not 60.0000038…), the
            // value metadata readers print and scotopia always read.
            AttributeValue::F32(f) => f.to_string().parse().ok(),
            AttributeValue::F64(f) => Some(*f),
            AttributeValue::I32(i) => Some(f64::from(*i)),
            AttributeValue::Text(t) => t.to_string().trim().parse().ok(),
            _ => None,
        })
        .filter(|f| f.is_finite() && *f > 0.0);
    let projection = match header.own_attributes.other.get(&Text::from("projection")) {
        Some(AttributeValue::Text(t)) => Some(t.to_string()),
        _ => None,
    };
    Ok(XyzvImage {
        projection,
        width: header.layer_size.width(),
        height: header.layer_size.height(),
        pixels,
        fov_horizontal,
        quantity,
        notes,
    })
}

/// The pixels of the first layer that has the four channels `names`
/// (f16 and u32 samples converted), row-major.
fn read_four(path: &Path, names: [Text; 4]) -> Result<Vec<[f32; 4]>, ImageError> {
    let [a, b, c, d] = names;
    let image = read()
        .no_deep_data()
        .largest_resolution_level()
        .specific_channels()
        .required(a)
        .required(b)
        .required(c)
        .required(d)
        .collect_pixels(new_pixels, |px: &mut Pixels, at, (a, b, c, d)| {
            px.set(at, [a, b, c, d])
        })
        .first_valid_layer()
        .all_attributes()
        .from_file(path)
        .map_err(|e| exr_error(path, e))?;
    Ok(image.layer_data.channel_data.pixels.values)
}

/// As [`read_four`] for three channels, the fourth value left 0.
fn read_three(path: &Path, names: [Text; 3]) -> Result<Vec<[f32; 4]>, ImageError> {
    let [a, b, c] = names;
    let image = read()
        .no_deep_data()
        .largest_resolution_level()
        .specific_channels()
        .required(a)
        .required(b)
        .required(c)
        .collect_pixels(new_pixels, |px: &mut Pixels, at, (a, b, c)| {
            px.set(at, [a, b, c, 0.0])
        })
        .first_valid_layer()
        .all_attributes()
        .from_file(path)
        .map_err(|e| exr_error(path, e))?;
    Ok(image.layer_data.channel_data.pixels.values)
}

/// Pixels being read: the layer's width and its values, row-major.
struct Pixels {
    width: usize,
    values: Vec<[f32; 4]>,
}

impl Pixels {
    /// Stores a pixel; a position outside the layer (which the decoder
    /// never gives) is dropped rather than a panic.
    fn set(&mut self, at: Vec2<usize>, value: [f32; 4]) {
        if let Some(p) = self.values.get_mut(at.y() * self.width + at.x()) {
            *p = value;
        }
    }
}

fn new_pixels<T>(size: Vec2<usize>, _: &T) -> Pixels {
    // Written here, in parallel, rather than left to the decoder's first
    // touch: it fills the pixels on one thread, and each fresh 4 KiB page
    // costs a fault (a full-HD image: 8,100 of them, ~15 ms on one core).
    let mut values = Vec::with_capacity(size.area());
    values.par_extend(rayon::iter::repeat_n([0.0f32; 4], size.area()));
    Pixels {
        width: size.width(),
        values,
    }
}

fn exr_error(path: &Path, e: exr::error::Error) -> ImageError {
    ImageError::Exr {
        path: path.display().to_string(),
        message: e.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{write_exr, Meta};

    fn tmp(name: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("scotopia-xyzv-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        dir.join(name)
    }

    #[test]
    fn xyz_without_v_is_estimated_and_said() {
        let path = tmp("xyz.exr");
        // D65 at 10 cd/m²: V′ ≈ 24.6 scotopic cd/m².
        let c = |v: f32| (String::new(), vec![v; 4]);
        let chans = vec![
            ("X".into(), c(9.505).1),
            ("Y".into(), c(10.0).1),
            ("Z".into(), c(10.89).1),
        ];
        write_exr(
            &path,
            2,
            2,
            chans,
            &[("fovHorizontalDegrees", Meta::F32(40.0))],
        )
        .unwrap();
        let img = read_xyzv(&path, RgbInput::default()).unwrap();
        assert!(
            (img.pixels[0][3] / 24.645 - 1.0).abs() < 0.01,
            "{:?}",
            img.pixels[0]
        );
        assert_eq!(img.fov_horizontal, Some(40.0));
        assert!(img.notes[0].contains("estimated"));
    }

    #[test]
    fn rgb_needs_units_and_is_converted() {
        let path = tmp("rgb.exr");
        let chans = ["R", "G", "B"]
            .map(|n| (n.to_string(), vec![1.0f32; 4]))
            .to_vec();
        write_exr(&path, 2, 2, chans, &[]).unwrap();
        let err = read_xyzv(&path, RgbInput::default())
            .unwrap_err()
            .to_string();
        assert!(err.contains("--units") && err.contains("rgb.exr"), "{err}");
        let img = read_xyzv(
            &path,
            RgbInput {
                units: Some(50.0),
                space: RgbSpace::Srgb,
            },
        )
        .unwrap();
        // sRGB white (1, 1, 1) is D65 with Y = 1: 50 cd/m².
        assert!((img.pixels[0][1] - 50.0).abs() < 1e-3);
        assert!(img.fov_horizontal.is_none());
    }

    #[test]
    fn prefixed_channels_are_read_bit_for_bit_into_their_slots() {
        let path = tmp("prefixed.exr");
        let (w, h) = (5, 3);
        let values = |c: u32| -> Vec<f32> {
            (0..(w * h) as u32)
                .map(|i| f32::from_bits((i + 1).wrapping_mul(0x9E37_79B9) ^ (c << 24)))
                .collect()
        };
        let names = ["beauty.X", "beauty.Y", "beauty.Z", "beauty.V", "depth"];
        let chans: Vec<(String, Vec<f32>)> = names
            .iter()
            .zip(1..)
            .map(|(n, c)| (n.to_string(), values(c)))
            .collect();
        write_exr(
            &path,
            w,
            h,
            chans.clone(),
            &[("fovHorizontalDegrees", Meta::I32(50))],
        )
        .unwrap();
        let img = read_xyzv(&path, RgbInput::default()).unwrap();
        assert_eq!(
            (img.width, img.height, img.fov_horizontal),
            (w, h, Some(50.0))
        );
        for (slot, (_, want)) in chans.iter().take(4).enumerate() {
            let got: Vec<u32> = img.pixels.iter().map(|p| p[slot].to_bits()).collect();
            let want: Vec<u32> = want.iter().map(|v| v.to_bits()).collect();
            assert_eq!(got, want, "slot {slot}");
        }
    }

    #[test]
    fn half_float_channels_are_widened() {
        use exr::prelude::f16;
        let path = tmp("half.exr");
        let half = |v: f32| f16::from_f32(v);
        let chan = |name: &str, v: f32| AnyChannel::new(name, FlatSamples::F16(vec![half(v); 6]));
        let channels = AnyChannels::sort(SmallVec::from_vec(vec![
            chan("X", 0.5),
            chan("Y", 1.0),
            chan("Z", 2.0),
            chan("V", 3.0),
        ]));
        let layer = Layer::new(
            (3, 2),
            LayerAttributes::default(),
            Encoding::UNCOMPRESSED,
            channels,
        );
        Image::from_layer(layer).write().to_file(&path).unwrap();
        let img = read_xyzv(&path, RgbInput::default()).unwrap();
        assert!(
            img.pixels.iter().all(|p| *p == [0.5, 1.0, 2.0, 3.0]),
            "{:?}",
            img.pixels
        );
    }

    #[test]
    fn a_subsampled_channel_is_an_error_naming_it() {
        let path = tmp("subsampled.exr");
        let c = |n: &str| (n.to_string(), vec![1.0f32; 8]);
        write_exr(&path, 4, 2, vec![c("X"), c("Y"), c("Z")], &[]).unwrap();
        // Rewrite Z's x and y sampling in the channel list to 2 (name, then
        // pixel type i32, pLinear u8, 3 reserved bytes, xSampling, ySampling).
        let mut bytes = std::fs::read(&path).unwrap();
        let key = b"channels\0chlist\0";
        let list = bytes.windows(key.len()).position(|w| w == key).unwrap();
        let z = list + bytes[list..].windows(2).position(|w| w == b"Z\0").unwrap();
        for at in [z + 10, z + 14] {
            bytes[at..at + 4].copy_from_slice(&2i32.to_le_bytes());
        }
        std::fs::write(&path, bytes).unwrap();
        let err = read_xyzv(&path, RgbInput::default())
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("channel Z is subsampled") && err.contains("subsampled.exr"),
            "{err}"
        );
    }

    #[test]
    fn other_channels_are_an_error_naming_them() {
        let path = tmp("depth.exr");
        write_exr(&path, 1, 1, vec![("depth".into(), vec![1.0])], &[]).unwrap();
        let err = read_xyzv(&path, RgbInput::default())
            .unwrap_err()
            .to_string();
        assert!(err.contains("depth") && err.contains("X, Y, Z"), "{err}");
    }
}
