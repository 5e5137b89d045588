//! `scotopia display --false-colour`: a map of luminance, CIE 191 mesopic
//! luminance or illuminance with a labelled scale bar, for reading levels
//! off a picture. `scotopia view` shows the same map; `display` writes it
//! (`display::write_false_colour`).

use anyhow::{bail, Result};

use scotopia_image::XyzvImage;
use scotopia_vision::false_colour::{false_colour, Mapped, Scale};

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
    if !mapped.reads(made) {
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
