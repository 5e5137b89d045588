//! `<emitter>` elements other than area lights (which belong to shapes).

use scotopia_color::{RgbSpace, Spectrum};
use scotopia_image::read_rgb;
use scotopia_render::camera::Camera;
use scotopia_render::light::{
    ConstantLight, DirectionalLight, EnvMapLight, Light, PointLight, ProjectorLight, SceneExtent,
    SpotLight,
};
use scotopia_render::math::{Frame, Vec3};
use scotopia_render::texture::Texture;

use super::sensor::field_of_view;
use super::Builder;
use crate::mitsuba::{normalised_illuminant, resolve, Node, Props, SceneError, Usage};

pub fn build_emitter(b: &mut Builder, node: &Node) -> Result<Light, SceneError> {
    let kind = node.require("type")?;
    let p = Props::new(node);
    let required = |name: &str| -> Result<Spectrum, SceneError> {
        p.spectrum(name, Usage::Emission)?
            .ok_or_else(|| node.error(format!("missing '{name}'")))
    };
    let light = match kind {
        "point" => {
            let to_world = p.transform("to_world")?;
            let position = to_world.point(p.point("position", Vec3::ZERO)?);
            Light::Point(PointLight {
                position,
                intensity: required("intensity")?,
            })
        }
        "spot" => {
            let to_world = p.transform("to_world")?;
            let cutoff = p.float("cutoff_angle", 20.0)?;
            let beam = p.float("beam_width", cutoff * 0.75)?;
            let spot = SpotLight::new(
                to_world.point(Vec3::ZERO),
                to_world.vector(Vec3::new(0.0, 0.0, 1.0)),
                required("intensity")?,
                cutoff,
                beam,
            );
            match p.get("texture") {
                None => Light::Spot(spot),
                Some(_) => {
                    // Oriented by the emitter's own axes, as Mitsuba reads
                    // the texture in its local frame.
                    let axis = |v: Vec3| to_world.vector(v).normalize();
                    let frame = Frame {
                        s: axis(Vec3::new(1.0, 0.0, 0.0)),
                        t: axis(Vec3::new(0.0, 1.0, 0.0)),
                        n: axis(Vec3::new(0.0, 0.0, 1.0)),
                    };
                    let texture = b.texture(&p, "texture", Usage::Reflectance, 1.0)?;
                    Light::Spot(spot.with_texture(frame, texture))
                }
            }
        }
        "directional" => {
            let to_world = p.transform("to_world")?;
            let d = p
                .point("direction", to_world.vector(Vec3::new(0.0, 0.0, 1.0)))?
                .normalize();
            if !d.is_finite() {
                return Err(node.error("direction has zero length"));
            }
            Light::Directional(DirectionalLight {
                direction: d,
                irradiance: required("irradiance")?,
            })
        }
        // Mitsuba's default: radiance 1 in its spectral units (normalised D65).
        "constant" => Light::Constant(ConstantLight {
            radiance: match p.spectrum("radiance", Usage::Emission)? {
                Some(s) => s,
                None => normalised_illuminant("d65").map_err(|e| node.error(e))?,
            },
        }),
        "envmap" => {
            let file = p
                .string("filename")?
                .ok_or_else(|| node.error("an envmap needs a 'filename'"))?;
            let image = read_rgb(&resolve(&node.dir, file))
                .map_err(|e| node.error(e.to_string()))?
                .into_linear();
            let scale = p.float("scale", 1.0)?;
            let env = EnvMapLight::new(
                image.width,
                image.height,
                &image.pixels,
                RgbSpace::Srgb,
                scale,
                p.transform("to_world")?,
            )
            .map_err(|e| node.error(e.to_string()))?;
            Light::EnvMap(Box::new(env))
        }
        "projector" => {
            // Mitsuba's default irradiance: 1 in its spectral units.
            // A bitmap is upsampled as it is (white is equal-energy), a
            // colour or number × the normalised D65, as Mitsuba does.
            let irradiance = emissive_texture(b, &p, node, "irradiance")?;
            let (w, h) = match &irradiance {
                Texture::Bitmap(bm) => (bm.width() as u32, bm.height() as u32),
                _ => (1, 1),
            };
            let (fov, axis) = field_of_view(&p, node)?;
            let camera = Camera::new(
                p.transform("to_world")?,
                w,
                h,
                fov,
                axis,
                1e-4,
                1e4,
                0.0,
                1.0,
            )
            .map_err(|e| node.error(e.to_string()))?;
            let scale = p.float("scale", 1.0)?;
            if !(scale.is_finite() && scale >= 0.0) {
                return Err(node.error(format!("scale must be non-negative, got {scale}")));
            }
            Light::Projector(Box::new(ProjectorLight::new(camera, irradiance, scale)))
        }
        "ies" => Light::Goniometric(super::luminaire::build_ies(&p, node)?),
        "area" => return Err(node.error("an area emitter must be nested in a <shape>")),
        other => return Err(node.error(format!("emitter type '{other}' is not supported (area, point, spot, projector, directional, constant, envmap, ies)"))),
    };
    b.report_unused(&p);
    check_power(b, node, &light)?;
    Ok(light)
}

/// A light whose power is not a finite number (a NaN or overflowing
/// emission, a scale that overflows single precision) would make the image
/// black or NaN: an error naming the emitter. A light of zero power adds
/// nothing to the image: a warning. Lights at infinity are checked per
/// unit scene radius.
pub(super) fn check_power(b: &mut Builder, node: &Node, light: &Light) -> Result<(), SceneError> {
    let unit = SceneExtent {
        shapes: &[],
        center: Vec3::ZERO,
        radius: 1.0,
        casters: &[],
    };
    let p = light.power(&unit);
    // The light sampler weighs lights by their power in single precision.
    if !(p.watts.is_finite() && p.lumens.is_finite()) {
        return Err(node.error(format!(
            "the emitter's power is {} W ({} lm): it must be a finite number",
            p.watts, p.lumens
        )));
    }
    if !(p.watts as f32).is_finite() {
        return Err(node.error(format!(
            "the emitter's power {:e} W is beyond single precision (3.4e38): it must be finite \
             there; use larger length units (scenes of 1e-12 to 1e16 units render alike)",
            p.watts
        )));
    }
    if p.watts == 0.0 {
        b.warn(node, "the emitter's power is zero: it adds no light".into());
    }
    Ok(())
}

/// An emitter's texture parameter `name` (`radiance`, `irradiance`), as
/// Mitsuba's `get_emissive_texture` reads it: a `<texture>` or a `<ref>` to
/// one is used as it is (a bitmap upsampled unbounded: white is
/// equal-energy), a colour or number is × the normalised D65, and an
/// absent one is 1 (the normalised D65).
pub(super) fn emissive_texture(
    b: &mut Builder,
    p: &Props,
    node: &Node,
    name: &str,
) -> Result<Texture, SceneError> {
    Ok(match p.get(name) {
        Some(n) if n.tag == "texture" || n.tag == "ref" => {
            b.texture(p, name, Usage::Unbounded, 1.0)?
        }
        Some(_) => b.texture(p, name, Usage::Emission, 1.0)?,
        None => Texture::Constant(normalised_illuminant("d65").map_err(|e| node.error(e))?),
    })
}
