//! `<texture>` elements: `bitmap`, `checkerboard`, `mesh_attribute` and
//! `rawconstant`, nested in an object under a parameter's name or defined
//! at the top level with an `id` and referenced by `<ref name="…" id="…"/>`.

use scotopia_color::{RgbSpace, SpectrumKind};
use scotopia_image::{read_rgb, RgbImage};
use scotopia_render::math::Transform;
use scotopia_render::texture::{Bitmap, Checkerboard, Filter, Texture, UvTransform, Wrap};

use super::{mesh_attribute, Builder};
use crate::mitsuba::{resolve, Node, Props, SceneError, Usage};

/// The RGB upsampling kind for a use.
pub fn spectrum_kind(usage: Usage) -> SpectrumKind {
    match usage {
        Usage::Reflectance => SpectrumKind::Reflectance,
        Usage::Unbounded => SpectrumKind::Unbounded,
        Usage::Emission => SpectrumKind::Illuminant,
    }
}

/// Mitsuba's `to_uv`: the x and y rows of the 4×4 transform with its
/// translation (what Mitsuba 3 keeps; checked against Mitsuba 3.9).
pub(super) fn uv_transform(t: &Transform) -> UvTransform {
    let m = t.matrix();
    UvTransform([m[0][0], m[0][1], m[0][3], m[1][0], m[1][1], m[1][3]].map(|v| v as f32))
}

/// A `bitmap`'s image (linear unless `raw`), filter and wrap mode.
pub(super) fn read_bitmap(p: &Props, node: &Node) -> Result<(RgbImage, Filter, Wrap), SceneError> {
    let file = p
        .string("filename")?
        .ok_or_else(|| node.error("a bitmap needs a 'filename'"))?;
    let filter = match p.string("filter_type")?.unwrap_or("bilinear") {
        "bilinear" => Filter::Bilinear,
        "nearest" => Filter::Nearest,
        other => {
            return Err(node.error(format!(
                "filter_type '{other}' is not one of bilinear, nearest"
            )))
        }
    };
    let wrap = match p.string("wrap_mode")?.unwrap_or("repeat") {
        "repeat" => Wrap::Repeat,
        "mirror" => Wrap::Mirror,
        "clamp" => Wrap::Clamp,
        other => {
            return Err(node.error(format!(
                "wrap_mode '{other}' is not one of repeat, mirror, clamp"
            )))
        }
    };
    let raw = p.boolean("raw", false)?;
    let image = read_rgb(&resolve(&node.dir, file)).map_err(|e| node.error(e.to_string()))?;
    // `raw` keeps integer images' values as stored (already linear).
    let image = if raw { image } else { image.into_linear() };
    Ok((image, filter, wrap))
}

pub fn build_texture(b: &mut Builder, node: &Node, usage: Usage) -> Result<Texture, SceneError> {
    let kind = node.require("type")?;
    let p = Props::new(node);
    let to_uv = uv_transform(&p.transform("to_uv")?);
    let texture = match kind {
        "bitmap" => {
            let (image, filter, wrap) = read_bitmap(&p, node)?;
            let mut bitmap = Bitmap::from_rgb(
                image.width,
                image.height,
                &image.pixels,
                RgbSpace::Srgb,
                spectrum_kind(usage),
            )
            .map_err(|e| node.error(e.to_string()))?;
            bitmap.filter = filter;
            bitmap.wrap = wrap;
            bitmap.to_uv = to_uv;
            Texture::Bitmap(bitmap.into())
        }
        "checkerboard" => Texture::Checkerboard(
            Checkerboard {
                color0: b.texture(&p, "color0", usage, 0.4)?,
                color1: b.texture(&p, "color1", usage, 0.2)?,
                to_uv,
            }
            .into(),
        ),
        "mesh_attribute" => mesh_attribute::spectral(b, &p, node, spectrum_kind(usage))?,
        "rawconstant" => match raw_constant(&p, node)? {
            [v, _, _] if p.get("value").is_some_and(|n| n.tag == "float") => {
                Texture::Constant(scotopia_color::Spectrum::Constant(v))
            }
            _ => {
                return Err(node.error(
                    "a rawconstant of 3 values is not a spectrum (Mitsuba's spectral \
                     variants refuse it too): give one <float>, or an <rgb> spectrum",
                ))
            }
        },
        other => {
            return Err(node.error(format!(
                "texture type '{other}' is not supported (bitmap, checkerboard, \
                 mesh_attribute, rawconstant)"
            )))
        }
    };
    b.report_unused(&p);
    Ok(texture)
}

/// A `rawconstant`'s `value`: a `<float>` (repeated three times) or a
/// `<vector>`/`<point>`, taken as it is written, without colour handling
/// (Mitsuba's src/spectra/rawconstant.cpp).
pub(super) fn raw_constant(p: &Props, node: &Node) -> Result<[f32; 3], SceneError> {
    match p.get("value") {
        Some(n) if n.tag == "float" => Ok([p.float("value", 0.0)?; 3]),
        Some(n) if n.tag == "vector" || n.tag == "point" => {
            let v = p.point("value", scotopia_render::math::Vec3::ZERO)?;
            Ok([v.x, v.y, v.z])
        }
        Some(n) => Err(n.error("a rawconstant's 'value' is a <float> or a <vector>")),
        None => Err(node.error("a rawconstant needs a 'value'")),
    }
}
