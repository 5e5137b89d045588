//! Indices of refraction by number, spectrum or name.

use scotopia_color::Spectrum;

use crate::materials::{named_glass, GLASS_NAMES};
use crate::mitsuba::{Props, SceneError, Usage};

/// Constant indices by name, as Mitsuba 3 tabulates them (its
/// `dielectric` documentation), for the names without dispersion data.
const CONSTANT_IORS: [(&str, f32); 4] = [
    ("vacuum", 1.0),
    ("air", 1.000277),
    ("polypropylene", 1.49),
    ("acrylic glass", 1.49),
];

/// The index property `name`: a `<float>`, a `<spectrum>` (scotopia's
/// extension), or a `<string>` naming a material; `default` is a name.
pub fn read_ior(p: &Props, name: &str, default: &str) -> Result<Spectrum, SceneError> {
    if let Some(n) = p.get(name) {
        if n.tag != "string" {
            return Ok(p
                .spectrum(name, Usage::Unbounded)?
                .expect("property exists"));
        }
    }
    let value = p.string(name)?.unwrap_or(default);
    by_name(value).ok_or_else(|| {
        let known: Vec<&str> = GLASS_NAMES
            .iter()
            .copied()
            .chain(CONSTANT_IORS.iter().map(|c| c.0))
            .collect();
        p.node.error(format!(
            "unknown index of refraction '{value}' (known: {})",
            known.join(", ")
        ))
    })
}

fn by_name(name: &str) -> Option<Spectrum> {
    let n = name.trim().to_ascii_lowercase();
    named_glass(&n).or_else(|| {
        CONSTANT_IORS
            .iter()
            .find(|c| c.0 == n)
            .map(|c| Spectrum::Constant(c.1))
    })
}
