//! Shapes: triangle meshes, spheres, cylinders, disks, rectangles; what a
//! ray hit on them, and the surface there.

mod attribute;
mod cylinder;
mod mesh;
mod planar;
mod sample;
mod sphere;
mod tex_point;
mod triangle;

pub use attribute::Attribute;
pub use cylinder::{Cylinder, CylinderTest};
pub use mesh::TriangleMesh;
pub use planar::{Planar, PlanarKind, PlaneTest};
pub use sample::SurfacePoint;
pub use sphere::Sphere;
pub use tex_point::TexPoint;
pub use triangle::{intersect_triangle, RayShear, TriangleHit};

use crate::math::{Aabb, Ray, Vec3};

/// Geometry that cannot be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum GeometryError {
    #[error("{0}")]
    Invalid(String),
}

/// The closed set of shapes.
#[derive(Debug, Clone, PartialEq)]
pub enum Shape {
    Mesh(TriangleMesh),
    Sphere(Sphere),
    /// Boxed: it carries two 4×4 transforms.
    Planar(Box<Planar>),
    /// Boxed: it carries two 4×4 transforms.
    Cylinder(Box<Cylinder>),
}

/// The minimum a traversal records about the closest hit; the surface is
/// computed from it once, for that hit only.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hit {
    pub t: f32,
    pub shape: u32,
    pub prim: u32,
    /// Barycentrics (triangles) or object-space (x, y) (planar shapes).
    pub uv: [f32; 2],
    /// The instance hit, when the shape belongs to a shape group: `shape`
    /// is then the scene's number of the group's shape, `prim` its
    /// primitive, and `uv` is in the group's space
    /// (`Aggregate::surface` brings the surface to world space).
    pub instance: Option<u32>,
}

/// The surface at a hit: position, geometric and shading normals (unit,
/// facing the side the shape's normals point to), texture coordinates, and
/// the position's partial derivatives along them (Mitsuba's `dp_du`,
/// `dp_dv`: the shading frame's tangent follows `dpdu`, which normal maps
/// and bump maps rely on).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Surface {
    pub p: Vec3,
    pub n_geometric: Vec3,
    pub n_shading: Vec3,
    pub uv: [f32; 2],
    pub dpdu: Vec3,
    pub dpdv: Vec3,
}

impl Surface {
    /// Where textures are looked up at `hit` on this surface: its (u, v),
    /// and the triangle and barycentrics that mesh attributes are read at
    /// (on other shapes `hit.uv` is not barycentric, and no attribute is
    /// bound there).
    #[inline]
    pub fn tex(&self, hit: &Hit) -> TexPoint {
        TexPoint {
            uv: self.uv,
            prim: hit.prim,
            bary: hit.uv,
        }
    }
}

impl Shape {
    /// Number of primitives the BVH sees (triangles, or 1).
    pub fn primitive_count(&self) -> usize {
        match self {
            Shape::Mesh(m) => m.triangle_count(),
            _ => 1,
        }
    }

    /// Bounds of primitive `prim`.
    pub fn bounds(&self, prim: usize) -> Aabb {
        match self {
            Shape::Mesh(m) => {
                let (a, b, c) = m.vertices(prim);
                Aabb::from_points(&[a, b, c])
            }
            Shape::Sphere(s) => Aabb {
                min: s.center - Vec3::splat(s.radius),
                max: s.center + Vec3::splat(s.radius),
            },
            Shape::Planar(p) => {
                let corners = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];
                let pts = corners.map(|(x, y)| p.world_from_object.point(Vec3::new(x, y, 0.0)));
                Aabb::from_points(&pts)
            }
            Shape::Cylinder(c) => c.bounds(),
        }
    }

    /// Intersects primitive `prim` within (0, t_max).
    #[inline]
    pub fn intersect(
        &self,
        prim: usize,
        ray: &Ray,
        shear: &RayShear,
        t_max: f32,
    ) -> Option<(f32, [f32; 2])> {
        match self {
            Shape::Mesh(m) => {
                let (a, b, c) = m.vertices(prim);
                intersect_triangle(ray, shear, a, b, c, t_max).map(|h| (h.t, [h.b[1], h.b[2]]))
            }
            Shape::Sphere(s) => s.intersect(ray, t_max).map(|t| (t, [0.0, 0.0])),
            Shape::Planar(p) => p.intersect(ray, t_max),
            Shape::Cylinder(c) => c.intersect(ray, t_max),
        }
    }

    /// Total surface area.
    pub fn area(&self) -> f32 {
        match self {
            Shape::Mesh(m) => (0..m.triangle_count()).map(|f| m.face_area(f)).sum(),
            Shape::Sphere(s) => s.area(),
            Shape::Planar(p) => p.area(),
            Shape::Cylinder(c) => c.area(),
        }
    }

    /// The surface at `hit` of `ray`.
    pub fn surface(&self, hit: &Hit, ray: &Ray) -> Surface {
        match self {
            Shape::Mesh(m) => {
                let [b1, b2] = hit.uv;
                let b0 = 1.0 - b1 - b2;
                let f = hit.prim as usize;
                let (a, b, c) = m.vertices(f);
                let p = a * b0 + b * b1 + c * b2;
                let n_geometric = (b - a).cross(c - a).normalize();
                let [ia, ib, ic] = m.indices[f].map(|i| i as usize);
                let interpolated = m
                    .normals
                    .as_ref()
                    .map(|n| (n[ia] * b0 + n[ib] * b1 + n[ic] * b2).normalize())
                    .filter(|n| n.is_finite());
                // The geometric normal follows the shading normal's side.
                let (n_geometric, n_shading) = match interpolated {
                    Some(ns) if ns.dot(n_geometric) < 0.0 => (-n_geometric, ns),
                    Some(ns) => (n_geometric, ns),
                    None => (n_geometric, n_geometric),
                };
                let uv = m.uv_at(f, b1, b2);
                let (dpdu, dpdv) = match &m.uvs {
                    Some(t) => mesh::uv_derivatives([a, b, c], [t[ia], t[ib], t[ic]]),
                    // The texture coordinates are the barycentrics (b1, b2).
                    None => (b - a, c - a),
                };
                Surface {
                    p,
                    n_geometric,
                    n_shading,
                    uv,
                    dpdu,
                    dpdv,
                }
            }
            Shape::Sphere(s) => {
                let p = ray.at(hit.t);
                let n = (p - s.center).normalize();
                // Re-project onto the surface to remove the distance's rounding.
                let p = s.center + n * s.radius;
                // u = φ/2π, v = θ/π in the sphere's own frame:
                // ∂p/∂u = 2π r (−sin θ sin φ, sin θ cos φ, 0),
                // ∂p/∂v = π r (cos θ cos φ, cos θ sin φ, −sin θ).
                let local = s.frame.to_local(n);
                let (pi, r) = (std::f32::consts::PI, s.radius);
                let cos_t = local.z.clamp(-1.0, 1.0);
                let sin_t = (1.0 - cos_t * cos_t).max(0.0).sqrt();
                let (sin_p, cos_p) = local.y.atan2(local.x).sin_cos();
                let dpdu = Vec3::new(-sin_t * sin_p, sin_t * cos_p, 0.0) * (2.0 * pi * r);
                let dpdv = Vec3::new(cos_t * cos_p, cos_t * sin_p, -sin_t) * (pi * r);
                Surface {
                    p,
                    n_geometric: s.normal(n),
                    n_shading: s.normal(n),
                    uv: s.uv(n),
                    dpdu: s.frame.to_world(dpdu),
                    dpdv: s.frame.to_world(dpdv),
                }
            }
            Shape::Planar(pl) => {
                let [x, y] = hit.uv;
                let p = pl.world_from_object.point(Vec3::new(x, y, 0.0));
                let n = pl.normal();
                let two_pi = 2.0 * std::f32::consts::PI;
                let uv = pl.uv_at(x, y);
                // Object-space derivatives, then placed by the transform.
                let (dpdu, dpdv) = match pl.kind {
                    PlanarKind::Rectangle => (Vec3::new(2.0, 0.0, 0.0), Vec3::new(0.0, 2.0, 0.0)),
                    PlanarKind::Disk => {
                        let (sin_p, cos_p) = (two_pi * uv[1]).sin_cos();
                        (Vec3::new(cos_p, sin_p, 0.0), Vec3::new(-y, x, 0.0) * two_pi)
                    }
                };
                Surface {
                    p,
                    n_geometric: n,
                    n_shading: n,
                    uv,
                    dpdu: pl.world_from_object.vector(dpdu),
                    dpdv: pl.world_from_object.vector(dpdv),
                }
            }
            Shape::Cylinder(c) => {
                let (p, n, uv) = c.surface_at(ray.at(hit.t));
                // u = φ/2π around the axis, v along it (object z ∈ [0, 1]).
                let (sin_p, cos_p) = (2.0 * std::f32::consts::PI * uv[0]).sin_cos();
                let dpdu = Vec3::new(-sin_p, cos_p, 0.0) * (2.0 * std::f32::consts::PI);
                Surface {
                    p,
                    n_geometric: n,
                    n_shading: n,
                    uv,
                    dpdu: c.world_from_object.vector(dpdu),
                    dpdv: c.world_from_object.vector(Vec3::new(0.0, 0.0, 1.0)),
                }
            }
        }
    }
}
