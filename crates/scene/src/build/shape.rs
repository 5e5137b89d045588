//! `<shape>` elements: spheres, rectangles, disks, cubes and meshes (OBJ,
//! PLY, Mitsuba's serialized).

use scotopia_render::geometry::{Cylinder, Planar, PlanarKind, Shape, Sphere, TriangleMesh};
use scotopia_render::math::{Frame, Transform, Vec3};

use super::Builder;
use crate::mesh::{read_obj, read_ply, read_serialized, MeshData};
use crate::mitsuba::{resolve, Node, Props, SceneError};

pub fn build_shape(b: &mut Builder, node: &Node) -> Result<Shape, SceneError> {
    let kind = node.require("type")?;
    let p = Props::new(node);
    let to_world = p.transform("to_world")?;
    let flip = p.boolean("flip_normals", false)?;
    let flipped = |t: Transform| {
        if flip {
            t.then_after(&Transform::scale(Vec3::new(1.0, 1.0, -1.0)).expect("invertible"))
        } else {
            t
        }
    };
    let shape = match kind {
        "sphere" => {
            let center = p.point("center", Vec3::ZERO)?;
            let radius = p.float("radius", 1.0)?;
            // Mitsuba allows similarity transforms only: one scale factor.
            let axes = [
                Vec3::new(1.0, 0.0, 0.0),
                Vec3::new(0.0, 1.0, 0.0),
                Vec3::new(0.0, 0.0, 1.0),
            ]
            .map(|a| to_world.vector(a));
            let lengths = axes.map(|a| a.length());
            if (lengths[0] - lengths[1]).abs() > 1e-4 * lengths[0]
                || (lengths[0] - lengths[2]).abs() > 1e-4 * lengths[0]
            {
                return Err(node.error("a sphere's to_world must scale all axes equally"));
            }
            if radius.is_nan() || radius <= 0.0 {
                return Err(node.error(format!("radius must be positive, got {radius}")));
            }
            // The object axes in world space: texture coordinates turn
            // with the sphere, as in Mitsuba.
            let frame = Frame {
                s: axes[0] / lengths[0],
                t: axes[1] / lengths[1],
                n: axes[2] / lengths[2],
            };
            Shape::Sphere(
                Sphere::oriented(to_world.point(center), radius * lengths[0], frame)
                    .with_flipped_normals(flip),
            )
        }
        "rectangle" => Shape::Planar(Box::new(Planar::new(
            PlanarKind::Rectangle,
            flipped(to_world),
        ))),
        "disk" => Shape::Planar(Box::new(Planar::new(PlanarKind::Disk, flipped(to_world)))),
        "cylinder" => {
            let p0 = p.point("p0", Vec3::ZERO)?;
            let p1 = p.point("p1", Vec3::new(0.0, 0.0, 1.0))?;
            let radius = p.float("radius", 1.0)?;
            Shape::Cylinder(Box::new(
                Cylinder::new(p0, p1, radius, &to_world, flip)
                    .map_err(|e| node.error(e.to_string()))?,
            ))
        }
        "cube" => Shape::Mesh(
            cube(&to_world, flip != to_world.swaps_handedness())
                .map_err(|e| node.error(e.to_string()))?,
        ),
        "obj" | "ply" | "serialized" => {
            let file = p
                .string("filename")?
                .ok_or_else(|| node.error("missing <string name=\"filename\">"))?;
            let path = resolve(&node.dir, file);
            if !path.is_file() {
                let looked: Vec<String> = node
                    .dir
                    .folders()
                    .iter()
                    .map(|f| f.display().to_string())
                    .collect();
                return Err(node.error(format!(
                    "mesh file '{file}' not found (looked in {})",
                    looked.join(", ")
                )));
            }
            let mut data = match kind {
                "obj" => read_obj(&path),
                "ply" => read_ply(&path),
                _ => {
                    let index = p.integer("shape_index", 0)?;
                    let index = usize::try_from(index).map_err(|_| {
                        node.error(format!("shape_index must be nonnegative, got {index}"))
                    })?;
                    read_serialized(&path, index).map(|s| s.mesh)
                }
            }
            .map_err(|e| node.error(e.to_string()))?;
            // Mitsuba flips texture v by default for OBJ, not for PLY; its
            // serialized loader has no such option.
            if kind != "serialized" && p.boolean("flip_tex_coords", kind == "obj")? {
                if let Some(uvs) = data.uvs.as_mut() {
                    uvs.iter_mut().for_each(|t| t[1] = 1.0 - t[1]);
                }
            }
            for note in std::mem::take(&mut data.notes) {
                b.warn(node, format!("{file}: {note}"));
            }
            let face_normals = p.boolean("face_normals", false)?;
            Shape::Mesh(
                mesh(data, face_normals, flip, &to_world)
                    .map_err(|e| node.error(format!("{file}: {e}")))?,
            )
        }
        other => return Err(node.error(format!("shape type '{other}' is not supported"))),
    };
    // Read by `Media::of_shape`.
    for side in ["interior", "exterior"] {
        let _ = p.get(side);
    }
    b.report_unused(&p);
    Ok(shape)
}

/// A mesh file's data placed in the world, as Mitsuba places it: face
/// normals drop the vertex normals; a mesh without them gets smooth
/// ones computed from its faces; flipped normals negate the vertex
/// normals; the winding is reversed when flipped or mirrored (not both),
/// so that face normals point as the vertex normals do.
fn mesh(
    mut data: MeshData,
    face_normals: bool,
    flip: bool,
    to_world: &Transform,
) -> Result<TriangleMesh, scotopia_render::geometry::GeometryError> {
    if face_normals {
        data.normals = None;
    }
    if flip != to_world.swaps_handedness() {
        data.indices.iter_mut().for_each(|t| t.swap(1, 2));
    }
    if flip {
        if let Some(n) = data.normals.as_mut() {
            n.iter_mut().for_each(|v| *v = -*v);
        }
    }
    let smooth = !face_normals && data.normals.is_none();
    let mut m = TriangleMesh::new(
        data.positions,
        data.normals,
        data.uvs,
        data.indices,
        to_world,
    )?
    .with_attributes(data.attributes)?;
    if smooth {
        m.compute_smooth_normals(data.points.as_deref());
    }
    Ok(m)
}

/// Mitsuba's cube: [−1, 1]³ as 6 faces of 4 vertices and 2 triangles,
/// in Mitsuba's order, each face's vertices with the uv (0, 1), (1, 1),
/// (1, 0), (0, 0); normals outwards (the winding reversed when
/// `reverse`: flipped or mirrored, not both).
fn cube(
    to_world: &Transform,
    reverse: bool,
) -> Result<TriangleMesh, scotopia_render::geometry::GeometryError> {
    // Corner c is at (±1, ±1, ±1), bit k of c the sign of axis k; each row
    // one face (−y, +y, +x, +z, −x, −z), as Mitsuba's cube lists them.
    const FACES: [[u32; 4]; 6] = [
        [1, 5, 4, 0],
        [3, 2, 6, 7],
        [1, 3, 7, 5],
        [5, 7, 6, 4],
        [4, 6, 2, 0],
        [3, 1, 0, 2],
    ];
    const UV: [[f32; 2]; 4] = [[0.0, 1.0], [1.0, 1.0], [1.0, 0.0], [0.0, 0.0]];
    let corner = |c: u32| {
        let s = |bit: u32| if c & bit != 0 { 1.0 } else { -1.0 };
        Vec3::new(s(1), s(2), s(4))
    };
    let mut positions = Vec::with_capacity(24);
    let mut uvs = Vec::with_capacity(24);
    let mut indices = Vec::with_capacity(12);
    for (f, face) in FACES.iter().enumerate() {
        let v = 4 * f as u32;
        positions.extend(face.iter().map(|&c| corner(c)));
        uvs.extend_from_slice(&UV);
        for mut t in [[v, v + 1, v + 2], [v + 3, v, v + 2]] {
            if reverse {
                t.swap(1, 2);
            }
            indices.push(t);
        }
    }
    TriangleMesh::new(positions, None, Some(uvs), indices, to_world)
}
