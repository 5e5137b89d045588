//! Build: plain Mitsuba nodes to a renderable `Scene`. Each element type
//! has its file; this one walks the scene, resolves `id`/`ref`, and
//! collects warnings about what scotopia reads but does not use.

mod bsdf;
mod bsdf_nested;
mod emitter;
mod ior;
mod sensor;
mod shape;
mod texture;

use std::collections::HashMap;
use std::path::Path;

use scotopia_color::{Spectrum, SpectrumKind};
use scotopia_render::accel::Aggregate;
use scotopia_render::bsdf::{Bsdf, Diffuse};
use scotopia_render::light::{AreaLight, Light};
use scotopia_render::scene::{IntegratorKind, IntegratorSettings, Scene};
use scotopia_render::texture::Texture;

use crate::mitsuba::{parse_file, Node, Parameters, Props, SceneError, Usage};

/// Collects state while building.
pub struct Builder {
    warnings: Vec<String>,
    named_bsdfs: HashMap<String, Node>,
    named_textures: HashMap<String, Node>,
    /// Textures built from top-level definitions, by id and use.
    textures: HashMap<(String, SpectrumKind), Texture>,
    /// Ids being built through references, to refuse cycles.
    resolving: Vec<String>,
}

impl Builder {
    pub(crate) fn warn(&mut self, node: &Node, message: String) {
        let line = format!("{}: <{}>: {message}", node.location, node.tag);
        if !self.warnings.contains(&line) {
            self.warnings.push(line);
        }
    }

    /// One warning per property an object sets that scotopia ignores.
    pub(crate) fn report_unused(&mut self, p: &Props) {
        for n in p.unused() {
            let name = n.attr("name").unwrap_or("?").to_string();
            self.warn(
                n,
                format!("property '{name}' is not used by scotopia; ignored"),
            );
        }
    }

    /// Parameter `name` as a texture: a nested `<texture>`, a `<ref>` to a
    /// top-level one, or a constant spectrum (`default` when absent).
    pub(crate) fn texture(
        &mut self,
        p: &Props,
        name: &str,
        usage: Usage,
        default: f32,
    ) -> Result<Texture, SceneError> {
        match p.get(name) {
            Some(n) if n.tag == "texture" => texture::build_texture(self, n, usage),
            Some(n) if n.tag == "ref" => {
                let id = n.require("id")?;
                let key = (id.to_string(), texture::spectrum_kind(usage));
                if let Some(t) = self.textures.get(&key) {
                    return Ok(t.clone());
                }
                let target = self
                    .named_textures
                    .get(id)
                    .cloned()
                    .ok_or_else(|| n.error(format!("no <texture id=\"{id}\"> is defined")))?;
                let t = self.resolve(n, id, |b| texture::build_texture(b, &target, usage))?;
                self.textures.insert(key, t.clone());
                Ok(t)
            }
            _ => Ok(Texture::Constant(
                p.spectrum(name, usage)?
                    .unwrap_or(Spectrum::Constant(default)),
            )),
        }
    }

    /// Builds the object `id` that `at` refers to, refusing a reference
    /// cycle (which would recurse without end).
    fn resolve<T>(
        &mut self,
        at: &Node,
        id: &str,
        build: impl FnOnce(&mut Self) -> Result<T, SceneError>,
    ) -> Result<T, SceneError> {
        if self.resolving.iter().any(|r| r == id) {
            return Err(at.error(format!("'{id}' refers to itself through <ref>")));
        }
        self.resolving.push(id.to_string());
        let built = build(self);
        self.resolving.pop();
        built
    }

    /// A nested `<bsdf>` or a `<ref id>` to a top-level one.
    pub(crate) fn bsdf_child(&mut self, node: &Node) -> Result<Bsdf, SceneError> {
        if node.tag == "ref" {
            let id = node.require("id")?;
            let target = self
                .named_bsdfs
                .get(id)
                .cloned()
                .ok_or_else(|| node.error(format!("no <bsdf id=\"{id}\"> is defined")))?;
            return self.resolve(node, id, |b| bsdf::build_bsdf(b, &target));
        }
        bsdf::build_bsdf(self, node)
    }
}

/// Loads a Mitsuba 3 scene file with parameters (`$name` values).
pub fn load_scene(path: &Path, params: &Parameters) -> Result<Scene, SceneError> {
    let root = parse_file(path, params)?;
    let mut b = Builder {
        warnings: Vec::new(),
        named_bsdfs: HashMap::new(),
        named_textures: HashMap::new(),
        textures: HashMap::new(),
        resolving: Vec::new(),
    };
    if let Some(v) = root.attr("version") {
        if !v.starts_with('3') {
            b.warn(
                &root,
                format!("version {v}: scotopia reads the Mitsuba 3 format"),
            );
        }
    }
    for n in &root.children {
        if let Some(id) = n.attr("id") {
            match n.tag.as_str() {
                "bsdf" => b.named_bsdfs.insert(id.to_string(), n.clone()),
                "texture" => b.named_textures.insert(id.to_string(), n.clone()),
                _ => None,
            };
        }
    }

    let mut sensor = None;
    let mut integrator = IntegratorSettings {
        kind: IntegratorKind::Path,
        max_depth: -1,
        rr_depth: 5,
    };
    let mut shapes = Vec::new();
    let mut materials: Vec<Bsdf> = Vec::new();
    let mut material_ids: HashMap<String, u32> = HashMap::new();
    let mut shape_material = Vec::new();
    let mut shape_light = Vec::new();
    let mut lights = Vec::new();

    for n in &root.children {
        match n.tag.as_str() {
            "sensor" => {
                if sensor.is_some() {
                    b.warn(n, "more than one sensor: using the first".into());
                    continue;
                }
                sensor = Some(sensor::build_sensor(&mut b, n)?);
            }
            "integrator" => {
                let name = n.require("type")?;
                let p = Props::new(n);
                let kind = IntegratorKind::from_name(name).unwrap_or_else(|| {
                    b.warn(
                        n,
                        format!("integrator '{name}' is not supported, using path"),
                    );
                    IntegratorKind::Path
                });
                integrator = IntegratorSettings {
                    kind,
                    max_depth: p.integer("max_depth", -1)? as i32,
                    rr_depth: p.integer("rr_depth", 5)? as i32,
                };
                b.report_unused(&p);
            }
            "bsdf" => {
                // Built on use (by ref); a top-level BSDF without id is unused.
                n.require("type")?;
            }
            "shape" => {
                let shape = shape::build_shape(&mut b, n)?;
                // The material: a nested <bsdf>, a <ref>, or the default diffuse.
                let bsdf_node = n
                    .children
                    .iter()
                    .find(|c| c.tag == "bsdf" || c.tag == "ref");
                let material = match bsdf_node {
                    Some(c) if c.tag == "ref" => {
                        let id = c.require("id")?.to_string();
                        match material_ids.get(&id) {
                            Some(&m) => m,
                            None => {
                                let bsdf = b.bsdf_child(c)?;
                                materials.push(bsdf);
                                let m = (materials.len() - 1) as u32;
                                material_ids.insert(id, m);
                                m
                            }
                        }
                    }
                    Some(c) => {
                        materials.push(b.bsdf_child(c)?);
                        (materials.len() - 1) as u32
                    }
                    None => {
                        materials.push(Bsdf::Diffuse(Diffuse {
                            reflectance: Texture::constant(0.5),
                        }));
                        (materials.len() - 1) as u32
                    }
                };
                let index = shapes.len() as u32;
                let mut light = None;
                for e in n.children.iter().filter(|c| c.tag == "emitter") {
                    if e.require("type")? != "area" {
                        return Err(e.error("only an 'area' emitter can be attached to a shape"));
                    }
                    let p = Props::new(e);
                    let radiance = p
                        .spectrum("radiance", Usage::Emission)?
                        .ok_or_else(|| e.error("missing 'radiance'"))?;
                    b.report_unused(&p);
                    lights.push(Light::Area(AreaLight::new(index, &shape, radiance)));
                    light = Some((lights.len() - 1) as u32);
                }
                shapes.push(shape);
                shape_material.push(material);
                shape_light.push(light);
            }
            "emitter" => lights.push(emitter::build_emitter(&mut b, n)?),
            "texture" => {
                // Built on use (by ref), once per use (reflectance or emission).
                n.require("type")?;
                if n.attr("id").is_none() {
                    b.warn(n, "a top-level texture without an id is never used".into());
                }
            }
            other => b.warn(n, format!("<{other}> is not used by scotopia; ignored")),
        }
    }
    let sensor = sensor.ok_or_else(|| root.error("the scene has no <sensor>"))?;
    Ok(Scene {
        camera: sensor.camera,
        filter: sensor.filter,
        samples_per_pixel: sensor.spp,
        integrator,
        geometry: Aggregate::new(shapes),
        materials,
        shape_material,
        shape_light,
        lights,
        warnings: b.warnings,
    })
}
