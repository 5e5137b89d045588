//! Radiance pictures (`.hdr`, Ward's RGBE): what Radiance's own tools —
//! evalglare, falsecolor, pvalue — read. Radiance's RGB has its own
//! primaries (x, y: red 0.640, 0.330; green 0.290, 0.600; blue 0.150,
//! 0.060; white 1/3, 1/3, Radiance's `ray/src/common/color.h`) and its
//! own units: W·sr⁻¹·m⁻² of a white of luminous efficacy 179 lm/W, so a
//! pixel's luminance is 179·(0.265R + 0.670G + 0.065B) cd/m². scotopia
//! writes its absolute X, Y, Z in those units, the luminance exact.

use std::path::Path;

use scotopia_color::space::{xy_to_xyz, Mat3};

use crate::{write_atomic, ImageError};

/// Radiance's luminous efficacy of its white, lm/W (`WHTEFFICACY`).
pub const WHITE_EFFICACY: f64 = 179.0;

/// Radiance's RGB primaries and white, CIE 1931 x, y.
pub const PRIMARIES: [[f64; 2]; 4] = [
    [0.640, 0.330],
    [0.290, 0.600],
    [0.150, 0.060],
    [1.0 / 3.0, 1.0 / 3.0],
];

/// XYZ ← Radiance RGB (RGB (1, 1, 1) is the white with Y = 1).
pub fn xyz_from_rgb() -> Mat3 {
    let p = Mat3::from_columns([PRIMARIES[0], PRIMARIES[1], PRIMARIES[2]].map(xy_to_xyz));
    let s = p
        .inverse()
        .expect("Radiance's primaries are independent")
        .apply(xy_to_xyz(PRIMARIES[3]));
    p * Mat3::diagonal(s)
}

/// Radiance RGB of an absolute X, Y, Z (cd/m²): Y/179 in Radiance's
/// luminance. A colour outside Radiance's gamut (a sodium lamp's) has a
/// negative component, which RGBE cannot hold: it is set to 0 and the
/// others scaled so that the luminance stays Y.
fn rgb_of(xyz: [f64; 3], rgb_from_xyz: &Mat3, y_row: [f64; 3]) -> [f64; 3] {
    let rgb = rgb_from_xyz.apply(xyz.map(|v| v / WHITE_EFFICACY));
    if rgb.iter().all(|&c| c >= 0.0) {
        return rgb;
    }
    let clipped = rgb.map(|c| c.max(0.0));
    let y = xyz[1] / WHITE_EFFICACY;
    let y_clipped: f64 = (0..3).map(|i| y_row[i] * clipped[i]).sum();
    if y > 0.0 && y_clipped > 0.0 {
        clipped.map(|c| c * y / y_clipped)
    } else {
        [0.0; 3]
    }
}

/// A decoded RGBE pixel moved to the middle of its mantissa's step, as
/// Radiance reads them ((m + ½)·2^(e − 136), color.c's `colr_color`):
/// the decoder used reads m·2^(e − 136), every value up to a step low
/// (0.2–0.4 % of the luminance; found beside evalglare). The step is that
/// of the largest channel, whose mantissa m lies in 128…255.
fn mantissa_centre(rgb: [f32; 3]) -> [f64; 3] {
    let v = rgb.iter().fold(0.0f32, |a, &c| a.max(c));
    if !(v > 0.0 && v.is_finite()) {
        return rgb.map(f64::from);
    }
    let step = 2f64.powi(f64::from(v).log2().floor() as i32 - 7);
    rgb.map(|c| f64::from(c) + 0.5 * step)
}

/// Ward's shared-exponent encoding of one RGB (non-negative).
fn rgbe([r, g, b]: [f64; 3]) -> [u8; 4] {
    let v = r.max(g).max(b);
    if !v.is_finite() || v <= 1e-32 {
        return [0; 4];
    }
    // v = m·2^e with m in [0.5, 1).
    let e = v.log2().floor() as i32 + 1;
    let scale = 256.0 / 2f64.powi(e);
    let byte = |c: f64| (c * scale).clamp(0.0, 255.0) as u8;
    [byte(r), byte(g), byte(b), (e + 128).clamp(0, 255) as u8]
}

/// Writes `w` × `h` X, Y, Z (cd/m², the fourth value ignored) pixels,
/// row-major, top row first, as a Radiance picture at `path`, atomically:
/// uncompressed scanlines, which every Radiance reader takes. `view` is
/// the picture's Radiance view options (`-vtv -vh 60 -vv 40`), for tools
/// that read angles from it.
pub fn write_radiance_hdr(
    path: &Path,
    w: usize,
    h: usize,
    px: &[[f32; 4]],
    view: Option<&str>,
) -> Result<(), ImageError> {
    let xyz_from_rgb = xyz_from_rgb();
    let rgb_from_xyz = xyz_from_rgb.inverse().expect("invertible");
    let y_row = xyz_from_rgb.0[1];
    let mut out = Vec::with_capacity(256 + 4 * px.len());
    out.extend_from_slice(b"#?RADIANCE\nSOFTWARE=scotopia\nFORMAT=32-bit_rle_rgbe\n");
    let p = PRIMARIES;
    out.extend_from_slice(
        format!(
            "PRIMARIES= {} {} {} {} {} {} {:.4} {:.4}\n",
            p[0][0], p[0][1], p[1][0], p[1][1], p[2][0], p[2][1], p[3][0], p[3][1]
        )
        .as_bytes(),
    );
    if let Some(v) = view {
        out.extend_from_slice(format!("VIEW= {v}\n").as_bytes());
    }
    out.extend_from_slice(format!("\n-Y {h} +X {w}\n").as_bytes());
    for p in px.iter().take(w * h) {
        let xyz = [p[0], p[1], p[2]].map(|v| if v.is_finite() { f64::from(v) } else { 0.0 });
        out.extend_from_slice(&rgbe(rgb_of(xyz, &rgb_from_xyz, y_row)));
    }
    write_atomic(path, &out).map_err(|cause| ImageError::Io {
        path: path.display().to_string(),
        cause,
    })
}

/// A Radiance picture read for its luminance.
#[derive(Debug, Clone, PartialEq)]
pub struct RadiancePicture {
    pub width: usize,
    pub height: usize,
    /// Luminance, cd/m²: 179·(Y of its RGB in Radiance's primaries).
    pub luminance: Vec<f32>,
    /// Its header's view options (the last `VIEW=` line), if any.
    pub view: Option<String>,
}

/// Whether `path` starts as a Radiance picture does (`#?RADIANCE`, or
/// `#?RGBE` of other writers).
pub fn is_radiance(path: &Path) -> bool {
    let mut head = [0u8; 10];
    std::fs::File::open(path)
        .and_then(|mut f| std::io::Read::read_exact(&mut f, &mut head))
        .is_ok_and(|()| head.starts_with(b"#?RADIANCE") || head.starts_with(b"#?RGBE"))
}

/// Reads a Radiance picture (RGBE, RLE or flat) for its luminance and view,
/// through the `image` crate's decoder.
pub fn read_radiance(path: &Path) -> Result<RadiancePicture, ImageError> {
    let img = crate::read_rgb(path)?;
    let bytes = crate::plain_file::open_plain(path)
        .and_then(|f| {
            let mut head = Vec::new();
            std::io::Read::read_to_end(&mut std::io::Read::take(f, 64 * 1024), &mut head)?;
            Ok(head)
        })
        .map_err(|cause| ImageError::Io {
            path: path.display().to_string(),
            cause,
        })?;
    let end = bytes
        .windows(2)
        .position(|w| w == b"\n\n")
        .unwrap_or(bytes.len());
    let header = String::from_utf8_lossy(&bytes[..end]);
    let view = header
        .lines()
        .rev()
        .find_map(|l| l.strip_prefix("VIEW="))
        .map(|v| v.trim().to_string());
    let y = xyz_from_rgb().0[1];
    let luminance = img
        .pixels
        .iter()
        .map(|p| {
            let p = mantissa_centre([p[0], p[1], p[2]]);
            (WHITE_EFFICACY * (0..3).map(|i| y[i] * p[i]).sum::<f64>()) as f32
        })
        .collect();
    Ok(RadiancePicture {
        width: img.width,
        height: img.height,
        luminance,
        view,
    })
}

/// The projection (`angular`) and full horizontal angle (degrees) a
/// Radiance view gives an angular fisheye (`-vta … -vh H`), if it is one.
pub fn angular_view(view: &str) -> Option<(&'static str, f64)> {
    let words: Vec<&str> = view.split_whitespace().collect();
    let kind = words.iter().rev().find(|w| w.starts_with("-vt"))?;
    let h = words
        .windows(2)
        .rev()
        .find(|w| w[0] == "-vh")
        .and_then(|w| w[1].parse::<f64>().ok())?;
    (*kind == "-vta").then_some(("angular", h))
}

#[cfg(test)]
mod tests {

    #[test]
    fn a_decoded_value_is_read_at_the_middle_of_its_step() {
        // 100.3 encodes to a mantissa step of 0.5 (2^(6 − 7)): read as m·step
        // it is up to a step low; centred, within half a step.
        let [m, _, _, e] = super::rgbe([100.3, 50.0, 0.0]);
        let step = 2f64.powi(i32::from(e) - 136);
        let floor = [f64::from(m) * step, 0.0, 0.0];
        let read = super::mantissa_centre(floor.map(|v| v as f32));
        assert!((read[0] - 100.3).abs() <= 0.5 * step, "{read:?}");
        assert_eq!(step, 0.5);
        assert_eq!(super::mantissa_centre([0.0; 3]), [0.0; 3]);
    }

    use super::*;

    #[test]
    fn radiance_luminance_coefficients_follow_from_its_primaries() {
        // Radiance's color.h: luminance = 179·(0.265R + 0.670G + 0.065B).
        let y = xyz_from_rgb().0[1];
        for (got, want) in y.iter().zip([0.265, 0.670, 0.065]) {
            assert!((got - want).abs() < 1e-3, "{y:?}");
        }
    }

    #[test]
    fn a_picture_reads_back_with_its_luminance() {
        // Read by the `image` crate's own RGBE decoder: a grey of 100
        // cd/m², a sodium yellow (outside Radiance's gamut) of 10, black.
        let path =
            std::env::temp_dir().join(format!("scotopia-radiance-{}.hdr", std::process::id()));
        let sodium = [0.575 / 0.424 * 10.0, 10.0, 0.001 / 0.424 * 10.0, 0.0];
        let grey = [95.047, 100.0, 108.883, 0.0];
        let grey_e = [100.0 * 1.0, 100.0, 100.0, 0.0];
        let px = [grey, sodium, [0.0; 4], grey_e];
        write_radiance_hdr(&path, 2, 2, &px, Some("-vtv -vh 60 -vv 40")).unwrap();
        let bytes = std::fs::read(&path).unwrap();
        let text = String::from_utf8_lossy(&bytes[..bytes.len().min(300)]);
        assert!(text.starts_with("#?RADIANCE\n") && text.contains("VIEW= -vtv -vh 60 -vv 40\n"));
        let img = image::ImageReader::open(&path)
            .unwrap()
            .with_guessed_format()
            .unwrap();
        let img = img.decode().unwrap().into_rgb32f();
        let y = xyz_from_rgb().0[1];
        let lum = |x: u32, yy: u32| {
            let p = img.get_pixel(x, yy).0;
            WHITE_EFFICACY * (0..3).map(|i| y[i] * f64::from(p[i])).sum::<f64>()
        };
        // RGBE keeps 8 bits of mantissa, truncated as Radiance writes it (its
        // reader adds half a step back; this one does not): within 2 %, the
        // small components of a saturated colour losing most.
        for ((x, yy), want) in [
            ((0, 0), 100.0),
            ((1, 0), 10.0),
            ((0, 1), 0.0),
            ((1, 1), 100.0),
        ] {
            let l = lum(x, yy);
            assert!(
                (l - want).abs() <= 0.02 * want + 1e-9,
                "({x}, {yy}): {l} against {want}"
            );
        }
        // Equal-energy white is Radiance's white: R = G = B.
        let p = img.get_pixel(1, 1).0;
        assert!(
            (p[0] - p[1]).abs() < 0.01 * p[1] && (p[2] - p[1]).abs() < 0.01 * p[1],
            "{p:?}"
        );
        std::fs::remove_file(&path).ok();
    }
}
