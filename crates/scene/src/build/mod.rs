//! Build: plain Mitsuba nodes to a renderable `Scene`. Each element type
//! has its file; this one walks the scene, resolves `id`/`ref`, and
//! collects warnings about what scotopia reads but does not use.

mod bsdf;
mod bsdf_nested;
mod bsdf_principled;
mod emitter;
mod float_texture;
mod integrator;
mod ior;
mod luminaire;
mod medium;
mod mesh_attribute;
pub mod registry;
mod roughness;
mod sensor;
mod shape;
mod standalone;
mod texture;
mod unread;
mod world;

pub use sensor::Resolution;
pub use standalone::bsdf_from_xml;

use std::collections::{HashMap, HashSet};
use std::path::{Path, PathBuf};

use scotopia_color::{Spectrum, SpectrumKind};
use scotopia_render::bsdf::Bsdf;
use scotopia_render::scene::Scene;
use scotopia_render::texture::Texture;

use crate::mitsuba::{
    parse_scene, Node, Parameters, Props, SceneError, SceneErrors, Usage, MAX_DEPTH,
};

/// Collects state while building.
pub struct Builder {
    warnings: Vec<String>,
    /// The warnings given, to give each once (a set: a scene of 100 000
    /// objects may warn 100 000 times, and a scan per warning is quadratic).
    warned: HashSet<String>,
    errors: Vec<SceneError>,
    /// Top-level objects with an `id`, built on reference.
    named: HashMap<String, Node>,
    /// Textures built from top-level definitions, by id and use.
    textures: HashMap<(String, SpectrumKind), Texture>,
    /// Ids being built through references, to refuse cycles.
    resolving: Vec<String>,
    /// A film size that overrides the scene's.
    resolution: Option<Resolution>,
    /// The shape whose material is being built (what `mesh_attribute`
    /// textures read), and how many such textures were bound so far.
    on_shape: Option<mesh_attribute::OnShape>,
    mesh_attributes_bound: usize,
}

impl Builder {
    pub(crate) fn new() -> Self {
        Self {
            warnings: Vec::new(),
            warned: HashSet::new(),
            errors: Vec::new(),
            named: HashMap::new(),
            textures: HashMap::new(),
            resolving: Vec::new(),
            resolution: None,
            on_shape: None,
            mesh_attributes_bound: 0,
        }
    }

    /// The top-level object `id` refers to, which must be a `<tag>`.
    pub(crate) fn named(&self, at: &Node, tag: &str, id: &str) -> Result<Node, SceneError> {
        match self.named.get(id) {
            Some(n) if n.tag == tag => Ok(n.clone()),
            Some(n) => Err(at.error(format!(
                "'{id}' is a <{}> ({}), not a <{tag}>",
                n.tag, n.location
            ))),
            None => Err(at.error(format!("no <{tag} id=\"{id}\"> is defined"))),
        }
    }

    pub(crate) fn warn(&mut self, node: &Node, message: String) {
        let line = format!("{}: <{}>: {message}", node.location, node.tag);
        if self.warned.insert(line.clone()) {
            self.warnings.push(line);
        }
    }

    /// One warning per property an object sets that scotopia ignores.
    pub(crate) fn report_unused(&mut self, p: &Props) {
        for (n, note) in p.take_notes() {
            self.warn(n, note);
        }
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
                let target = self.named(n, "texture", id)?;
                let bound = self.mesh_attributes_bound;
                let t = self.resolve(n, id, |b| texture::build_texture(b, &target, usage))?;
                // One bound to a mesh is built again for the next.
                if self.mesh_attributes_bound == bound {
                    self.textures.insert(key, t.clone());
                }
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
        // A chain of references nests objects as deeply as elements do.
        if self.resolving.len() >= MAX_DEPTH {
            return Err(at.error(format!(
                "<ref>s to objects that hold <ref>s are chained more than {MAX_DEPTH} deep \
                 (through '{}' … '{id}')",
                self.resolving[0]
            )));
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
            let target = self.named(node, "bsdf", id)?;
            return self.resolve(node, id, |b| bsdf::build_bsdf(b, &target));
        }
        bsdf::build_bsdf(self, node)
    }
}

/// How a scene is loaded, beyond its parameters.
#[derive(Debug, Clone, Default)]
pub struct LoadOptions {
    /// Overrides the film size (`--res`), keeping the field of view along
    /// the film's `fov_axis`, as Mitsuba does when width and height change.
    pub resolution: Option<Resolution>,
    /// A scene without a `<sensor>` loads with Mitsuba's default one (for
    /// `measure`, which needs no camera) instead of being an error.
    pub sensor_optional: bool,
}

/// Loads a Mitsuba 3 scene file with parameters (`$name` values). On
/// failure, every error found (up to [`SceneErrors::LIMIT`]) with the
/// warnings so far.
pub fn load_scene(path: &Path, params: &Parameters) -> Result<Scene, SceneErrors> {
    load_scene_with(path, params, &LoadOptions::default())
}

/// [`load_scene`] with options.
pub fn load_scene_with(
    path: &Path,
    params: &Parameters,
    options: &LoadOptions,
) -> Result<Scene, SceneErrors> {
    load_scene_tracked(path, params, options).map(|(scene, _)| scene)
}

/// [`load_scene_with`], and every file the scene read: the scene file, its
/// includes, meshes, textures, spectra, photometric files, grids (what a
/// checkpoint's fingerprint hashes, so that an edited one is noticed).
pub fn load_scene_tracked(
    path: &Path,
    params: &Parameters,
    options: &LoadOptions,
) -> Result<(Scene, Vec<PathBuf>), SceneErrors> {
    let (scene, read) = crate::mitsuba::recording(|| load(path, params, options));
    let mut files = vec![path.to_path_buf()];
    files.extend(read.into_iter().filter(|f| f != path));
    Ok((scene?, files))
}

fn load(path: &Path, params: &Parameters, options: &LoadOptions) -> Result<Scene, SceneErrors> {
    let parsed = parse_scene(path, params)?;
    let root = parsed.root;
    let mut b = Builder::new();
    b.resolution = options.resolution;
    b.warnings.extend(parsed.warnings);
    if let Some(v) = root.attr("version") {
        if !v.starts_with('3') {
            b.warn(
                &root,
                format!("version {v}: scotopia reads the Mitsuba 3 format"),
            );
        }
    }
    b.collect_ids(&root);
    world::warn_media(&mut b, &root);
    unread::warn_unread(&mut b, &root);

    let mut world = world::World::default();
    for n in &root.children {
        if b.errors.len() > SceneErrors::LIMIT {
            break;
        }
        if let Err(e) = world.add(&mut b, n) {
            b.errors.push(e);
        }
    }
    if world.ignores_media() {
        b.warn(
            &root,
            "the scene's media are not rendered: its integrator ignores them, as Mitsuba's \
             path does (render with volpath or bdpt)"
                .into(),
        );
    }
    if world.sensor.is_none() && b.errors.is_empty() {
        if options.sensor_optional {
            // Mitsuba's default sensor: an empty perspective one.
            let implicit = Node {
                tag: "sensor".into(),
                attributes: vec![("type".into(), "perspective".into())],
                children: Vec::new(),
                location: root.location.clone(),
                dir: root.dir.clone(),
            };
            match sensor::build_sensor(&mut b, &implicit) {
                Ok(s) => world.sensor = Some(s),
                Err(e) => b.errors.push(e),
            }
        } else {
            b.errors.push(root.error("the scene has no <sensor>"));
        }
    }
    match world.sensor.take() {
        Some(sensor) if b.errors.is_empty() => Ok(world.scene(sensor, b.warnings)),
        _ => {
            let truncated = b.errors.len() > SceneErrors::LIMIT;
            b.errors.truncate(SceneErrors::LIMIT);
            // In the order of the file (ids are checked before the rest).
            b.errors.sort_by(|x, y| {
                let key =
                    |e: &SceneError| (e.location.file.clone(), e.location.line, e.location.column);
                key(x).cmp(&key(y))
            });
            Err(SceneErrors {
                errors: b.errors,
                warnings: b.warnings,
                truncated,
            })
        }
    }
}

impl Builder {
    /// Registers top-level objects by `id`. A second object with the same
    /// id, at the top level or nested anywhere, is an error (as in Mitsuba,
    /// which keeps one table of ids), naming both.
    fn collect_ids(&mut self, root: &Node) {
        let mut first: HashMap<&str, &Node> = HashMap::new();
        // Depth first in document order, without recursion.
        let mut stack: Vec<(&Node, bool)> = root.children.iter().rev().map(|n| (n, true)).collect();
        while let Some((n, top)) = stack.pop() {
            stack.extend(n.children.iter().rev().map(|c| (c, false)));
            // A `<ref id>` names an object; it defines none.
            let Some(id) = n.attr("id").filter(|_| n.tag != "ref") else {
                continue;
            };
            if let Some(f) = first.get(id) {
                self.errors.push(n.error(format!(
                    "id '{id}' is already used by the <{}> at {}",
                    f.tag, f.location
                )));
                continue;
            }
            first.insert(id, n);
            if top {
                self.named.insert(id.to_string(), n.clone());
            }
        }
    }
}
