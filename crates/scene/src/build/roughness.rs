//! The microfacet roughness of the rough BSDFs, read as Mitsuba 3 reads
//! it: the distribution, α (numbers, or textures where Mitsuba takes
//! them), and `sample_visible`.

use scotopia_render::bsdf::{MicrofacetDistribution, MicrofacetKind, Roughness};
use scotopia_render::texture::FloatTexture;

use super::float_texture::float_texture;
use super::Builder;
use crate::mitsuba::{Node, Props, SceneError};

/// Whether a plugin takes `alpha_u` ≠ `alpha_v` (Mitsuba 3's
/// `roughplastic` refuses them).
#[derive(Clone, Copy, PartialEq, Eq)]
pub(super) enum Anisotropy {
    Allowed,
    Refused,
}

/// The roughness of `roughconductor` and `roughdielectric`, whose α may
/// be textures (Mitsuba 3 reads them with `get_unbounded_texture`): as
/// [`roughness`] reads it otherwise.
pub(super) fn textured_roughness(
    b: &mut Builder,
    p: &Props,
    node: &Node,
) -> Result<Roughness, SceneError> {
    let (kind, u, v) = roughness_textures(b, p, node)?;
    if let (FloatTexture::Constant(u), FloatTexture::Constant(v)) = (&u, &v) {
        return check_constant(b, p, node, kind, *u, *v, Anisotropy::Allowed).map(Roughness::from);
    }
    sample_visible(b, p, node)?;
    Ok(Roughness::new(kind, u, v))
}

/// The microfacet roughness of a rough BSDF, read as Mitsuba 3 reads it
/// (`microfacet.h`, `roughconductor.cpp`): `distribution` (`beckmann`, the
/// default, or `ggx`); `alpha` (0.1) or both `alpha_u` and `alpha_v`;
/// `sample_visible` (true). Numbers only: a texture is refused, as by
/// Mitsuba's `roughplastic`.
pub(super) fn roughness(
    b: &mut Builder,
    p: &Props,
    node: &Node,
    anisotropy: Anisotropy,
) -> Result<MicrofacetDistribution, SceneError> {
    for name in ["alpha", "alpha_u", "alpha_v"] {
        if let Some(n) = p.get(name).filter(|n| n.tag == "texture" || n.tag == "ref") {
            return Err(n.error(format!(
                "a textured roughness ('{name}') is not supported by '{}': give a <float>",
                node.attr("type").unwrap_or("?")
            )));
        }
    }
    let (kind, u, v) = roughness_textures(b, p, node)?;
    let constant = |t: FloatTexture| match t {
        FloatTexture::Constant(a) => a,
        _ => unreachable!("textures are refused above"),
    };
    check_constant(b, p, node, kind, constant(u), constant(v), anisotropy)
}

/// `distribution` and α_u, α_v (numbers or textures): `alpha` (0.1) or
/// both `alpha_u` and `alpha_v`.
fn roughness_textures(
    b: &mut Builder,
    p: &Props,
    node: &Node,
) -> Result<(MicrofacetKind, FloatTexture, FloatTexture), SceneError> {
    let kind = match p.string("distribution")? {
        None => MicrofacetKind::Beckmann,
        Some(name) => match name.to_lowercase().as_str() {
            "beckmann" => MicrofacetKind::Beckmann,
            "ggx" => MicrofacetKind::Ggx,
            _ => {
                return Err(p.get("distribution").unwrap_or(node).error(format!(
                    "invalid microfacet distribution '{name}': must be 'beckmann' or 'ggx'"
                )))
            }
        },
    };
    let mut alpha = |name: &str| match p.get(name) {
        Some(_) => float_texture(b, p, name, 0.1).map(Some),
        None => Ok(None),
    };
    let (alpha, u, v) = (alpha("alpha")?, alpha("alpha_u")?, alpha("alpha_v")?);
    let (au, av) = match (alpha, u, v) {
        (Some(_), Some(_), _) | (Some(_), _, Some(_)) => {
            return Err(node.error("give either 'alpha' or 'alpha_u' and 'alpha_v', not both"))
        }
        (Some(a), None, None) => (a.clone(), a),
        (None, Some(u), Some(v)) => (u, v),
        (None, Some(_), None) | (None, None, Some(_)) => {
            return Err(node.error("give both 'alpha_u' and 'alpha_v'"))
        }
        (None, None, None) => (FloatTexture::Constant(0.1), FloatTexture::Constant(0.1)),
    };
    Ok((kind, au, av))
}

/// Checks constant α_u, α_v as Mitsuba does and builds the distribution.
fn check_constant(
    b: &mut Builder,
    p: &Props,
    node: &Node,
    kind: MicrofacetKind,
    au: f32,
    av: f32,
    anisotropy: Anisotropy,
) -> Result<MicrofacetDistribution, SceneError> {
    for a in [au, av] {
        if !(a >= 0.0 && a.is_finite()) {
            return Err(node.error(format!("roughness must be positive, got {a}")));
        }
    }
    if anisotropy == Anisotropy::Refused && au != av {
        return Err(node.error(
            "anisotropic roughness (alpha_u ≠ alpha_v) is not supported by this plugin \
             (nor by Mitsuba 3)",
        ));
    }
    if au.min(av) < scotopia_render::bsdf::MIN_ALPHA {
        b.warn(
            node,
            format!(
                "roughness below {} is raised to it, as Mitsuba does; \
                 a smooth surface is the smooth plugin",
                scotopia_render::bsdf::MIN_ALPHA
            ),
        );
    }
    sample_visible(b, p, node)?;
    Ok(MicrofacetDistribution::new(kind, au, av))
}

/// `sample_visible`: scotopia always samples visible normals.
fn sample_visible(b: &mut Builder, p: &Props, node: &Node) -> Result<(), SceneError> {
    if !p.boolean("sample_visible", true)? {
        b.warn(
            node,
            "sample_visible=false is not honoured: scotopia samples visible normals \
             (the same image, with less noise)"
                .into(),
        );
    }
    Ok(())
}
