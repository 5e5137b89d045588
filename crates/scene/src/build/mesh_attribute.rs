//! `<texture type="mesh_attribute">` (Mitsuba 3's plugin of that name):
//! a mesh's named attribute (`name`, times `scale`). Its values belong to
//! one mesh, so the texture is built for the shape whose material is being
//! built — the builder holds that shape meanwhile — and a material or
//! texture that contains one is built afresh for each shape, never shared
//! through its id. An attribute the mesh lacks is an error naming the
//! shape's file, as Mitsuba 3.9's scalar variants fail on it.

use std::sync::Arc;

use scotopia_color::SpectrumKind;
use scotopia_render::geometry::Shape;
use scotopia_render::texture::{FloatTexture, MeshAttribute, Texture};

use super::Builder;
use crate::mitsuba::{Node, Props, SceneError};

/// The shape whose material is being built, and how errors name it.
pub(super) struct OnShape {
    pub shape: Shape,
    /// E.g. "the mesh 'meshes/bunny.ply' (the shape at scene.xml:12:5)".
    pub described: String,
}

impl OnShape {
    pub fn new(shape: Shape, node: &Node) -> Self {
        let p = Props::new(node);
        let file = p.string("filename").ok().flatten();
        let described = match file {
            Some(f) => format!("the mesh '{f}' (the shape at {})", node.location),
            None => format!(
                "the {} shape at {}",
                node.attr("type").unwrap_or("?"),
                node.location
            ),
        };
        Self { shape, described }
    }
}

impl Builder {
    /// Runs `build` (a shape's material) with `on` held as the shape that
    /// mesh attributes are read from; returns the shape and whether a
    /// mesh attribute was bound (then the result must not be shared).
    pub(super) fn on_shape<T>(
        &mut self,
        on: OnShape,
        build: impl FnOnce(&mut Self) -> T,
    ) -> (Shape, T, bool) {
        let before = self.mesh_attributes_bound;
        let outer = self.on_shape.replace(on);
        let built = build(self);
        let on = std::mem::replace(&mut self.on_shape, outer).expect("set above");
        (on.shape, built, self.mesh_attributes_bound != before)
    }
}

/// The texture as a spectrum for use as `kind`.
pub(super) fn spectral(
    b: &mut Builder,
    p: &Props,
    node: &Node,
    kind: SpectrumKind,
) -> Result<Texture, SceneError> {
    bind(b, p, node, |mesh, name, scale| {
        MeshAttribute::spectral(mesh, name, scale, kind)
    })
    .map(|m| Texture::MeshAttribute(Arc::new(m)))
}

/// The texture as one number per point.
pub(super) fn numbers(b: &mut Builder, p: &Props, node: &Node) -> Result<FloatTexture, SceneError> {
    bind(b, p, node, MeshAttribute::numbers).map(|m| FloatTexture::MeshAttribute(Arc::new(m)))
}

fn bind(
    b: &mut Builder,
    p: &Props,
    node: &Node,
    make: impl FnOnce(
        &scotopia_render::geometry::TriangleMesh,
        &str,
        f32,
    ) -> Result<MeshAttribute, String>,
) -> Result<MeshAttribute, SceneError> {
    let name = p
        .string("name")?
        .ok_or_else(|| node.error("a mesh_attribute needs a <string name=\"name\">"))?;
    let scale = p.float("scale", 1.0)?;
    let Some(on) = &b.on_shape else {
        return Err(node.error(format!(
            "mesh_attribute '{name}' is read from the mesh a material is on; here there is none"
        )));
    };
    let built = match &on.shape {
        Shape::Mesh(mesh) => make(mesh, name, scale),
        _ => Err(format!(
            "no attribute '{name}' (only meshes have attributes)"
        )),
    }
    .map_err(|e| node.error(format!("mesh_attribute: {}: {e}", on.described)))?;
    b.mesh_attributes_bound += 1;
    Ok(built)
}
