//! `scotopia display --false-colour`: a map of luminance, CIE 191 mesopic
//! luminance or illuminance with a labelled scale bar, for reading levels
//! off a picture.

use anyhow::{bail, Context, Result};

use scotopia_image::{write_png_rgb8, XyzvImage};
use scotopia_vision::false_colour::{false_colour, Scale};
use scotopia_vision::mode::mesopic_luminance;

use crate::display::Args;

pub fn run(args: &Args, quantity: &str, image: &XyzvImage) -> Result<()> {
    let Some(out) = &args.output else {
        bail!("--false-colour: give -o OUT.png");
    };
    let made = image.quantity.as_deref().unwrap_or("radiance");
    let needs = |q: &str| {
        if q == "illuminance" {
            "illuminance"
        } else {
            "radiance"
        }
    };
    let unit = match (quantity, made) {
        ("luminance" | "mesopic", "radiance") => "cd/m2",
        ("illuminance", "illuminance") => "lx",
        ("luminance" | "mesopic" | "illuminance", _) => bail!(
            "--false-colour {quantity}: {} holds {made} (render --quantity {} makes it)",
            args.input.display(),
            needs(quantity)
        ),
        _ => bail!("--false-colour {quantity}: use luminance, mesopic or illuminance"),
    };
    let y: Vec<f32> = if quantity == "mesopic" {
        // Each pixel as an eye adapted to it sees it (CIE 191:2010).
        image
            .pixels
            .iter()
            .map(|p| {
                let sp = if p[1] > 0.0 { p[3] / p[1] } else { 0.0 };
                mesopic_luminance(p[1] as f64, sp as f64) as f32
            })
            .collect()
    } else {
        image.pixels.iter().map(|p| p[1]).collect()
    };
    let scale = match &args.range {
        Some(text) => {
            let parsed = text
                .split_once(':')
                .and_then(|(a, b)| Some((a.trim().parse().ok()?, b.trim().parse().ok()?)));
            let Some((lo, hi)) = parsed else {
                bail!("--range {text}: give LO:HI, e.g. 0:50");
            };
            Scale {
                lo,
                hi,
                log: args.log,
            }
        }
        None => Scale::auto(&y, args.log),
    };
    if !scale.is_valid() {
        bail!(
            "--range {}:{}: needs finite LO < HI{}",
            scale.lo,
            scale.hi,
            if scale.log {
                ", LO > 0 on a --log scale"
            } else {
                ""
            }
        );
    }
    let (w, h, rgb) = false_colour(&y, image.width, image.height, &scale, unit);
    write_png_rgb8(out, w as u32, h as u32, &rgb)
        .with_context(|| format!("{}: cannot write", out.display()))?;
    eprintln!(
        "scotopia: false colour of {quantity}, {} to {} {unit}{} → {}",
        scale.lo,
        scale.hi,
        if scale.log { " (log)" } else { "" },
        out.display()
    );
    Ok(())
}
