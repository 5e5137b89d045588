//! `<shape>` elements: spheres, rectangles, disks, cubes and meshes (OBJ,
//! PLY, Mitsuba's serialized).

use scotopia_render::geometry::{Cylinder, Planar, PlanarKind, Shape, Sphere, TriangleMesh};
use scotopia_render::math::{Transform, Vec3};

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
            if flip {
                return Err(node.error("flip_normals on a sphere is not supported"));
            }
            let center = p.point("center", Vec3::ZERO)?;
            let radius = p.float("radius", 1.0)?;
            // Mitsuba allows similarity transforms only: one scale factor.
            let axes = [
                Vec3::new(1.0, 0.0, 0.0),
                Vec3::new(0.0, 1.0, 0.0),
                Vec3::new(0.0, 0.0, 1.0),
            ]
            .map(|a| to_world.vector(a).length());
            if (axes[0] - axes[1]).abs() > 1e-4 * axes[0]
                || (axes[0] - axes[2]).abs() > 1e-4 * axes[0]
            {
                return Err(node.error("a sphere's to_world must scale all axes equally"));
            }
            if radius.is_nan() || radius <= 0.0 {
                return Err(node.error(format!("radius must be positive, got {radius}")));
            }
            Shape::Sphere(Sphere {
                center: to_world.point(center),
                radius: radius * axes[0],
            })
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
        "cube" => Shape::Mesh(cube(&to_world, flip).map_err(|e| node.error(e.to_string()))?),
        "obj" | "ply" | "serialized" => {
            let file = p
                .string("filename")?
                .ok_or_else(|| node.error("missing <string name=\"filename\">"))?;
            let path = resolve(&node.dir, file);
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
            let face_normals = p.boolean("face_normals", false)?;
            Shape::Mesh(
                mesh(data, face_normals, flip, &to_world)
                    .map_err(|e| node.error(format!("{file}: {e}")))?,
            )
        }
        other => return Err(node.error(format!("shape type '{other}' is not supported"))),
    };
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
    )?;
    if smooth {
        m.compute_smooth_normals(data.points.as_deref());
    }
    Ok(m)
}

/// Mitsuba's cube: [−1, 1]³, outward normals (inward when flipped).
fn cube(
    to_world: &Transform,
    flip: bool,
) -> Result<TriangleMesh, scotopia_render::geometry::GeometryError> {
    let mut positions = Vec::new();
    let mut indices = Vec::new();
    // Each face: normal axis and sign; corners wound counter-clockwise seen from outside.
    for axis in 0..3 {
        for sign in [-1.0f32, 1.0] {
            let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
            let base = positions.len() as u32;
            for (a, c) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                let mut p = [0.0f32; 3];
                p[axis] = sign;
                p[u] = a;
                p[v] = c * sign;
                positions.push(Vec3::from(p));
            }
            let (t1, t2) = ([base, base + 1, base + 2], [base, base + 2, base + 3]);
            if flip {
                indices.push([t1[0], t1[2], t1[1]]);
                indices.push([t2[0], t2[2], t2[1]]);
            } else {
                indices.push(t1);
                indices.push(t2);
            }
        }
    }
    TriangleMesh::new(positions, None, None, indices, to_world)
}
