//! `scotopia display --false-colour`: a map of luminance, CIE 191 mesopic
//! luminance or illuminance with a labelled scale bar, for reading levels
//! off a picture.

use anyhow::{bail, Context, Result};

use scotopia_image::{write_png_rgb8, XyzvImage};
use scotopia_vision::false_colour::{false_colour, Mapped, Scale};

use crate::display::Args;

pub fn run(args: &Args, quantity: &str, image: &XyzvImage) -> Result<()> {
    let Some(out) = &args.output else {
        bail!("--false-colour: give -o OUT.png");
    };
    let Some(mapped) = Mapped::from_name(quantity) else {
        bail!("--false-colour {quantity}: use {}", Mapped::NAMES);
    };
    let made = image.quantity.as_deref().unwrap_or("radiance");
    if made != mapped.needs() {
        bail!(
            "--false-colour {quantity}: {} holds {made} (render --quantity {} makes it)",
            args.input.display(),
            mapped.needs()
        );
    }
    let unit = mapped.unit();
    let y = mapped.values(&image.pixels);
    let scale = match &args.range {
        Some(text) => match Scale::parse(text, args.log) {
            Some(s) => s,
            None => bail!("--range {text}: give LO:HI, e.g. 0:50"),
        },
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
