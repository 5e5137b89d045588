//! Uniform sampling of points on shapes, by area. Each point carries the
//! texture coordinates a ray hitting it would find (`Shape::surface`), so
//! a textured emitter is evaluated alike at hits and at sampled points.

use super::{PlanarKind, Shape};
use crate::math::Vec3;
use crate::sampling::distribution::Distribution1D;
use crate::sampling::warp::{square_to_disk_concentric, square_to_uniform_sphere};

/// A point on a surface, its unit normal and its texture coordinates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfacePoint {
    pub p: Vec3,
    pub n: Vec3,
    pub uv: [f32; 2],
}

impl Shape {
    /// The table `sample_area` chooses a mesh's triangles by (their areas);
    /// `None` for other shapes.
    pub fn area_table(&self) -> Option<Distribution1D> {
        match self {
            Shape::Mesh(m) => Some(Distribution1D::new(
                (0..m.triangle_count()).map(|f| m.face_area(f)).collect(),
            )),
            _ => None,
        }
    }

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
                let (b1, b2) = (u[1] * s, s - u[1] * s);
                let p = a * (1.0 - b1 - b2) + b * b1 + c * b2;
                let n = (b - a).cross(c - a).normalize();
                n.is_finite().then_some(SurfacePoint {
                    p,
                    n,
                    uv: m.uv_at(face, b1, b2),
                })
            }
            Shape::Sphere(s) => {
                let n = square_to_uniform_sphere(u);
                Some(SurfacePoint {
                    p: s.center + n * s.radius,
                    n: s.normal(n),
                    uv: s.uv(n),
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
                    uv: pl.uv_at(x, y),
                })
            }
            Shape::Cylinder(c) => Some(c.sample_area(u)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{Cylinder, Hit, Planar, RayShear, Sphere, TriangleMesh};
    use crate::math::{Frame, Ray, Transform};

    /// Points of the R2 sequence in [0, 1)², and a third coordinate.
    fn r2(k: usize) -> (f32, [f32; 2]) {
        let f = |g: f64| ((0.5 + g * k as f64).fract()) as f32;
        (
            f(0.819_172_513_396_164_4),
            [f(0.671_043_606_703_789_2), f(0.549_700_477_901_970_4)],
        )
    }

    /// The texture coordinates a ray finds at `s` when it comes back to it
    /// along the normal from a little above it.
    fn uv_hit(shape: &Shape, s: &SurfacePoint) -> [f32; 2] {
        let ray = Ray::new(s.p + s.n * 0.25, -s.n);
        let shear = RayShear::new(&ray);
        let (prim, (t, uv)) = (0..shape.primitive_count())
            .filter_map(|i| {
                shape
                    .intersect(i, &ray, &shear, f32::INFINITY)
                    .map(|h| (i, h))
            })
            .min_by(|a, b| a.1 .0.total_cmp(&b.1 .0))
            .expect("the ray comes back to the sampled point");
        let hit = Hit {
            t,
            shape: 0,
            prim: prim as u32,
            uv,
            instance: None,
        };
        let surface = shape.surface(&hit, &ray);
        assert!(
            (surface.p - s.p).length() < 1e-4,
            "{:?} vs {:?}",
            surface.p,
            s.p
        );
        surface.uv
    }

    /// Samples `shape` by area and checks each point's uv against the
    /// hit's; `periodic`: the
    /// coordinate that wraps around (an angle), `skip` leaves out points
    /// where the angle is undefined (poles, centres).
    fn check(
        name: &str,
        shape: &Shape,
        periodic: Option<usize>,
        skip: impl Fn(&SurfacePoint) -> bool,
    ) {
        let cdf = match shape {
            Shape::Mesh(m) => Some(Distribution1D::new(
                (0..m.triangle_count()).map(|f| m.face_area(f)).collect(),
            )),
            _ => None,
        };
        let mut checked = 0;
        for k in 0..500 {
            let (u_select, u) = r2(k);
            let s = shape.sample_area(cdf.as_ref(), u_select, u).unwrap();
            if skip(&s) {
                continue;
            }
            let got = uv_hit(shape, &s);
            for c in 0..2 {
                let mut d = got[c] - s.uv[c];
                if periodic == Some(c) {
                    d -= d.round();
                }
                assert!(
                    d.abs() < 1e-3,
                    "{name}: sampled uv {:?}, hit uv {got:?}",
                    s.uv
                );
            }
            checked += 1;
        }
        assert!(checked > 400, "{name}: only {checked} points checked");
    }

    fn placement() -> Transform {
        Transform::translate(Vec3::new(0.3, -0.2, 1.5))
            .then_after(&Transform::rotate(Vec3::new(1.0, 2.0, 0.5), 37.0).unwrap())
            .then_after(&Transform::scale(Vec3::new(1.5, 0.7, 1.2)).unwrap())
    }

    #[test]
    fn sampled_points_carry_the_uv_a_ray_finds_there() {
        // A quad of two triangles with UVs that are not one affine map, and
        // the same quad without UVs (the barycentrics are the UVs).
        let positions = vec![
            Vec3::new(-1.0, -1.0, 0.0),
            Vec3::new(1.0, -1.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(-1.0, 1.0, 0.0),
        ];
        let uvs = vec![[0.1, 0.0], [0.9, 0.2], [1.0, 0.8], [0.0, 1.0]];
        let indices = vec![[0, 1, 2], [0, 2, 3]];
        for uvs in [Some(uvs), None] {
            let m = TriangleMesh::new(
                positions.clone(),
                None,
                uvs.clone(),
                indices.clone(),
                &placement(),
            )
            .unwrap();
            check("mesh", &Shape::Mesh(m), None, |_| false);
        }
        // A sphere turned in its frame: uv are (φ/2π, θ/π) in object space.
        let frame = Frame::from_normal(Vec3::new(0.3, -0.5, 0.8).normalize());
        let sphere = Sphere::oriented(Vec3::new(0.5, 1.0, -2.0), 0.7, frame);
        let near_pole = |s: &SurfacePoint| frame.to_local(s.n).z.abs() > 0.999;
        check("sphere", &Shape::Sphere(sphere), Some(0), near_pole);
        // The part of it seen from outside, sampled by its cone.
        let from = Vec3::new(2.0, 3.0, -1.0);
        for k in 0..200 {
            let (_, u) = r2(k);
            let (s, _) = sphere.sample_seen(from, u).unwrap();
            if near_pole(&s) {
                continue;
            }
            let got = uv_hit(&Shape::Sphere(sphere), &s);
            let d = [got[0] - s.uv[0], got[1] - s.uv[1]];
            assert!(
                (d[0] - d[0].round()).abs() < 1e-3 && d[1].abs() < 1e-3,
                "sphere cone: sampled uv {:?}, hit uv {got:?}",
                s.uv
            );
        }
        for (kind, periodic) in [(PlanarKind::Rectangle, None), (PlanarKind::Disk, Some(1))] {
            let planar = Shape::Planar(Box::new(Planar::new(kind, placement())));
            check("planar", &planar, periodic, |s| {
                s.uv[0] < 0.01 && periodic.is_some()
            });
        }
        let tube = Cylinder::new(
            Vec3::new(0.0, 0.0, -1.0),
            Vec3::new(0.2, 0.1, 1.0),
            0.6,
            &placement(),
            false,
        )
        .unwrap();
        check(
            "cylinder",
            &Shape::Cylinder(Box::new(tube)),
            Some(0),
            |_| false,
        );
    }
}
