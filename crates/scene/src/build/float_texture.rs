//! Textures read as numbers (`FloatTexture`): a roughness, a blend weight,
//! a mask's opacity — a `<float>`, a spectrum's mean, or a `bitmap`,
//! `checkerboard`, `mesh_attribute` or `rawconstant` texture.

use std::sync::Arc;

use scotopia_color::Spectrum;
use scotopia_render::texture::{FloatCheckerboard, FloatTexture, RgbBitmap, Texture};

use super::texture::{raw_constant, read_bitmap, uv_transform};
use super::{mesh_attribute, Builder};
use crate::mitsuba::{Node, Props, SceneError, Usage};

/// Parameter `name` as one number per point: a `<float>`, a spectrum (its
/// mean over 360–830 nm, the value itself for a constant), a nested
/// `<texture>`, or a `<ref>` to a top-level one.
pub(super) fn float_texture(
    b: &mut Builder,
    p: &Props,
    name: &str,
    default: f32,
) -> Result<FloatTexture, SceneError> {
    match p.get(name) {
        None => Ok(FloatTexture::Constant(default)),
        Some(n) if n.tag == "texture" || n.tag == "ref" => float_texture_node(b, n),
        Some(_) => match p.spectrum(name, Usage::Unbounded)? {
            Some(Spectrum::Constant(v)) => Ok(FloatTexture::Constant(v)),
            Some(s) => Ok(FloatTexture::Constant(Texture::Constant(s).mean())),
            None => Ok(FloatTexture::Constant(default)),
        },
    }
}

/// A `<texture>` node, or a `<ref>` to a top-level one, as numbers.
pub(super) fn float_texture_node(b: &mut Builder, node: &Node) -> Result<FloatTexture, SceneError> {
    if node.tag == "ref" {
        let id = node.require("id")?;
        let target = b.named(node, "texture", id)?;
        return b.resolve(node, id, |b| float_texture_node(b, &target));
    }
    let p = Props::new(node);
    let texture = match node.require("type")? {
        "bitmap" => FloatTexture::Bitmap(Arc::new(rgb_bitmap(&p, node)?)),
        "checkerboard" => FloatTexture::Checkerboard(Arc::new(FloatCheckerboard {
            first: float_texture(b, &p, "color0", 0.4)?,
            second: float_texture(b, &p, "color1", 0.2)?,
            to_uv: uv_transform(&p.transform("to_uv")?),
        })),
        "mesh_attribute" => mesh_attribute::numbers(b, &p, node)?,
        "rawconstant" => match p.get("value").map(|n| n.tag.as_str()) {
            Some("float") | None => FloatTexture::Constant(raw_constant(&p, node)?[0]),
            Some(_) => {
                return Err(node.error(
                    "a rawconstant of 3 values is not one number (Mitsuba's eval_1 refuses \
                     it too): give a <float>",
                ))
            }
        },
        other => {
            return Err(node.error(format!(
                "texture type '{other}' is not supported here (bitmap, checkerboard, \
                 mesh_attribute, rawconstant)"
            )))
        }
    };
    b.report_unused(&p);
    Ok(texture)
}

/// A `bitmap` node kept as linear RGB numbers.
pub(super) fn rgb_bitmap(p: &Props, node: &Node) -> Result<RgbBitmap, SceneError> {
    let to_uv = uv_transform(&p.transform("to_uv")?);
    let (image, filter, wrap) = read_bitmap(p, node)?;
    let mut bitmap = RgbBitmap::new(image.width, image.height, image.pixels)
        .ok_or_else(|| node.error("the image has no pixels"))?;
    bitmap.filter = filter;
    bitmap.wrap = wrap;
    bitmap.to_uv = to_uv;
    Ok(bitmap)
}
