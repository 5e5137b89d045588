//! `<bsdf>` types that pass light through or wrap other BSDFs — `null`,
//! `mask`, `blendbsdf`, `normalmap`, `bumpmap` — and the polarisation
//! plugins, which scotopia reads as Mitsuba's unpolarised variants render
//! them: `pplastic`, `polarizer`, `retarder`, `circular`,
//! `measured_polarized`; `principled` and `principledthin` are dispatched
//! from here to `bsdf_principled`.

use std::sync::Arc;

use scotopia_render::bsdf::{
    Blend, Bsdf, BumpMap, Diffuse, Mask, NormalMap, Null, PolarizedPlastic,
};
use scotopia_render::texture::{RgbBitmap, Texture};

use super::float_texture::{float_texture, float_texture_node, rgb_bitmap};
use super::ior::read_ior;
use super::roughness::textured_roughness;
use super::texture::raw_constant;
use super::Builder;
use crate::mitsuba::{parse_rgb, Node, Props, SceneError, Usage};

/// The BSDF types this file builds.
pub const NESTED_TYPES: [&str; 12] = [
    "null",
    "mask",
    "blendbsdf",
    "normalmap",
    "bumpmap",
    "pplastic",
    "polarizer",
    "retarder",
    "circular",
    "measured_polarized",
    "principled",
    "principledthin",
];

/// Builds `<bsdf type=kind>` for a kind in [`NESTED_TYPES`].
pub fn build(b: &mut Builder, kind: &str, p: &Props, node: &Node) -> Result<Bsdf, SceneError> {
    Ok(match kind {
        "null" => Bsdf::Null(Null::default()),
        "mask" => {
            let opacity = float_texture(b, p, "opacity", 0.5)?;
            let inner = one_child(b, p, node)?;
            refuse_fluorescence(&inner, node)?;
            Bsdf::Mask(Box::new(Mask { opacity, inner }))
        }
        "blendbsdf" => {
            let weight = match p.get("weight") {
                Some(_) => float_texture(b, p, "weight", 0.0)?,
                None => return Err(node.error("blendbsdf needs a 'weight'")),
            };
            let children = bsdf_children(b, p, node);
            let [first, second] = children.as_slice() else {
                return Err(node.error(format!(
                    "blendbsdf needs exactly two nested BSDFs, found {}",
                    children.len()
                )));
            };
            let (first, second) = (b.bsdf_child(first)?, b.bsdf_child(second)?);
            refuse_fluorescence(&first, node)?;
            refuse_fluorescence(&second, node)?;
            Bsdf::Blend(Box::new(Blend {
                weight,
                first,
                second,
            }))
        }
        "normalmap" => {
            let normals = rgb_texture(b, p, node, "normalmap")?;
            let inner = one_child(b, p, node)?;
            Bsdf::NormalMap(Box::new(NormalMap {
                normals,
                inner,
                flip_invalid_normals: p.boolean("flip_invalid_normals", true)?,
                use_shadowing_function: p.boolean("use_shadowing_function", true)?,
            }))
        }
        "bumpmap" => {
            // Mitsuba takes the one nested texture, whatever its name.
            let textures: Vec<&Node> = node
                .children
                .iter()
                .filter(|c| c.tag == "texture" || (c.tag == "ref" && is_texture_ref(b, c)))
                .collect();
            let [texture] = textures.as_slice() else {
                return Err(node.error(format!(
                    "bumpmap needs exactly one nested height <texture>, found {}",
                    textures.len()
                )));
            };
            match texture.attr("name") {
                Some(name) => {
                    p.get(name);
                }
                None => p.mark_unnamed_used(),
            }
            let height = float_texture_node(b, texture)?;
            let scale = p.float("scale", 1.0)?;
            let inner = one_child(b, p, node)?;
            Bsdf::BumpMap(Box::new(BumpMap {
                height,
                scale,
                inner,
                flip_invalid_normals: p.boolean("flip_invalid_normals", true)?,
                use_shadowing_function: p.boolean("use_shadowing_function", true)?,
            }))
        }
        "pplastic" => {
            let int = read_ior(p, "int_ior", "polypropylene")?.eval(550.0);
            let ext = read_ior(p, "ext_ior", "air")?.eval(550.0);
            let diffuse = b.texture(p, "diffuse_reflectance", Usage::Reflectance, 0.5)?;
            let specular = b.texture(p, "specular_reflectance", Usage::Reflectance, 1.0)?;
            let distribution = textured_roughness(b, p, node)?;
            b.warn(
                node,
                "pplastic: scotopia does not track polarisation; rendered as Mitsuba's \
                 unpolarised variants do (glossy reflection plus a diffuse term behind two \
                 refractions)"
                    .into(),
            );
            Bsdf::PolarizedPlastic(PolarizedPlastic::new(
                diffuse,
                specular,
                int / ext,
                distribution,
            ))
        }
        "polarizer" | "retarder" | "circular" => {
            let transmittance = b.texture(p, "transmittance", Usage::Reflectance, 1.0)?;
            // Read so that they are not reported as unused: they only
            // orient the polarisation.
            for name in ["theta", "delta", "polarizing", "left_handed"] {
                p.get(name);
            }
            // A retarder only shifts phases; a linear or circular polariser
            // passes half of unpolarised light.
            let scale = if kind == "retarder" { 1.0 } else { 0.5 };
            b.warn(
                node,
                format!(
                    "{kind}: scotopia does not track polarisation; rendered as Mitsuba's \
                     unpolarised variants do, a pass-through surface transmitting {scale} × \
                     transmittance"
                ),
            );
            Bsdf::Null(Null {
                transmittance,
                scale,
            })
        }
        "principled" => super::bsdf_principled::build(b, p, node)?,
        "principledthin" => super::bsdf_principled::build_thin(b, p)?,
        "measured_polarized" => {
            b.warn(
                node,
                "measured_polarized: its pBRDF file format is not read by scotopia; rendered \
                 as a grey diffuse surface (reflectance 0.5)"
                    .into(),
            );
            for name in ["filename", "alpha_sample", "wavelength"] {
                p.get(name);
            }
            Bsdf::Diffuse(Diffuse {
                reflectance: Texture::constant(0.5),
            })
        }
        other => return Err(node.error(format!("BSDF type '{other}' is not supported"))),
    })
}

/// Whether `<ref>` node `c` names a top-level texture.
fn is_texture_ref(b: &Builder, c: &Node) -> bool {
    c.attr("id")
        .is_some_and(|id| b.named.get(id).is_some_and(|n| n.tag == "texture"))
}

/// The nested BSDFs of `node`, in order: `<bsdf>` children and `<ref>`s
/// to top-level BSDFs (named or not).
fn bsdf_children<'n>(b: &Builder, p: &Props, node: &'n Node) -> Vec<&'n Node> {
    node.children
        .iter()
        .filter(|c| {
            c.tag == "bsdf"
                || (c.tag == "ref"
                    && c.attr("id")
                        .is_some_and(|id| b.named.get(id).is_some_and(|n| n.tag == "bsdf")))
        })
        .inspect(|c| {
            // A named reference reads as a property: mark it used.
            if let Some(name) = c.attr("name") {
                p.get(name);
            }
        })
        .collect()
}

/// The single nested BSDF of a wrapper.
fn one_child(b: &mut Builder, p: &Props, node: &Node) -> Result<Bsdf, SceneError> {
    let children = bsdf_children(b, p, node);
    match children.as_slice() {
        [one] => b.bsdf_child(one),
        _ => Err(node.error(format!(
            "{} needs exactly one nested <bsdf> or <ref>, found {}",
            node.attr("type").unwrap_or("this BSDF"),
            children.len()
        ))),
    }
}

/// Fluorescence moves wavelengths before the lobe is chosen, which a
/// mask's pass-through or a blend's other half would not undo.
fn refuse_fluorescence(inner: &Bsdf, node: &Node) -> Result<(), SceneError> {
    match inner.fluorescent() {
        Some(_) => Err(node.error(format!(
            "a fluorescent BSDF inside '{}' is not supported",
            node.attr("type").unwrap_or("?")
        ))),
        None => Ok(()),
    }
}

/// Parameter `name` as RGB numbers: a bitmap (nested or by `<ref>`), or an
/// `<rgb>` constant taken as it is written.
fn rgb_texture(
    b: &mut Builder,
    p: &Props,
    node: &Node,
    name: &str,
) -> Result<Arc<RgbBitmap>, SceneError> {
    let n = p
        .get(name)
        .ok_or_else(|| node.error(format!("'{name}' (a texture) is missing")))?;
    let constant = |rgb: [f32; 3]| {
        RgbBitmap::new(1, 1, vec![rgb])
            .map(Arc::new)
            .ok_or_else(|| n.error("not a colour"))
    };
    match n.tag.as_str() {
        "rgb" => constant(parse_rgb(n)?),
        "ref" => {
            let id = n.require("id")?;
            let target = b.named(n, "texture", id)?;
            b.resolve(n, id, |b| rgb_texture_node(b, &target))
        }
        "texture" => rgb_texture_node(b, n),
        other => Err(n.error(format!(
            "'{name}' must be a bitmap <texture> or an <rgb>, not <{other}>"
        ))),
    }
}

fn rgb_texture_node(b: &mut Builder, node: &Node) -> Result<Arc<RgbBitmap>, SceneError> {
    let p = Props::new(node);
    let bitmap = match node.require("type")? {
        "bitmap" => rgb_bitmap(&p, node)?,
        // Mitsuba's `eval_3` of a constant: the value everywhere.
        "rawconstant" => RgbBitmap::new(1, 1, vec![raw_constant(&p, node)?])
            .ok_or_else(|| node.error("not a colour"))?,
        other => {
            return Err(node.error(format!(
                "a normal map must be a bitmap or rawconstant texture, not '{other}'"
            )))
        }
    };
    b.report_unused(&p);
    Ok(Arc::new(bitmap))
}
