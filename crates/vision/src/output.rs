//! Writing the pipeline's result — PNG (sRGB 8-bit dithered or 16-bit, or
//! PQ for HDR), or a linear display-referred EXR — and the `--compare`
//! sheet of its stages.

use std::path::Path;

use scotopia_color::RgbSpace;
use scotopia_image::{
    encode_png, encode_png_stored, sheet, write_exr, ImageError, Meta, Panel, PngColour, PngSamples,
};

use crate::encode::{pq16, srgb16, srgb8};
use crate::pipeline::{display_observed, DisplayParams, Displayed, Stage};

/// How to encode a PNG.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct PngOptions {
    /// 16 bits per sample instead of 8 (ignored for HDR, always 16).
    pub sixteen_bit: bool,
    /// Rec. 2100 PQ at the display's absolute peak (`--hdr`).
    pub hdr: bool,
    /// Samples stored uncompressed (the viewer's responses: compressing
    /// costs more time than the loopback takes to carry the bytes).
    pub stored: bool,
}

impl PngOptions {
    /// From the command line's `--bits` and `--hdr`.
    pub fn new(bits: u8, hdr: bool) -> Result<Self, String> {
        match bits {
            8 | 16 => Ok(Self {
                sixteen_bit: bits == 16,
                hdr,
                stored: false,
            }),
            _ => Err(format!("bits {bits}: use 8 or 16")),
        }
    }
}

/// The display's peak luminance: `given`, or 100 cd/m² (1000 for HDR);
/// it must lie in (0, 10 000] cd/m², PQ's range, and be a normal f32 (the
/// pipeline divides by it in f32: 1e-300 would be 0 there, a black image).
pub fn display_peak(given: Option<f64>, hdr: bool) -> Result<f64, String> {
    let peak = given.unwrap_or(if hdr { 1000.0 } else { 100.0 });
    if peak.is_finite() && peak > 0.0 && peak <= 10_000.0 && (peak as f32).is_normal() {
        Ok(peak)
    } else {
        // 1e-300 as itself, not as 300 digits.
        let shown = if peak != 0.0 && !(1e-4..1e6).contains(&peak.abs()) {
            format!("{peak:e}")
        } else {
            peak.to_string()
        };
        Err(format!(
            "display-peak {shown}: must be in (0, 10000] cd/m² and at least {:e} (single precision)",
            f32::MIN_POSITIVE
        ))
    }
}

/// The display's gamut by name, or sRGB (Rec. 2020 for HDR); ACEScg is a
/// working space, not a display's.
pub fn display_gamut(given: Option<&str>, hdr: bool) -> Result<RgbSpace, String> {
    let space = match given {
        Some(name) => RgbSpace::from_name(name).map_err(|e| e.to_string())?,
        None if hdr => RgbSpace::Rec2020,
        None => RgbSpace::Srgb,
    };
    if space == RgbSpace::AcesCg {
        return Err(format!(
            "gamut {}: not a display gamut; use srgb, p3 or rec2020",
            given.unwrap_or_default()
        ));
    }
    Ok(space)
}

/// Writes `d` to `path` by its extension: `.png` (see [`PngOptions`]) or
/// `.exr` (linear RGB in the target gamut, 1 = the display's peak).
pub fn write_display(
    path: &Path,
    d: &Displayed,
    p: &DisplayParams,
    png: PngOptions,
) -> Result<(), ImageError> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .unwrap_or_default();
    match ext.as_str() {
        "png" => {
            let bytes = display_png(&path.display().to_string(), d, p, png)?;
            scotopia_image::write_atomic(path, &bytes).map_err(|cause| ImageError::Io {
                path: path.display().to_string(),
                cause,
            })
        }
        "exr" => {
            let channel = |c: usize| d.rgb.iter().map(|p| p[c]).collect::<Vec<f32>>();
            let channels = vec![
                ("R".into(), channel(0)),
                ("G".into(), channel(1)),
                ("B".into(), channel(2)),
            ];
            let meta = [
                (
                    "colorSpace",
                    Meta::Text(format!(
                        "linear {} (display-referred, 1.0 = peak)",
                        p.gamut.name()
                    )),
                ),
                ("displayPeakCdM2", Meta::F32(p.display_peak as f32)),
                (
                    "renderer",
                    Meta::Text(format!("scotopia {}", env!("CARGO_PKG_VERSION"))),
                ),
            ];
            write_exr(path, d.width, d.height, channels, &meta)
        }
        _ => Err(ImageError::Invalid(format!(
            "{}: unknown output type {ext:?}: use .png or .exr",
            path.display()
        ))),
    }
}

/// The PNG file's bytes for `d` (see [`PngOptions`]); `name` is what
/// errors call it.
pub fn display_png(
    name: &str,
    d: &Displayed,
    p: &DisplayParams,
    png: PngOptions,
) -> Result<Vec<u8>, ImageError> {
    let (w, h) = (d.width as u32, d.height as u32);
    let encode_png = if png.stored {
        encode_png_stored
    } else {
        encode_png
    };
    if png.hdr {
        if p.gamut != RgbSpace::Rec2020 {
            return Err(ImageError::Invalid(format!(
                "{name}: HDR (PQ) output is Rec. 2100, whose primaries are Rec. 2020: use --gamut rec2020"
            )));
        }
        let codes = pq16(&d.rgb, p.display_peak);
        return encode_png(name, w, h, PngSamples::Rgb16(&codes), PngColour::REC2100_PQ);
    }
    let colour = match p.gamut {
        RgbSpace::Srgb => PngColour::SRGB,
        RgbSpace::DisplayP3 => PngColour::DISPLAY_P3,
        RgbSpace::Rec2020 => PngColour::REC2020_SRGB,
        RgbSpace::AcesCg => {
            return Err(ImageError::Invalid(format!(
                "{name}: ACEScg is not a display gamut: use srgb, p3 or rec2020"
            )))
        }
    };
    if png.sixteen_bit {
        encode_png(name, w, h, PngSamples::Rgb16(&srgb16(&d.rgb)), colour)
    } else {
        encode_png(name, w, h, PngSamples::Rgb8(&srgb8(&d.rgb)), colour)
    }
}

/// Runs the pipeline and lays its stages side by side with labels, each
/// panel at most `panel_height` rows; returns the result and the sheet
/// (width, height, 8-bit sRGB).
pub fn compare_sheet(
    pixels: &[[f32; 4]],
    width: usize,
    height: usize,
    p: &DisplayParams,
    panel_height: usize,
) -> (Displayed, (usize, usize, Vec<u8>)) {
    let mut stages: Vec<(Stage, Vec<u8>)> = Vec::new();
    let srgb = RgbSpace::Srgb.def();
    let d = display_observed(pixels, width, height, p, &mut |stage, xyz| {
        // A plain clip into sRGB: the sheet shows each stage as it is.
        let rgb: Vec<[f32; 3]> = xyz
            .iter()
            .map(|q| {
                srgb.xyz_to_rgb(q.map(f64::from))
                    .map(|v| v.clamp(0.0, 1.0) as f32)
            })
            .collect();
        stages.push((stage, srgb8(&rgb)));
    });
    let panels: Vec<Panel> = stages
        .iter()
        .map(|(stage, rgb)| Panel {
            label: stage.label(),
            width,
            height,
            rgb,
        })
        .collect();
    let s = sheet(&panels, panel_height);
    (d, s)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unknown_types_and_hdr_outside_rec2020_are_errors() {
        let d = Displayed {
            width: 1,
            height: 1,
            rgb: vec![[0.5; 3]],
            report: crate::pipeline::display(&[[1.0; 4]], 1, 1, &DisplayParams::default()).report,
        };
        let p = DisplayParams::default();
        let dir = std::env::temp_dir();
        let err = write_display(&dir.join("x.tiff"), &d, &p, PngOptions::default()).unwrap_err();
        assert!(err.to_string().contains(".png or .exr"));
        let hdr = PngOptions {
            hdr: true,
            ..Default::default()
        };
        let err = write_display(&dir.join("x.png"), &d, &p, hdr).unwrap_err();
        assert!(err.to_string().contains("rec2020"));
    }

    #[test]
    fn the_sheet_has_a_panel_per_stage() {
        let px = vec![[9.5f32, 10.0, 10.9, 24.6]; 32 * 16];
        let (_, (w, h, rgb)) = compare_sheet(&px, 32, 16, &DisplayParams::default(), 16);
        assert_eq!(rgb.len(), w * h * 3);
        assert!(w > 5 * 32, "five panels side by side: {w}");
    }

    #[test]
    fn luminances_that_are_0_or_infinite_in_f32_are_refused() {
        use crate::mode::Adaptation;
        assert!(display_peak(Some(1e-300), false).is_err());
        assert!(display_peak(Some(1e-40), false).is_err());
        assert_eq!(display_peak(Some(1e-30), false), Ok(1e-30));
        for bad in ["1e39", "1e11", "1e-300", "1e-40", "0", "-1", "inf", "nan"] {
            assert_eq!(Adaptation::parse(bad), None, "{bad}");
        }
        assert_eq!(Adaptation::parse("1e10"), Some(Adaptation::Fixed(1e10)));
        assert_eq!(Adaptation::parse("0.001"), Some(Adaptation::Fixed(0.001)));
    }
}
