//! The scene's top-level elements gathered into a renderable world:
//! shapes with their materials and area lights, other lights, the sensor
//! and the integrator.

use std::collections::HashMap;
use std::sync::Arc;

use scotopia_render::accel::{Aggregate, Instance, ShapeGroup};
use scotopia_render::bsdf::{Bsdf, Diffuse};
use scotopia_render::camera::IrradianceMeter;
use scotopia_render::geometry::Shape;
use scotopia_render::light::{AreaLight, Light};
use scotopia_render::math::Transform;
use scotopia_render::medium::ShapeMedia;
use scotopia_render::scene::{IntegratorSettings, Scene};
use scotopia_render::texture::Texture;

use super::integrator::{build_integrator, DEFAULT};
use super::medium::Media;
use super::mesh_attribute::OnShape;
use super::registry::{self, Support};
use super::sensor::{build_meter, build_sensor, Sensor};
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
    /// Shape groups built (on their first instance), and their numbers by id.
    groups: Vec<Group>,
    group_ids: HashMap<String, usize>,
    /// Each instance: its group and its placement.
    instances: Vec<(usize, Transform)>,
    media: Media,
}

/// A shape built with its material, and the emitters it holds.
struct Member {
    shape: Shape,
    material: u32,
    emitters: Vec<Node>,
    /// An `irradiancemeter` the shape holds.
    sensor: Option<Node>,
    media: ShapeMedia,
}

/// The shapes of a `shapegroup` and their materials.
#[derive(Default)]
struct Group {
    shapes: Vec<Shape>,
    shape_material: Vec<u32>,
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
            groups: Vec::new(),
            group_ids: HashMap::new(),
            instances: Vec::new(),
            media: Media::default(),
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
                    self.media.camera = self.media.of_sensor(b, n)?;
                }
            }
            "integrator" => self.integrator = build_integrator(b, n)?,
            "bsdf" | "texture" | "volume" => {
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

    /// A top-level shape (or those a `merge` holds): each with its
    /// material and its area emitter.
    fn add_shape(&mut self, b: &mut Builder, n: &Node) -> Result<(), SceneError> {
        match n.require("type")? {
            // Built where an instance refers to it.
            "shapegroup" => {
                if n.attr("id").is_none() {
                    b.warn(n, "a shapegroup without an id is never used".into());
                }
                Ok(())
            }
            "instance" => self.add_instance(b, n),
            _ => {
                for m in self.build_members(b, n)? {
                    self.push_shape(b, m)?;
                }
                Ok(())
            }
        }
    }

    /// The shapes `n` describes (one, or those of a `merge`: Mitsuba merges
    /// its meshes into one for speed, the same image), each with its
    /// material (nested, referenced, or the default diffuse) and the
    /// emitters it holds. Shapes scotopia cannot intersect yet (the
    /// registry's "skipped") are left out with a warning, so the rest of
    /// the scene renders.
    fn build_members(&mut self, b: &mut Builder, n: &Node) -> Result<Vec<Member>, SceneError> {
        let kind = n.require("type")?;
        if kind == "merge" {
            let mut members = Vec::new();
            for c in n.children.iter().filter(|c| c.tag == "shape") {
                members.extend(self.build_members(b, c)?);
            }
            return Ok(members);
        }
        if registry::plugin("shape", kind).is_some_and(|p| p.support == Support::Skipped) {
            b.warn(
                n,
                format!("shape type '{kind}' is not supported yet: skipped (the image lacks it)"),
            );
            return Ok(Vec::new());
        }
        let shape = shape::build_shape(b, n)?;
        let mut bsdf: Option<(&Node, Option<String>)> = None;
        let mut emitters = Vec::new();
        let mut sensor = None;
        for c in &n.children {
            match c.tag.as_str() {
                "bsdf" => set_bsdf(&mut bsdf, c, None)?,
                "sensor" if sensor.is_some() => {
                    return Err(c.error("a shape can hold one sensor"));
                }
                "sensor" => sensor = Some(c.clone()),
                "emitter" => emitters.push(c.clone()),
                // An unnamed reference (or Mitsuba's name="bsdf") is an
                // object the shape holds: a BSDF or an emitter.
                "ref" if c.attr("name").is_none_or(|k| k == "bsdf") => {
                    let id = c.require("id")?;
                    match b.named.get(id).map(|t| t.tag.as_str()) {
                        Some("emitter") => emitters.push(b.named(c, "emitter", id)?),
                        Some("medium") => {}
                        _ => set_bsdf(&mut bsdf, c, Some(id.to_string()))?,
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
        let media = self.media.of_shape(b, n)?;
        Ok(vec![Member {
            shape,
            material,
            emitters,
            sensor,
            media,
        }])
    }

    /// A shape of the scene's own (outside groups), with its area light.
    fn push_shape(&mut self, b: &mut Builder, m: Member) -> Result<(), SceneError> {
        let index = self.shapes.len() as u32;
        let mut light = None;
        for e in &m.emitters {
            if light.is_some() {
                return Err(e.error("a shape can hold one area emitter"));
            }
            if e.require("type")? != "area" {
                return Err(e.error("only an 'area' emitter can be attached to a shape"));
            }
            let p = Props::new(e);
            let radiance = emitter::emissive_texture(b, &p, e, "radiance")?;
            b.report_unused(&p);
            let area = Light::Area(AreaLight::new(index, &m.shape, radiance));
            emitter::check_power(b, e, &area)?;
            self.lights.push(area);
            light = Some((self.lights.len() - 1) as u32);
        }
        if let Some(s) = &m.sensor {
            if s.require("type")? != "irradiancemeter" {
                return Err(s.error("a shape can hold only an 'irradiancemeter' sensor"));
            }
            if self.sensor.is_some() {
                b.warn(s, "more than one sensor: using the first".into());
            } else {
                self.sensor = Some(build_meter(b, s, index)?);
            }
        }
        self.shapes.push(m.shape);
        self.shape_material.push(m.material);
        self.shape_light.push(light);
        self.media.shape_media.push(m.media);
        Ok(())
    }

    /// `<shape type="instance">`: a placement (`to_world`) of the
    /// `shapegroup` it refers to. The group is built once, on its first
    /// instance, and shared by all.
    fn add_instance(&mut self, b: &mut Builder, n: &Node) -> Result<(), SceneError> {
        let group_ref = n
            .children
            .iter()
            .find(|c| c.tag == "ref" || (c.tag == "shape" && c.attr("type") == Some("shapegroup")))
            .ok_or_else(|| n.error("an instance needs a <ref id=\"…\"/> to a shapegroup"))?;
        let group = if group_ref.tag == "ref" {
            let id = group_ref.require("id")?;
            match self.group_ids.get(id) {
                Some(&g) => g,
                None => {
                    let node = b.named(group_ref, "shape", id)?;
                    if node.attr("type") != Some("shapegroup") {
                        return Err(group_ref.error(format!("'{id}' is not a shapegroup")));
                    }
                    let g = self.build_group(b, &node)?;
                    self.group_ids.insert(id.to_string(), g);
                    g
                }
            }
        } else {
            self.build_group(b, group_ref)?
        };
        let p = Props::new(n);
        let world_from_object = p.transform("to_world")?;
        for c in &n.children {
            if c.tag != "ref" && c.tag != "transform" && c.tag != "shape" {
                b.warn(c, format!("<{}> in an instance is ignored", c.tag));
            }
        }
        self.instances.push((group, world_from_object));
        Ok(())
    }

    /// The shapes of a `shapegroup`, with their materials. As Mitsuba, a
    /// group holds no groups or instances, and its shapes no emitters.
    fn build_group(&mut self, b: &mut Builder, n: &Node) -> Result<usize, SceneError> {
        let mut group = Group::default();
        for member in n.children.iter().filter(|c| c.tag == "shape") {
            if member.attr("type") == Some("shapegroup") || member.attr("type") == Some("instance")
            {
                return Err(member.error("a shapegroup cannot hold groups or instances"));
            }
            for m in self.build_members(b, member)? {
                if let Some(s) = &m.sensor {
                    return Err(s.error(
                        "a shape in a shapegroup cannot hold a sensor: place the measuring \
                         shape outside the group",
                    ));
                }
                if let Some(e) = m.emitters.first() {
                    return Err(e.error(
                        "a shape in a shapegroup cannot hold an emitter (Mitsuba does not \
                         instance emitters): place the emitting shape outside the group",
                    ));
                }
                group.shapes.push(m.shape);
                group.shape_material.push(m.material);
            }
        }
        self.groups.push(group);
        Ok(self.groups.len() - 1)
    }

    fn push_material(&mut self, bsdf: Bsdf) -> u32 {
        self.materials.push(bsdf);
        (self.materials.len() - 1) as u32
    }

    /// Whether the scene has media that its integrator does not trace
    /// (Mitsuba's `path` ignores them).
    pub fn ignores_media(&self) -> bool {
        !self.media.list.is_empty() && !self.integrator.media
    }

    pub fn scene(self, sensor: Sensor, warnings: Vec<String>) -> Scene {
        // The groups' shapes are numbered after the scene's own, each group
        // once: materials by shape, and no area lights (groups hold none).
        let (mut shape_material, mut shape_light) = (self.shape_material, self.shape_light);
        let groups: Vec<Arc<ShapeGroup>> = self
            .groups
            .into_iter()
            .map(|g| {
                let first = shape_material.len() as u32;
                shape_material.extend(g.shape_material);
                shape_light.resize(shape_material.len(), None);
                Arc::new(ShapeGroup::new(g.shapes, first))
            })
            .collect();
        // Shapes in groups are in vacuum (their media are not read).
        let mut shape_media = self.media.shape_media;
        shape_media.resize(shape_material.len(), ShapeMedia::default());
        let instances = self
            .instances
            .into_iter()
            .map(|(g, world_from_object)| Instance::new(groups[g].clone(), world_from_object))
            .collect();
        let meter = sensor
            .meter
            .map(|i| IrradianceMeter::new(i, &self.shapes[i as usize]));
        Scene {
            camera: sensor.camera,
            meter,
            filter: sensor.filter,
            samples_per_pixel: sensor.spp,
            integrator: self.integrator,
            geometry: Aggregate::with_instances(self.shapes, instances),
            materials: self.materials,
            shape_material,
            shape_light,
            lights: self.lights,
            media: self.media.list,
            shape_media,
            camera_medium: self.media.camera,
            warnings,
        }
    }
}

/// Sets a shape's BSDF; as Mitsuba, a shape takes one (a second would be
/// dropped without a word).
fn set_bsdf<'n>(
    slot: &mut Option<(&'n Node, Option<String>)>,
    c: &'n Node,
    id: Option<String>,
) -> Result<(), SceneError> {
    match slot.replace((c, id)) {
        Some((first, _)) => Err(c.error(format!(
            "a shape takes one BSDF, and one is already given at {}",
            first.location
        ))),
        None => Ok(()),
    }
}

/// One warning for each `<medium>` of a kind scotopia does not render,
/// anywhere in the scene: a medium silently dropped would change the image
/// without a word.
pub fn warn_media(b: &mut Builder, node: &Node) {
    for c in &node.children {
        if c.tag == "medium" {
            let kind = c.attr("type").unwrap_or("?");
            if matches!(kind, "homogeneous" | "heterogeneous") {
                continue;
            }
            b.warn(
                c,
                format!(
                    "medium '{kind}' is ignored: scotopia renders homogeneous and \
                     heterogeneous media, so the image lacks its absorption and scattering"
                ),
            );
        } else {
            warn_media(b, c);
        }
    }
}
