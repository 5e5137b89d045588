//! The camera as the end of a light path (Veach 1997, §10.2; pbrt-v4,
//! Pharr et al. 2023, §5.4.4): its importance We, the density of the
//! directions `generate_ray` draws, and connecting a point in the scene
//! to a point on the lens, for light tracing.
//!
//! The film position is uniform over the image, so on the plane z = 1 of
//! camera space (area A = 4·tan(fov_x/2)·tan(fov_y/2)) the ray directions
//! from a lens point have density 1/(A·cos³θ) per solid angle, θ from the
//! optical axis; the lens point is uniform over the aperture (area A_lens,
//! 1 for a pinhole). We = 1/(A·A_lens·cos⁴θ) makes the measurement of a
//! light path, summed over all light paths and divided by the samples per
//! pixel, the same pixel value as the camera's own samples give.

use super::{fisheye, Camera, FisheyeMap, Projection};
use crate::math::Vec3;
use crate::sampling::warp::square_to_disk_concentric;

/// A scene point seen through the lens.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LensConnection {
    /// Film position, pixels.
    pub raster: [f32; 2],
    /// The lens point, world space.
    pub lens: Vec3,
    /// We·cos θ_lens / (p_lens·d²) = 1/(A·cos³θ·d²): what a light path's
    /// throughput at the point (times its BSDF towards the lens, cosine
    /// included) is multiplied by.
    pub importance: f32,
}

impl Camera {
    /// Area of the image on the plane z = 1 of camera space.
    fn image_area(&self) -> f32 {
        4.0 * self.tan_half_x * self.tan_half_x / self.full_aspect()
    }

    /// Area of the aperture (1 for a pinhole, whose lens point is fixed).
    fn lens_area(&self) -> f32 {
        if self.aperture_radius > 0.0 {
            std::f32::consts::PI * self.aperture_radius * self.aperture_radius
        } else {
            1.0
        }
    }

    /// A fisheye's film position of camera-space unit direction `d`, and
    /// the density per solid angle of its rays there.
    fn fisheye_raster(&self, map: FisheyeMap, d: Vec3) -> Option<([f32; 2], f32)> {
        let ([a, b], theta) = fisheye::film_point(map, d, self.half_fov)?;
        let (w, h) = (self.width as f32, self.height as f32);
        let half = 0.5 * w;
        let (x, y) = (half + a * half, 0.5 * h - b * half);
        if !((0.0..w).contains(&x) && (0.0..h).contains(&y)) {
            return None;
        }
        // The film's area, its half width 1, over which positions are
        // uniform (`fisheye.rs`).
        let area = 4.0 * h / w;
        Some(([x, y], fisheye::pdf(map, theta, self.half_fov, area)))
    }

    /// Film position of a camera-space direction through the lens centre,
    /// if it lands on the film.
    fn raster_of(&self, d: Vec3) -> Option<[f32; 2]> {
        if let Projection::Fisheye(map) = self.projection {
            return self.fisheye_raster(map, d.normalize()).map(|(r, _)| r);
        }
        if d.z <= 0.0 {
            return None;
        }
        // Position on the whole film, then in the crop window.
        let u = 0.5 * (1.0 - d.x / (d.z * self.tan_half_x));
        let v = 0.5 * (1.0 - d.y * self.full_aspect() / (d.z * self.tan_half_x));
        let [w, h] = self.full_size.map(|v| v as f32);
        let x = u * w - self.crop_offset[0] as f32;
        let y = v * h - self.crop_offset[1] as f32;
        ((0.0..self.width as f32).contains(&x) && (0.0..self.height as f32).contains(&y))
            .then_some([x, y])
    }

    /// Where a ray leaving lens point `o` (camera space) in direction `d`
    /// lands on the film: through the focus plane for a thin lens.
    fn raster_through(&self, o: Vec3, d: Vec3) -> Option<[f32; 2]> {
        if self.aperture_radius > 0.0 {
            if d.z <= 0.0 {
                return None;
            }
            let focus = o + d * (self.focus_distance / d.z);
            self.raster_of(focus)
        } else {
            self.raster_of(d)
        }
    }

    /// Where world direction `d` from the lens centre lands on the film
    /// (pixels), with the cosine of its angle to the optical axis; `None`
    /// off the film. (A projector is a camera run backwards.)
    pub fn raster_towards(&self, d: Vec3) -> Option<([f32; 2], f32)> {
        let dc = self.camera_from_world.vector(d).normalize();
        self.raster_of(dc).map(|r| (r, dc.z))
    }

    /// Area of the image on the plane z = 1 of camera space.
    pub fn film_plane_area(&self) -> f32 {
        self.image_area()
    }

    /// Density per solid angle of `generate_ray` leaving lens point
    /// `lens` (world) in world direction `d`; zero off the film.
    pub fn pdf_direction(&self, lens: Vec3, d: Vec3) -> f32 {
        let o = self.camera_from_world.point(lens);
        let dc = self.camera_from_world.vector(d).normalize();
        if let Projection::Fisheye(map) = self.projection {
            return self.fisheye_raster(map, dc).map_or(0.0, |(_, pdf)| pdf);
        }
        if self.raster_through(o, dc).is_none() {
            return 0.0;
        }
        let cos = dc.z;
        1.0 / (self.image_area() * cos * cos * cos)
    }

    /// Connects world point `p` to a lens point drawn with `u`: `None`
    /// when `p` is outside the view or the clip range.
    pub fn connect(&self, p: Vec3, u: [f32; 2]) -> Option<LensConnection> {
        if let Projection::Fisheye(map) = self.projection {
            // A pinhole: the importance is the rays' density per solid
            // angle over the squared distance, as the perspective
            // camera's 1/(A·cos³θ·d²) is.
            let pc = self.camera_from_world.point(p);
            let dist2 = pc.length_squared();
            let dist = dist2.sqrt();
            if !(dist >= self.near_clip && dist <= self.far_clip) {
                return None;
            }
            let (raster, pdf) = self.fisheye_raster(map, pc / dist)?;
            return Some(LensConnection {
                raster,
                lens: self.world_from_camera.point(Vec3::ZERO),
                importance: pdf / dist2,
            });
        }
        let [lx, ly] = if self.aperture_radius > 0.0 {
            square_to_disk_concentric(u)
        } else {
            [0.0, 0.0]
        };
        let o = Vec3::new(lx * self.aperture_radius, ly * self.aperture_radius, 0.0);
        let pc = self.camera_from_world.point(p);
        let to = pc - o;
        let dist2 = to.length_squared();
        if dist2.is_nan() || dist2 <= 0.0 {
            return None;
        }
        let d = to / dist2.sqrt();
        // The camera's rays run between the clip planes.
        if pc.z < self.near_clip || pc.z > self.far_clip {
            return None;
        }
        let raster = self.raster_through(o, d)?;
        let cos = d.z;
        // Distances in camera space equal world ones for the rigid camera
        // transforms scenes use.
        Some(LensConnection {
            raster,
            lens: self.world_from_camera.point(o),
            importance: 1.0 / (self.image_area() * cos * cos * cos * dist2),
        })
    }

    /// Density of a lens point per unit area.
    pub fn pdf_lens(&self) -> f32 {
        1.0 / self.lens_area()
    }
}

#[cfg(test)]
mod tests {
    use crate::camera::{Camera, FovAxis};
    use crate::math::{Transform, Vec3};

    #[test]
    fn connection_finds_the_pixel_a_camera_ray_came_from() {
        let t = Transform::look_at(
            Vec3::new(0.0, 1.0, 3.0),
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
        )
        .unwrap();
        for aperture in [0.0, 0.1] {
            let c = Camera::new(t, 64, 48, 50.0, FovAxis::X, 1e-3, 1e3, aperture, 2.5).unwrap();
            let film = [17.3, 30.8];
            let lens = [0.3, 0.7];
            let ray = c.generate_ray(film, lens);
            let p = ray.at(2.0);
            let conn = c.connect(p, lens).unwrap();
            assert!(
                (conn.raster[0] - film[0]).abs() < 1e-2 && (conn.raster[1] - film[1]).abs() < 1e-2,
                "{aperture}: {:?}",
                conn.raster
            );
            assert!((conn.lens - ray.o).length() < 0.01);
            // Behind the camera: nothing.
            let behind = c.world_from_camera.point(Vec3::new(0.0, 0.0, -1.0));
            assert!(c.connect(behind, lens).is_none());
        }
    }

    #[test]
    fn a_fisheyes_direction_density_integrates_to_the_share_of_the_film_its_circle_covers() {
        // Film positions are uniform over the square film; those outside
        // the circle draw no ray, so ∫ pdf dω = π/4 at any field of view.
        use crate::camera::FisheyeMap;
        for (map, fov) in [(FisheyeMap::Angular, 180.0), (FisheyeMap::Equisolid, 240.0)] {
            let c = Camera::fisheye(Transform::IDENTITY, [40, 40], map, fov, 1e-3, 1e3).unwrap();
            let mean = integrated_density(&c);
            assert!(
                (mean - std::f64::consts::FRAC_PI_4).abs() < 0.01,
                "{map:?}: {mean}"
            );
            // A ray's film position is found again from its direction.
            let film = [13.2, 31.7];
            let ray = c.generate_ray(film, [0.5, 0.5]);
            let conn = c.connect(ray.at(2.0), [0.5, 0.5]).unwrap();
            assert!(
                (conn.raster[0] - film[0]).abs() < 1e-3 && (conn.raster[1] - film[1]).abs() < 1e-3
            );
        }
    }

    #[test]
    fn direction_density_integrates_to_one() {
        // ∫ pdf dω over the sphere, by uniform sphere sampling.
        let c = Camera::new(
            Transform::IDENTITY,
            40,
            30,
            60.0,
            FovAxis::X,
            1e-3,
            1e3,
            0.0,
            1.0,
        )
        .unwrap();
        let mean = integrated_density(&c);
        assert!((mean - 1.0).abs() < 0.02, "{mean}");
    }

    /// ∫ pdf dω over the sphere of the camera's rays from its centre, by
    /// uniform sphere sampling on a lattice.
    fn integrated_density(c: &Camera) -> f64 {
        let n = 400_000;
        let mut sum = 0.0f64;
        for i in 0..n {
            let u = [
                (i as f32 + 0.5) / n as f32,
                ((i as f64 * 0.618_034) % 1.0) as f32,
            ];
            let d = crate::sampling::warp::square_to_uniform_sphere(u);
            sum +=
                (c.pdf_direction(Vec3::ZERO, d) / crate::sampling::warp::UNIFORM_SPHERE_PDF) as f64;
        }
        sum / n as f64
    }
}
