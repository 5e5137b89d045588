//! The XYZV′ image: absolute X, Y, Z (cd/m²) and V′ (scotopic cd/m²) per
//! pixel — the contract between the renderer and the vision pipeline — read
//! from an OpenEXR written by scotopia or by any other renderer.

use std::path::Path;

use scotopia_color::photometry::estimate_scotopic;
use scotopia_color::RgbSpace;

use crate::{read_exr, ImageError};

/// An absolute XYZV′ image with what is known of its viewing geometry.
#[derive(Debug, Clone, PartialEq)]
pub struct XyzvImage {
    pub width: usize,
    pub height: usize,
    /// [X, Y, Z, V′], row-major, top row first.
    pub pixels: Vec<[f32; 4]>,
    /// Horizontal field of view in degrees, from the file's metadata.
    pub fov_horizontal: Option<f64>,
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
    let exr = read_exr(path)?;
    let fail = |message: String| ImageError::Read {
        path: path.display().to_string(),
        message,
    };
    let channel = |name: &str| {
        exr.channels
            .iter()
            .find(|(n, _)| n == name || n.ends_with(&format!(".{name}")))
            .map(|(_, v)| v.as_slice())
    };
    let n = exr.width * exr.height;
    let mut notes = Vec::new();
    let pixels: Vec<[f32; 4]> = match (channel("X"), channel("Y"), channel("Z")) {
        (Some(x), Some(y), Some(z)) => {
            if rgb.units.is_some() {
                notes.push("--units ignored: an XYZ image is already absolute".into());
            }
            match channel("V") {
                // Zipped slices: one pass, no bounds checks, no per-pixel work.
                Some(v) => x
                    .iter()
                    .zip(y)
                    .zip(z)
                    .zip(v)
                    .map(|(((&x, &y), &z), &v)| [x, y, z, v])
                    .collect(),
                None => {
                    notes.push(
                        "no V channel: V′ estimated from X, Y, Z with Pattanaik et al. 1998's \
                         fit (exact for D65, ~13 % low for tungsten)"
                            .into(),
                    );
                    (0..n)
                        .map(|i| {
                            let xyz = [x[i], y[i], z[i]].map(f64::from);
                            [x[i], y[i], z[i], estimate_scotopic(xyz) as f32]
                        })
                        .collect()
                }
            }
        }
        _ => {
            let (Some(r), Some(g), Some(b)) = (channel("R"), channel("G"), channel("B")) else {
                let names: Vec<&str> = exr.channels.iter().map(|(n, _)| n.as_str()).collect();
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
            (0..n)
                .map(|i| {
                    let xyz = space
                        .rgb_to_xyz([r[i], g[i], b[i]].map(f64::from))
                        .map(|v| v * units);
                    let [x, y, z] = xyz.map(|v| v as f32);
                    [x, y, z, estimate_scotopic(xyz) as f32]
                })
                .collect()
        }
    };
    // Non-finite values are kept as they are: the vision pipeline leaves
    // them out of its statistics and says so (reading them as black would
    // count them as black in the adaptation luminance).
    let fov_horizontal = exr
        .metadata
        .iter()
        .find(|(k, _)| k == "fovHorizontalDegrees")
        .and_then(|(_, v)| v.parse::<f64>().ok())
        .filter(|f| f.is_finite() && *f > 0.0);
    Ok(XyzvImage {
        width: exr.width,
        height: exr.height,
        pixels,
        fov_horizontal,
        notes,
    })
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
    fn other_channels_are_an_error_naming_them() {
        let path = tmp("depth.exr");
        write_exr(&path, 1, 1, vec![("depth".into(), vec![1.0])], &[]).unwrap();
        let err = read_xyzv(&path, RgbInput::default())
            .unwrap_err()
            .to_string();
        assert!(err.contains("depth") && err.contains("X, Y, Z"), "{err}");
    }
}
