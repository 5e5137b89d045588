//! Uniform sampling of points on shapes, by area.

use super::{PlanarKind, Shape};
use crate::math::Vec3;
use crate::sampling::distribution::Distribution1D;
use crate::sampling::warp::{square_to_disk_concentric, square_to_uniform_sphere};

/// A point on a surface and its unit normal.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfacePoint {
    pub p: Vec3,
    pub n: Vec3,
}

impl Shape {
    /// A point uniformly distributed over the shape's area (density 1/area).
    /// `cdf` is the mesh's triangle-area table (ignored for other shapes).
    pub fn sample_area(
        &self,
        cdf: Option<&Distribution1D>,
        u_select: f32,
        u: [f32; 2],
    ) -> Option<SurfacePoint> {
        match self {
            Shape::Mesh(m) => {
                let (face, _, _) = cdf?.sample_discrete(u_select)?;
                let (a, b, c) = m.vertices(face);
                // Uniform barycentrics (the square-root parameterisation).
                let s = u[0].sqrt();
                let (b0, b1) = (1.0 - s, u[1] * s);
                let p = a * b0 + b * b1 + c * (1.0 - b0 - b1);
                let n = (b - a).cross(c - a).normalize();
                n.is_finite().then_some(SurfacePoint { p, n })
            }
            Shape::Sphere(s) => {
                let n = square_to_uniform_sphere(u);
                Some(SurfacePoint {
                    p: s.center + n * s.radius,
                    n: s.normal(n),
                })
            }
            Shape::Planar(pl) => {
                let [x, y] = match pl.kind {
                    PlanarKind::Disk => square_to_disk_concentric(u),
                    PlanarKind::Rectangle => [2.0 * u[0] - 1.0, 2.0 * u[1] - 1.0],
                };
                Some(SurfacePoint {
                    p: pl.world_from_object.point(Vec3::new(x, y, 0.0)),
                    n: pl.normal(),
                })
            }
            Shape::Cylinder(c) => Some(c.sample_area(u)),
        }
    }
}
