//! The scene's top-level elements gathered into a renderable world:
//! shapes with their materials and area lights, other lights, the sensor
//! and the integrator.

use std::collections::HashMap;

use scotopia_render::accel::Aggregate;
use scotopia_render::bsdf::{Bsdf, Diffuse};
use scotopia_render::geometry::Shape;
use scotopia_render::light::{AreaLight, Light};
use scotopia_render::scene::{IntegratorSettings, Scene};
use scotopia_render::texture::Texture;

use super::integrator::{build_integrator, DEFAULT};
use super::mesh_attribute::OnShape;
use super::registry::{self, Support};
use super::sensor::{build_sensor, Sensor};
use super::{emitter, shape, Builder};
use crate::mitsuba::{Node, Props, SceneError};

pub struct World {
    pub sensor: Option<Sensor>,
    integrator: IntegratorSettings,
    shapes: Vec<Shape>,
    materials: Vec<Bsdf>,
    /// Materials built from top-level BSDFs, by id (shared by shapes).
    material_ids: HashMap<String, u32>,
    shape_material: Vec<u32>,
    shape_light: Vec<Option<u32>>,
    lights: Vec<Light>,
}

impl Default for World {
    fn default() -> Self {
        Self {
            sensor: None,
            integrator: DEFAULT,
            shapes: Vec::new(),
            materials: Vec::new(),
            material_ids: HashMap::new(),
            shape_material: Vec::new(),
            shape_light: Vec::new(),
            lights: Vec::new(),
        }
    }
}

impl World {
    /// Adds one top-level element.
    pub fn add(&mut self, b: &mut Builder, n: &Node) -> Result<(), SceneError> {
        match n.tag.as_str() {
            "sensor" => {
                if self.sensor.is_some() {
                    b.warn(n, "more than one sensor: using the first".into());
                } else {
                    self.sensor = Some(build_sensor(b, n)?);
                }
            }
            "integrator" => self.integrator = build_integrator(b, n)?,
            "bsdf" | "texture" => {
                // Built on use (by ref); without an id it is never used.
                n.require("type")?;
                if n.attr("id").is_none() {
                    b.warn(
                        n,
                        format!("a top-level <{}> without an id is never used", n.tag),
                    );
                }
            }
            "shape" => self.add_shape(b, n)?,
            "emitter" => {
                if n.attr("type") == Some("area") && n.attr("id").is_some() {
                    // Built where a shape refers to it.
                    return Ok(());
                }
                self.lights.push(emitter::build_emitter(b, n)?);
            }
            // Warned about once by `warn_media`.
            "medium" => {}
            other => b.warn(n, format!("<{other}> is not used by scotopia; ignored")),
        }
        Ok(())
    }

    /// A shape, its material (nested, referenced, or the default diffuse)
    /// and its area emitter (nested or referenced).
    fn add_shape(&mut self, b: &mut Builder, n: &Node) -> Result<(), SceneError> {
        let kind = n.require("type")?;
        match kind {
            // Built where an instance refers to it.
            "shapegroup" => {
                if n.attr("id").is_none() {
                    b.warn(n, "a shapegroup without an id is never used".into());
                }
                return Ok(());
            }
            "instance" => return self.add_instance(b, n),
            // Mitsuba merges its meshes into one for speed: the same image.
            "merge" => {
                for c in n.children.iter().filter(|c| c.tag == "shape") {
                    self.add_shape(b, c)?;
                }
                return Ok(());
            }
            _ => {}
        }
        // Shapes scotopia cannot intersect yet (the registry's "skipped"):
        // left out with a warning, so the rest of the scene renders.
        if registry::plugin("shape", kind).is_some_and(|p| p.support == Support::Skipped) {
            b.warn(
                n,
                format!("shape type '{kind}' is not supported yet: skipped (the image lacks it)"),
            );
            return Ok(());
        }
        let shape = shape::build_shape(b, n)?;
        let mut bsdf = None;
        let mut emitters = Vec::new();
        for c in &n.children {
            match c.tag.as_str() {
                "bsdf" => bsdf = Some((c, None)),
                "emitter" => emitters.push(c.clone()),
                // An unnamed reference (or Mitsuba's name="bsdf") is an
                // object the shape holds: a BSDF or an emitter.
                "ref" if c.attr("name").is_none_or(|k| k == "bsdf") => {
                    let id = c.require("id")?;
                    match b.named.get(id).map(|t| t.tag.as_str()) {
                        Some("emitter") => emitters.push(b.named(c, "emitter", id)?),
                        Some("medium") => {}
                        _ => bsdf = Some((c, Some(id.to_string()))),
                    }
                }
                _ => {}
            }
        }
        // The material, built with the shape at hand for the mesh
        // attributes it reads; one that reads them is this shape's alone.
        let (shape, material) = match bsdf {
            Some((c, id)) => match id.as_ref().and_then(|id| self.material_ids.get(id)) {
                Some(&m) => (shape, m),
                None => {
                    let (shape, built, bound) =
                        b.on_shape(OnShape::new(shape, n), |b| b.bsdf_child(c));
                    let m = self.push_material(built?);
                    if let (Some(id), false) = (id, bound) {
                        self.material_ids.insert(id, m);
                    }
                    (shape, m)
                }
            },
            None => (
                shape,
                self.push_material(Bsdf::Diffuse(Diffuse {
                    reflectance: Texture::constant(0.5),
                })),
            ),
        };
        let index = self.shapes.len() as u32;
        let mut light = None;
        for e in &emitters {
            if light.is_some() {
                return Err(e.error("a shape can hold one area emitter"));
            }
            if e.require("type")? != "area" {
                return Err(e.error("only an 'area' emitter can be attached to a shape"));
            }
            let p = Props::new(e);
            let radiance = emitter::emissive_texture(b, &p, e, "radiance")?;
            b.report_unused(&p);
            self.lights
                .push(Light::Area(AreaLight::new(index, &shape, radiance)));
            light = Some((self.lights.len() - 1) as u32);
        }
        self.shapes.push(shape);
        self.shape_material.push(material);
        self.shape_light.push(light);
        Ok(())
    }

    /// `<shape type="instance">`: the shapes of the `shapegroup` it refers
    /// to, each placed by its own `to_world` and then the instance's.
    /// The group's shapes are copied per instance (not shared).
    fn add_instance(&mut self, b: &mut Builder, n: &Node) -> Result<(), SceneError> {
        let group_ref = n
            .children
            .iter()
            .find(|c| c.tag == "ref" || (c.tag == "shape" && c.attr("type") == Some("shapegroup")))
            .ok_or_else(|| n.error("an instance needs a <ref id=\"…\"/> to a shapegroup"))?;
        let group = if group_ref.tag == "ref" {
            let id = group_ref.require("id")?;
            let g = b.named(group_ref, "shape", id)?;
            if g.attr("type") != Some("shapegroup") {
                return Err(group_ref.error(format!("'{id}' is not a shapegroup")));
            }
            g
        } else {
            group_ref.clone()
        };
        let p = Props::new(n);
        let placement = p.get("to_world");
        if let Some(t) = placement {
            if t.tag != "transform" {
                return Err(t.error("'to_world' must be a <transform>"));
            }
        }
        for c in &n.children {
            if c.tag != "ref" && c.tag != "transform" && c.tag != "shape" {
                b.warn(c, format!("<{}> in an instance is ignored", c.tag));
            }
        }
        for member in group.children.iter().filter(|c| c.tag == "shape") {
            if member.attr("type") == Some("shapegroup") || member.attr("type") == Some("instance")
            {
                return Err(member.error("a shapegroup cannot hold groups or instances"));
            }
            let placed = match placement {
                Some(t) => place(member, t),
                None => member.clone(),
            };
            self.add_shape(b, &placed)?;
        }
        Ok(())
    }

    fn push_material(&mut self, bsdf: Bsdf) -> u32 {
        self.materials.push(bsdf);
        (self.materials.len() - 1) as u32
    }

    pub fn scene(self, sensor: Sensor, warnings: Vec<String>) -> Scene {
        Scene {
            camera: sensor.camera,
            filter: sensor.filter,
            samples_per_pixel: sensor.spp,
            integrator: self.integrator,
            geometry: Aggregate::new(self.shapes),
            materials: self.materials,
            shape_material: self.shape_material,
            shape_light: self.shape_light,
            lights: self.lights,
            warnings,
        }
    }
}

/// One warning for each `<medium>` anywhere in the scene: scotopia has no
/// participating media yet, and a medium silently dropped would change the
/// image without a word.
pub fn warn_media(b: &mut Builder, node: &Node) {
    for c in &node.children {
        if c.tag == "medium" {
            let kind = c.attr("type").unwrap_or("?");
            b.warn(
                c,
                format!(
                    "medium '{kind}' is ignored: scotopia does not render participating \
                     media yet, so the image lacks its absorption and scattering"
                ),
            );
        } else {
            warn_media(b, c);
        }
    }
}

/// `shape` moved by `placement` (a `<transform>`): its own `to_world`
/// operations followed by the placement's, which Mitsuba's rule (each
/// operation applies after the previous) makes placement ∘ own.
fn place(shape: &Node, placement: &Node) -> Node {
    let mut placed = shape.clone();
    let own = placed
        .children
        .iter_mut()
        .find(|c| c.tag == "transform" && c.attr("name") == Some("to_world"));
    match own {
        Some(t) => t.children.extend(placement.children.iter().cloned()),
        None => {
            let mut t = placement.clone();
            t.attributes = vec![("name".into(), "to_world".into())];
            placed.children.push(t);
        }
    }
    placed
}
