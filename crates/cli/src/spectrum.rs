//! `scotopia spectrum`: the colorimetry of one spectrum.

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::ArgGroup;
use serde_json::json;

use scotopia_color::{
    cie, io, rgb_to_spectrum, Colorimetry, RgbSpace, Spectrum, SpectrumKind, UpsampleMethod,
};
use scotopia_image::{display_colour, plot_spectrum};

#[derive(clap::Args)]
#[command(
    group(ArgGroup::new("source").required(true).args(["illuminant", "blackbody", "daylight", "file", "rgb"])),
    after_help = "Values are read as spectral radiance in W·sr⁻¹·m⁻²·nm⁻¹, so X, Y, Z are in cd/m² \
                  (K_m = 683 lm/W) and V′ in scotopic cd/m² (K′_m = 1700 lm/W). A reflectance gives \
                  its colour under an equal-energy illuminant of 1 W·sr⁻¹·m⁻²·nm⁻¹.\n\n\
                  Examples:\n  scotopia spectrum --illuminant F11\n  scotopia spectrum --blackbody 2700 --json\n  \
                  scotopia spectrum --rgb 0.8,0.2,0.1 --space srgb --plot red.png\n  \
                  scotopia spectrum --file lamp.csv"
)]
pub struct Args {
    /// A CIE illuminant: A, D50, D55, D65, D75, E, F1 … F12.
    #[arg(long, value_name = "NAME")]
    illuminant: Option<String>,
    /// A black body at this temperature, in absolute spectral radiance.
    #[arg(long, value_name = "KELVIN", allow_negative_numbers = true)]
    blackbody: Option<f32>,
    /// CIE daylight (D series) at this correlated colour temperature (4000–25000 K).
    #[arg(long, value_name = "KELVIN", allow_negative_numbers = true)]
    daylight: Option<f64>,
    /// A spectrum file: `wavelength,value` per line (CSV or .spd), wavelengths in nm.
    #[arg(long, value_name = "PATH")]
    file: Option<PathBuf>,
    /// A linear RGB colour, upsampled to a spectrum.
    #[arg(long, value_name = "R,G,B", value_parser = parse_rgb, allow_hyphen_values = true)]
    rgb: Option<[f32; 3]>,
    /// Colour space of --rgb.
    #[arg(long, default_value = "srgb", value_parser = ["srgb", "p3", "rec2020", "acescg"])]
    space: String,
    /// RGB → spectrum method for --rgb.
    #[arg(long, default_value = "jakob2019", value_parser = ["jakob2019", "smits", "primaries"])]
    method: String,
    /// What --rgb describes: a reflectance in [0, 1], an unbounded colour, or an emitter.
    #[arg(long, default_value = "reflectance", value_parser = ["reflectance", "unbounded", "illuminant"])]
    kind: String,
    /// Print JSON instead of text.
    #[arg(long)]
    json: bool,
    /// Also draw the spectrum over 360–830 nm to this PNG.
    #[arg(long, value_name = "FILE.png")]
    plot: Option<PathBuf>,
}

/// Parses `R,G,B`.
fn parse_rgb(s: &str) -> Result<[f32; 3], String> {
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    if parts.len() != 3 {
        return Err(format!(
            "expected three comma-separated numbers R,G,B, got '{s}'"
        ));
    }
    let mut rgb = [0.0f32; 3];
    for (v, p) in rgb.iter_mut().zip(&parts) {
        *v = p.parse().map_err(|_| format!("'{p}' is not a number"))?;
    }
    Ok(rgb)
}

/// Builds the spectrum the arguments name, and a description of it.
fn source(args: &Args) -> Result<(Spectrum, String)> {
    if let Some(name) = &args.illuminant {
        return Ok((
            cie::illuminant(name)?,
            format!("CIE illuminant {}", name.to_uppercase()),
        ));
    }
    if let Some(k) = args.blackbody {
        return Ok((Spectrum::blackbody(k)?, format!("black body at {k} K")));
    }
    if let Some(k) = args.daylight {
        return Ok((cie::daylight(k)?.into(), format!("CIE daylight at {k} K")));
    }
    if let Some(path) = &args.file {
        return Ok((
            io::read_spectrum_file(path)?.into(),
            path.display().to_string(),
        ));
    }
    // clap guarantees that one source is given.
    let rgb = args.rgb.context("no spectrum given")?;
    let space = RgbSpace::from_name(&args.space)?;
    let method = UpsampleMethod::from_name(&args.method)?;
    let kind = SpectrumKind::from_name(&args.kind)?;
    let s = rgb_to_spectrum(rgb, space, method, kind)?;
    Ok((
        s,
        format!(
            "{} RGB {rgb:?} ({}, {})",
            space.name(),
            method.name(),
            kind.name()
        ),
    ))
}

pub fn run(args: Args) -> Result<()> {
    if let (Some(file), Some(plot)) = (&args.file, &args.plot) {
        scotopia_image::check_outputs(&[("the --file spectrum", file)], &[("--plot", plot)])
            .map_err(anyhow::Error::msg)?;
    }
    let text = report(&args)?;
    crate::print(&text)
}

/// The text (or JSON) `scotopia spectrum` prints; writes the plot if asked.
fn report(args: &Args) -> Result<String> {
    use std::fmt::Write;
    let (spectrum, name) = source(args)?;
    let c = Colorimetry::of(&spectrum);
    if let Some(path) = &args.plot {
        let linear = RgbSpace::Srgb.def().xyz_to_rgb(c.xyzv.xyz());
        plot_spectrum(path, &spectrum, display_colour(linear))?;
    }
    if args.json {
        let report = json!({
            "xyz": [c.xyzv.x, c.xyzv.y, c.xyzv.z],
            "xy": c.xy,
            "vprime": c.xyzv.v,
            "sp_ratio": c.sp_ratio,
            "cct": c.cct.map(|t| t.kelvin),
            "duv": c.cct.map(|t| t.duv),
            "wavelengths": c.wavelengths,
            "values": c.values,
        });
        return Ok(format!("{report}\n"));
    }
    let mut out = String::new();
    writeln!(out, "{name}")?;
    writeln!(
        out,
        "  X, Y, Z       {:.6e}, {:.6e}, {:.6e} cd/m²",
        c.xyzv.x, c.xyzv.y, c.xyzv.z
    )?;
    writeln!(out, "  luminance     {:.6e} cd/m²", c.xyzv.y)?;
    writeln!(out, "  scotopic V′   {:.6e} scotopic cd/m²", c.xyzv.v)?;
    match c.sp_ratio {
        Some(r) => writeln!(out, "  S/P ratio     {r:.4}")?,
        None => writeln!(out, "  S/P ratio     — (no luminance)")?,
    }
    match c.xy {
        Some([x, y]) => writeln!(out, "  x, y          {x:.5}, {y:.5}")?,
        None => writeln!(out, "  x, y          — (black)")?,
    }
    match c.cct {
        Some(t) => writeln!(out, "  CCT           {:.1} K (Duv {:+.5})", t.kelvin, t.duv)?,
        None => writeln!(out, "  CCT           — (farther than 0.05 from the Planckian locus, or outside 1000–100000 K)")?,
    }
    if let Some(path) = &args.plot {
        writeln!(out, "  plot          {}", path.display())?;
    }
    Ok(out)
}
