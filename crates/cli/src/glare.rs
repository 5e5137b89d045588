//! `scotopia glare`: glare ratings from a fisheye luminance picture, as
//! Radiance's evalglare computes them (docs/lighting.md).

use std::path::PathBuf;

use anyhow::{bail, Context, Result};
use serde_json::json;

use scotopia_image::{radiance, read_xyzv, write_png_rgb8, RgbInput};
use scotopia_vision::ratings::{evaluate, neighbours, Figures, Fisheye, Projection, FISHEYE_VIEW};
use scotopia_vision::Observer;

#[derive(clap::Args)]
pub struct Args {
    /// A fisheye picture of luminance: an X, Y, Z (V′) OpenEXR, Y in
    /// cd/m², or a Radiance picture (luminance 179·Y of its RGB).
    image: PathBuf,
    /// Its projection (default: the image's `projection` metadata):
    /// angular (equidistant, Radiance's -vta) or equisolid.
    #[arg(long, value_name = "angular|equisolid")]
    projection: Option<String>,
    /// Its full angle across the width, degrees (default: the image's
    /// fovHorizontalDegrees metadata).
    #[arg(long, value_name = "DEG")]
    fov: Option<f64>,
    /// Glare sources are the pixels above this many times the picture's
    /// mean luminance (evalglare's default, 5), merged where they touch;
    /// above 100, a luminance in cd/m² (as evalglare's -b).
    #[arg(long, default_value_t = 5.0, value_name = "K")]
    threshold: f64,
    /// The observer's age, years, for CIE 146's veiling luminance.
    #[arg(long, default_value_t = Observer::DEFAULT_AGE, value_parser = crate::numbers::age)]
    age: f64,
    /// Print one JSON object (Ev_lx, UGR, DGP, Lveil_cdm2, sources, …)
    /// instead of text.
    #[arg(long)]
    json: bool,
    /// Also write the picture (grey, log luminance) with the sources
    /// outlined in red.
    #[arg(short, long, value_name = "OUT.png")]
    output: Option<PathBuf>,
}

/// The figures of the picture at `args.image`, with its geometry.
pub fn figures(
    image: &std::path::Path,
    projection: Option<&str>,
    fov: Option<f64>,
    threshold: f64,
    age: f64,
) -> Result<(Figures, Fisheye, Vec<f32>)> {
    let name = image.display();
    let picture = read_picture(image)?;
    let projection = match projection.or(picture.projection.as_deref()) {
        Some(p) => Projection::from_name(p)
            .with_context(|| format!("projection '{p}': use angular or equisolid"))?,
        None => bail!("{name} does not say its projection: give --projection angular|equisolid"),
    };
    let fov = match fov.or(picture.fov) {
        Some(f) if f.is_finite() && f > 0.0 && f <= 360.0 => f,
        Some(f) => bail!("--fov {f}: give the full angle across the width, 0 to 360 degrees"),
        None => bail!("{name} does not say its field of view: give --fov DEG"),
    };
    if !(threshold.is_finite() && threshold > 1.0) {
        bail!("--threshold {threshold}: give a factor above 1");
    }
    let eye = Fisheye {
        projection,
        fov,
        width: picture.width,
        height: picture.height,
    };
    let lum = picture.luminance;
    let observer = Observer::new(age, Observer::DEFAULT_PIGMENTATION)?;
    Ok((evaluate(&lum, &eye, threshold, &observer), eye, lum))
}

/// A picture's luminance and what its file says of its geometry.
struct Picture {
    width: usize,
    height: usize,
    luminance: Vec<f32>,
    projection: Option<String>,
    fov: Option<f64>,
}

/// Reads an X, Y, Z OpenEXR, or a Radiance picture (whose `-vta` view
/// gives an angular fisheye's projection and angle).
fn read_picture(image: &std::path::Path) -> Result<Picture> {
    let name = image.display();
    if radiance::is_radiance(image) {
        let p = radiance::read_radiance(image)
            .with_context(|| format!("{name}: cannot read the picture"))?;
        let view = p.view.as_deref().and_then(radiance::angular_view);
        return Ok(Picture {
            width: p.width,
            height: p.height,
            luminance: p.luminance,
            projection: view.map(|v| v.0.to_string()),
            fov: view.map(|v| v.1),
        });
    }
    let img = read_xyzv(image, RgbInput::default())
        .with_context(|| format!("{name}: cannot read the picture"))?;
    if let Some(q) = img.quantity.as_deref().filter(|&q| q != "radiance") {
        bail!("{name} holds {q}, not luminance");
    }
    Ok(Picture {
        width: img.width,
        height: img.height,
        luminance: img.pixels.iter().map(|p| p[1]).collect(),
        projection: img.projection,
        fov: img.fov_horizontal,
    })
}

/// The figures as one JSON object.
pub fn to_json(f: &Figures, eye: &Fisheye) -> serde_json::Value {
    let sources: Vec<_> = f
        .sources
        .iter()
        .map(|s| {
            json!({
                "luminance_cdm2": s.source.luminance,
                "solid_angle_sr": s.source.solid_angle,
                "direction": s.source.dir,
                "sigma_deg": FISHEYE_VIEW.sigma(s.source.dir),
                "position_index": s.position_index,
                "pixels": s.pixels.len(),
            })
        })
        .collect();
    json!({
        "projection": eye.projection.name(),
        "fov_deg": eye.fov,
        "Ev_lx": f.ev_lx,
        "UGR": f.ugr,
        "DGP": f.dgp,
        "Lveil_cdm2": f.veil_cdm2,
        "average_cdm2": f.average_cdm2,
        "threshold_cdm2": f.threshold_cdm2,
        "background_cdm2": f.background_cdm2,
        "sources": sources,
    })
}

pub fn run(args: Args) -> Result<()> {
    let (f, eye, lum) = figures(
        &args.image,
        args.projection.as_deref(),
        args.fov,
        args.threshold,
        args.age,
    )?;
    if let Some(out) = &args.output {
        write_outlined(out, &lum, &f, &eye)?;
    }
    if args.json {
        println!("{}", to_json(&f, &eye));
        return Ok(());
    }
    println!("vertical illuminance at the lens  E_v = {:.1} lx", f.ev_lx);
    println!(
        "mean luminance {:.2} cd/m²; sources above {:.2} cd/m²: {}",
        f.average_cdm2,
        f.threshold_cdm2,
        f.sources.len()
    );
    for (i, s) in f.sources.iter().enumerate() {
        println!(
            "  source {}: L = {:.1} cd/m², ω = {:.5} sr, {:.1}° from the line of sight, P = {:.2}",
            i + 1,
            s.source.luminance,
            s.source.solid_angle,
            FISHEYE_VIEW.sigma(s.source.dir),
            s.position_index
        );
    }
    let ugr = f.ugr.map_or("— (no source or no background)".into(), |u| {
        format!("{u:.1}")
    });
    println!(
        "UGR (CIE 117) = {ugr}, background {:.2} cd/m²",
        f.background_cdm2
    );
    println!("DGP (Wienold & Christoffersen 2006) = {:.3}", f.dgp);
    println!(
        "veiling luminance (CIE 146, {} years) = {:.3} cd/m²",
        args.age, f.veil_cdm2
    );
    Ok(())
}

/// Writes the picture with its sources outlined (`outlined`) as a PNG.
pub fn write_outlined(
    out: &std::path::Path,
    lum: &[f32],
    f: &Figures,
    eye: &Fisheye,
) -> Result<()> {
    let rgb = outlined(lum, f, eye.width, eye.height);
    write_png_rgb8(out, eye.width as u32, eye.height as u32, &rgb)?;
    Ok(())
}

/// The picture in grey (log luminance over four decades below its
/// brightest) with the sources' edge pixels red.
fn outlined(lum: &[f32], f: &Figures, w: usize, h: usize) -> Vec<u8> {
    let top = lum
        .iter()
        .copied()
        .filter(|v| v.is_finite())
        .fold(0.0f32, f32::max);
    let mut source = vec![false; w * h];
    for s in &f.sources {
        for &i in &s.pixels {
            source[i] = true;
        }
    }
    let mut rgb = Vec::with_capacity(3 * w * h);
    for i in 0..w * h {
        let edge = source[i]
            && neighbours(i, w, h)
                .into_iter()
                .any(|j| j.is_none_or(|j| !source[j]));
        if edge {
            rgb.extend_from_slice(&[255, 0, 0]);
            continue;
        }
        let v = if top > 0.0 && lum[i] > 0.0 {
            ((lum[i] / top).log10() / 4.0 + 1.0).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let g = (v * 255.0) as u8;
        rgb.extend_from_slice(&[g, g, g]);
    }
    rgb
}
