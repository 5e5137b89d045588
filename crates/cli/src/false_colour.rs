//! `scotopia display --false-colour`: a map of luminance, CIE 191 mesopic
//! luminance or illuminance with a labelled scale bar, for reading levels
//! off a picture. `scotopia view` shows the same map.

use anyhow::{bail, Context, Result};

use scotopia_image::{write_png_rgb8, XyzvImage};
use scotopia_vision::false_colour::{false_colour, Mapped, Scale};

use crate::display::Args;

pub fn run(args: &Args, quantity: &str, image: &XyzvImage) -> Result<()> {
    let Some(out) = &args.output else {
        bail!("--false-colour: give -o OUT.png");
    };
    let name = args.input.display().to_string();
    let map = map(quantity, args.range.as_deref(), args.log, image, &name)?;
    write_png_rgb8(out, map.width as u32, map.height as u32, &map.rgb)
        .with_context(|| format!("{}: cannot write", out.display()))?;
    eprintln!(
        "scotopia: false colour of {quantity}, {} → {}",
        map.legend,
        out.display()
    );
    Ok(())
}

/// A false-colour picture: 8-bit sRGB with its scale bar, and what its
/// scale spans ("0 to 12.5 cd/m² (log)").
pub struct FalseColour {
    pub width: usize,
    pub height: usize,
    pub rgb: Vec<u8>,
    pub legend: String,
}

/// The map of `quantity` over `image` (called `name` in errors), on the
/// scale `range` ("LO:HI"; default from the image), logarithmic if `log`.
pub fn map(
    quantity: &str,
    range: Option<&str>,
    log: bool,
    image: &XyzvImage,
    name: &str,
) -> Result<FalseColour> {
    let Some(mapped) = Mapped::from_name(quantity) else {
        bail!("--false-colour {quantity}: use {}", Mapped::NAMES);
    };
    let made = image.quantity.as_deref().unwrap_or("radiance");
    if made != mapped.needs() {
        bail!(
            "--false-colour {quantity}: {name} holds {made} (render --quantity {} makes it)",
            mapped.needs()
        );
    }
    let unit = mapped.unit();
    let y = mapped.values(&image.pixels);
    let scale = match range {
        Some(text) => match Scale::parse(text, log) {
            Some(s) => s,
            None => bail!("--range {text}: give LO:HI, e.g. 0:50"),
        },
        None => Scale::auto(&y, log),
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
    let (width, height, rgb) = false_colour(&y, image.width, image.height, &scale, unit);
    Ok(FalseColour {
        width,
        height,
        rgb,
        legend: format!(
            "{} to {} {unit}{}",
            scale.lo,
            scale.hi,
            if scale.log { " (log)" } else { "" }
        ),
    })
}
