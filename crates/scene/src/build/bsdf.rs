//! `<bsdf>` elements.

use scotopia_color::Spectrum;
use scotopia_render::bsdf::{
    Bsdf, Conductor, Dielectric, Diffuse, Fluorescent, Ior, Plastic, RoughDielectric, RoughPlastic,
    ThinDielectric,
};
use scotopia_render::texture::Texture;

use super::ior::read_ior;
use super::Builder;
use crate::materials::{named_conductor, CONDUCTOR_NAMES};
use crate::mitsuba::{Node, Props, SceneError, Usage};

pub fn build_bsdf(b: &mut Builder, node: &Node) -> Result<Bsdf, SceneError> {
    let kind = node.require("type")?;
    let p = Props::new(node);
    let bsdf = match kind {
        "diffuse" => Bsdf::Diffuse(Diffuse {
            reflectance: b.texture(&p, "reflectance", Usage::Reflectance, 0.5)?,
        }),
        "conductor" | "roughconductor" => {
            let alpha = if kind == "roughconductor" {
                roughness(b, &p, node)?
            } else {
                0.0
            };
            let (eta, k) = match (
                p.spectrum("eta", Usage::Unbounded)?,
                p.spectrum("k", Usage::Unbounded)?,
            ) {
                (Some(e), Some(k)) => (e, k),
                (None, None) => {
                    let name = p.string("material")?.unwrap_or("none");
                    if name == "none" {
                        // Mitsuba's "none": a perfect mirror (η = 0, κ = 1 gives R = 1).
                        (Spectrum::Constant(0.0), Spectrum::Constant(1.0))
                    } else {
                        named_conductor(name).ok_or_else(|| {
                            node.error(format!(
                                "unknown conductor '{name}' (known: none, {})",
                                CONDUCTOR_NAMES.join(", ")
                            ))
                        })?
                    }
                }
                _ => return Err(node.error("give both 'eta' and 'k', or a 'material'")),
            };
            Bsdf::Conductor(Conductor {
                eta,
                k,
                specular_reflectance: b.texture(
                    &p,
                    "specular_reflectance",
                    Usage::Reflectance,
                    1.0,
                )?,
                alpha,
            })
        }
        "dielectric" | "roughdielectric" | "thindielectric" => {
            let ior = Ior {
                interior: read_ior(&p, "int_ior", "bk7")?,
                exterior: read_ior(&p, "ext_ior", "air")?,
            };
            let sr = b.texture(&p, "specular_reflectance", Usage::Reflectance, 1.0)?;
            let st = b.texture(&p, "specular_transmittance", Usage::Reflectance, 1.0)?;
            match kind {
                "dielectric" => Bsdf::Dielectric(Dielectric {
                    ior,
                    specular_reflectance: sr,
                    specular_transmittance: st,
                }),
                "thindielectric" => Bsdf::ThinDielectric(ThinDielectric {
                    ior,
                    specular_reflectance: sr,
                    specular_transmittance: st,
                }),
                _ => Bsdf::RoughDielectric(RoughDielectric {
                    alpha: roughness(b, &p, node)?,
                    ior,
                    specular_reflectance: sr,
                    specular_transmittance: st,
                }),
            }
        }
        "plastic" | "roughplastic" => {
            // The coating model takes one index: the interior over exterior at 550 nm.
            let int = read_ior(&p, "int_ior", "polypropylene")?.eval(550.0);
            let ext = read_ior(&p, "ext_ior", "air")?.eval(550.0);
            let diffuse = b.texture(&p, "diffuse_reflectance", Usage::Reflectance, 0.5)?;
            let specular = b.texture(&p, "specular_reflectance", Usage::Reflectance, 1.0)?;
            let nonlinear = p.boolean("nonlinear", false)?;
            if kind == "plastic" {
                Bsdf::Plastic(Plastic::new(diffuse, specular, int / ext, nonlinear))
            } else {
                let alpha = roughness(b, &p, node)?;
                Bsdf::RoughPlastic(RoughPlastic::new(
                    diffuse,
                    specular,
                    int / ext,
                    alpha,
                    nonlinear,
                ))
            }
        }
        "fluorescent" => fluorescent(b, &p, node)?,
        "twosided" => {
            let inner: Vec<&Node> = node
                .children
                .iter()
                .filter(|c| c.tag == "bsdf" || c.tag == "ref")
                .collect();
            match inner.as_slice() {
                [one] => Bsdf::TwoSided(Box::new(b.bsdf_child(one)?)),
                _ => return Err(node.error("twosided needs exactly one nested <bsdf> or <ref>")),
            }
        }
        other => return Err(node.error(format!("BSDF type '{other}' is not supported"))),
    };
    b.report_unused(&p);
    Ok(bsdf)
}

/// `alpha` (GGX). An explicit Beckmann or anisotropic roughness would render
/// a different material, so they are errors; an unstated distribution
/// (Mitsuba's default is Beckmann) is a warning.
fn roughness(b: &mut Builder, p: &Props, node: &Node) -> Result<f32, SceneError> {
    match p.string("distribution")? {
        Some("ggx") => {}
        Some(other) => {
            return Err(node.error(format!(
                "microfacet distribution '{other}' is not supported; use ggx"
            )))
        }
        None => b.warn(
            node,
            "no 'distribution' given: Mitsuba would use beckmann, scotopia renders ggx".into(),
        ),
    }
    let alpha = p.float("alpha", 0.1)?;
    let (au, av) = (p.float("alpha_u", alpha)?, p.float("alpha_v", alpha)?);
    if au != av {
        return Err(node.error("anisotropic roughness (alpha_u ≠ alpha_v) is not supported"));
    }
    if !(au > 0.0 && au.is_finite()) {
        return Err(node.error(format!("roughness alpha must be positive, got {au}")));
    }
    Ok(au)
}

/// `<bsdf type="fluorescent">`: elastic `reflectance`, `excitation` (the
/// fraction absorbed for re-emission), `emission` (its shape, normalised
/// here), `quantum_yield` (photons out per photon absorbed, default 1).
fn fluorescent(b: &mut Builder, p: &Props, node: &Node) -> Result<Bsdf, SceneError> {
    if let Some(m) = p.get("matrix") {
        return Err(m.error(
            "a reradiation (Donaldson) matrix is not supported yet; give 'excitation', \
             'emission' and 'quantum_yield'",
        ));
    }
    let reflectance = b.texture(p, "reflectance", Usage::Reflectance, 0.0)?;
    let Texture::Constant(rho) = &reflectance else {
        return Err(node.error(
            "a fluorescent 'reflectance' must be a <spectrum>, <rgb> or <float>, not a texture",
        ));
    };
    let excitation = p
        .spectrum("excitation", Usage::Reflectance)?
        .ok_or_else(|| node.error("a fluorescent BSDF needs an 'excitation' spectrum"))?;
    let emission = p
        .spectrum("emission", Usage::Unbounded)?
        .ok_or_else(|| node.error("a fluorescent BSDF needs an 'emission' spectrum"))?;
    let q = p.float("quantum_yield", 1.0)?;
    if !(0.0..=1.0).contains(&q) {
        return Err(node.error(format!(
            "quantum_yield {q}: a ratio of photons, between 0 and 1"
        )));
    }
    // Light reflected and light absorbed for re-emission cannot exceed
    // the light arriving.
    for l in 360..=830 {
        let (r, e) = (rho.eval(l as f32), excitation.eval(l as f32));
        if r + e > 1.0 + 1e-4 {
            return Err(node.error(format!(
                "reflectance + excitation is {:.4} at {l} nm: it must not exceed 1",
                r + e
            )));
        }
    }
    let bsdf = Fluorescent::new(reflectance.clone(), &excitation, &emission, q)
        .ok_or_else(|| node.error("the 'emission' spectrum has no positive value in 360–830 nm"))?;
    Ok(Bsdf::Fluorescent(bsdf))
}
