//! `<bsdf type="principled">` and `<bsdf type="principledthin">`: Mitsuba
//! 3's Disney-style BSDFs, read as `src/bsdfs/principled.cpp` and
//! `principledthin.cpp` read them.

use scotopia_render::bsdf::{
    specular_to_eta, Bsdf, Principled, PrincipledThin, SamplingRates, ThinSamplingRates,
};
use scotopia_render::texture::FloatTexture;

use super::float_texture::float_texture;
use super::Builder;
use crate::mitsuba::{Node, Props, SceneError, Usage};

/// A parameter whose lobe Mitsuba switches off when it is absent or the
/// number 0 (its `get_flag`); any texture or spectrum switches it on.
fn flagged(b: &mut Builder, p: &Props, name: &str) -> Result<Option<FloatTexture>, SceneError> {
    let Some(n) = p.get(name) else {
        return Ok(None);
    };
    if n.tag == "float" && p.float(name, 0.0)? == 0.0 {
        return Ok(None);
    }
    float_texture(b, p, name, 0.0).map(Some)
}

pub fn build(b: &mut Builder, p: &Props, node: &Node) -> Result<Bsdf, SceneError> {
    let spec_trans = flagged(b, p, "spec_trans")?;
    let eta = match (p.get("eta"), p.get("specular")) {
        (Some(_), Some(_)) => {
            return Err(node.error("give either 'eta' or 'specular', not both (as Mitsuba)"))
        }
        (Some(_), None) => {
            let eta = p.float("eta", 1.5)?;
            // An index-matched interface would make the transmission lobe
            // a delta; Mitsuba nudges it.
            if spec_trans.is_some() && eta == 1.0 {
                1.001
            } else {
                eta
            }
        }
        (None, _) => {
            let mut specular = p.float("specular", 0.5)?;
            if spec_trans.is_some() && specular == 0.0 {
                specular = 1e-3;
            }
            specular_to_eta(specular)
        }
    };
    if !(eta.is_finite() && eta > 0.0) {
        return Err(node.error(format!(
            "principled: the index of refraction must be positive, got {eta}"
        )));
    }
    Ok(Bsdf::Principled(Box::new(Principled {
        base_color: b.texture(p, "base_color", Usage::Reflectance, 0.5)?,
        roughness: float_texture(b, p, "roughness", 0.5)?,
        anisotropic: flagged(b, p, "anisotropic")?,
        metallic: flagged(b, p, "metallic")?,
        spec_trans,
        spec_tint: flagged(b, p, "spec_tint")?,
        sheen: flagged(b, p, "sheen")?,
        sheen_tint: flagged(b, p, "sheen_tint")?,
        flatness: flagged(b, p, "flatness")?,
        clearcoat: flagged(b, p, "clearcoat")?,
        clearcoat_gloss: float_texture(b, p, "clearcoat_gloss", 0.0)?,
        eta,
        rates: SamplingRates {
            diffuse: p.float("diffuse_reflectance_sampling_rate", 1.0)?,
            specular: p.float("main_specular_sampling_rate", 1.0)?,
            clearcoat: p.float("clearcoat_sampling_rate", 1.0)?,
        },
    })))
}

pub fn build_thin(b: &mut Builder, p: &Props) -> Result<Bsdf, SceneError> {
    Ok(Bsdf::PrincipledThin(Box::new(PrincipledThin {
        base_color: b.texture(p, "base_color", Usage::Reflectance, 0.5)?,
        roughness: float_texture(b, p, "roughness", 0.5)?,
        anisotropic: flagged(b, p, "anisotropic")?,
        spec_trans: flagged(b, p, "spec_trans")?,
        spec_tint: flagged(b, p, "spec_tint")?,
        sheen: flagged(b, p, "sheen")?,
        sheen_tint: flagged(b, p, "sheen_tint")?,
        flatness: flagged(b, p, "flatness")?,
        diff_trans: flagged(b, p, "diff_trans")?,
        eta: float_texture(b, p, "eta", 1.5)?,
        rates: ThinSamplingRates {
            specular_reflectance: p.float("specular_reflectance_sampling_rate", 1.0)?,
            specular_transmittance: p.float("specular_transmittance_sampling_rate", 1.0)?,
            diffuse_reflectance: p.float("diffuse_reflectance_sampling_rate", 1.0)?,
            diffuse_transmittance: p.float("diffuse_transmittance_sampling_rate", 1.0)?,
        },
    })))
}
