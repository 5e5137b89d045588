//! Cameras: perspective (pinhole), thin lens and orthographic, with
//! Mitsuba 3's mapping from film position to ray, so that a scene rendered
//! by both lines up pixel for pixel; and scotopia's fisheye (`fisheye.rs`),
//! which Mitsuba has not, for glare ratings.
//!
//! Camera space (Mitsuba's): +z is the view direction, +y up, +x left. The
//! film position (x, y) runs from (0, 0) at the top-left corner of the image
//! to (width, height) at the bottom-right; a pixel (i, j) covers
//! [i, i + 1) × [j, j + 1). A crop window (Mitsuba's film `crop_*`)
//! renders a part of a larger film: the image is `width`×`height` pixels
//! from `crop_offset` of a `full_size` film whose field of view is given.

mod fisheye;
mod importance;
mod meter;

pub use fisheye::FisheyeMap;
pub use importance::LensConnection;
pub use meter::IrradianceMeter;

use crate::math::{Ray, Transform, Vec3};
use crate::sampling::warp::square_to_disk_concentric;

/// Which image axis `fov` spans (Mitsuba's `fov_axis`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FovAxis {
    X,
    Y,
    Diagonal,
    /// The smaller of the two image axes.
    Smaller,
    /// The larger of the two image axes.
    Larger,
}

impl FovAxis {
    pub fn from_name(name: &str) -> Option<Self> {
        Some(match name {
            "x" => FovAxis::X,
            "y" => FovAxis::Y,
            "diagonal" => FovAxis::Diagonal,
            "smaller" => FovAxis::Smaller,
            "larger" => FovAxis::Larger,
            _ => return None,
        })
    }
}

/// How film positions become rays.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Projection {
    /// Rays from the lens through the image plane (pinhole or thin lens).
    Perspective,
    /// Parallel rays along +z from the film rectangle x ∈ [−1, 1],
    /// y ∈ [−1/aspect, 1/aspect] of camera space (Mitsuba's
    /// `orthographic`; `to_world`'s scale sets the extent).
    Orthographic,
    /// Rays from a point in every direction of a fisheye's field
    /// (`fisheye.rs`), up to 360° across the image's width.
    Fisheye(FisheyeMap),
}

/// A perspective camera (a thin lens when `aperture_radius` > 0), or an
/// orthographic one.
#[derive(Debug, Clone, PartialEq)]
pub struct Camera {
    pub projection: Projection,
    pub world_from_camera: Transform,
    camera_from_world: Transform,
    /// The image rendered (the crop window), pixels.
    pub width: u32,
    pub height: u32,
    /// The whole film the field of view spans, pixels.
    full_size: [u32; 2],
    /// Top-left pixel of the image on the whole film.
    crop_offset: [u32; 2],
    /// tan of half the whole film's horizontal field of view.
    tan_half_x: f32,
    /// A fisheye's half field of view θm, radians (0 for the others).
    half_fov: f32,
    pub near_clip: f32,
    pub far_clip: f32,
    pub aperture_radius: f32,
    pub focus_distance: f32,
}

/// A camera that cannot be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("camera: {0}")]
pub struct CameraError(pub String);

impl Camera {
    /// A camera with field of view `fov_degrees` along `axis` over a film of
    /// `width`×`height` pixels. `aperture_radius` 0 is a pinhole.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        world_from_camera: Transform,
        width: u32,
        height: u32,
        fov_degrees: f32,
        axis: FovAxis,
        near_clip: f32,
        far_clip: f32,
        aperture_radius: f32,
        focus_distance: f32,
    ) -> Result<Self, CameraError> {
        let bad = |m: String| Err(CameraError(m));
        if width == 0 || height == 0 {
            return bad(format!("film of {width}×{height} pixels"));
        }
        if !(fov_degrees > 0.0 && fov_degrees < 180.0) {
            return bad(format!("field of view {fov_degrees}° is not in (0°, 180°)"));
        }
        if !(near_clip > 0.0 && far_clip > near_clip) {
            return bad(format!("clip range near {near_clip}, far {far_clip}"));
        }
        if !(aperture_radius >= 0.0 && aperture_radius.is_finite()) {
            return bad(format!("aperture radius {aperture_radius}"));
        }
        if aperture_radius > 0.0 && !(focus_distance > 0.0 && focus_distance.is_finite()) {
            return bad(format!("focus distance {focus_distance}"));
        }
        let aspect = width as f32 / height as f32;
        let t = (0.5 * fov_degrees.to_radians()).tan();
        // Mitsuba's fov_axis conversion to a horizontal field of view.
        let axis = match axis {
            FovAxis::Smaller if aspect > 1.0 => FovAxis::Y,
            FovAxis::Smaller => FovAxis::X,
            FovAxis::Larger if aspect > 1.0 => FovAxis::X,
            FovAxis::Larger => FovAxis::Y,
            a => a,
        };
        let tan_half_x = match axis {
            FovAxis::Y => t * aspect,
            FovAxis::Diagonal => t / (1.0 + 1.0 / (aspect * aspect)).sqrt(),
            _ => t,
        };
        Ok(Self {
            projection: Projection::Perspective,
            camera_from_world: world_from_camera.inverse(),
            world_from_camera,
            width,
            height,
            full_size: [width, height],
            crop_offset: [0, 0],
            tan_half_x,
            half_fov: 0.0,
            near_clip,
            far_clip,
            aperture_radius,
            focus_distance,
        })
    }

    /// Mitsuba's `orthographic` sensor over a `width`×`height` film.
    pub fn orthographic(
        world_from_camera: Transform,
        width: u32,
        height: u32,
        near_clip: f32,
        far_clip: f32,
    ) -> Result<Self, CameraError> {
        // tan 45° = 1 makes the perspective film mapping give x ∈ [−1, 1].
        let mut c = Self::square_pinhole(world_from_camera, [width, height], near_clip, far_clip)?;
        c.projection = Projection::Orthographic;
        Ok(c)
    }

    /// A pinhole of 90° across the width: what the orthographic and
    /// fisheye cameras start from, with the perspective camera's checks
    /// of film size and clip range.
    fn square_pinhole(
        world_from_camera: Transform,
        [width, height]: [u32; 2],
        near_clip: f32,
        far_clip: f32,
    ) -> Result<Self, CameraError> {
        Self::new(
            world_from_camera,
            width,
            height,
            90.0,
            FovAxis::X,
            near_clip,
            far_clip,
            0.0,
            1.0,
        )
    }

    /// A fisheye of projection `map` whose full field of view
    /// `fov_degrees` (up to 360°) spans the film's width, centred, with
    /// square pixels: a pinhole at the origin of `world_from_camera`
    /// looking along its +z. Its rays run from `near_clip` to `far_clip`
    /// along themselves (not between planes: they may look backwards).
    pub fn fisheye(
        world_from_camera: Transform,
        size: [u32; 2],
        map: FisheyeMap,
        fov_degrees: f32,
        near_clip: f32,
        far_clip: f32,
    ) -> Result<Self, CameraError> {
        if !(fov_degrees > 0.0 && fov_degrees <= 360.0) {
            return Err(CameraError(format!(
                "fisheye field of view {fov_degrees}° is not in (0°, 360°]"
            )));
        }
        let mut c = Self::square_pinhole(world_from_camera, size, near_clip, far_clip)?;
        c.projection = Projection::Fisheye(map);
        c.half_fov = (0.5 * fov_degrees).to_radians();
        Ok(c)
    }

    /// Renders only the window of `size` pixels at `offset` of the film
    /// (Mitsuba's `crop_offset_x/y`, `crop_width/height`).
    pub fn with_crop(mut self, offset: [u32; 2], size: [u32; 2]) -> Result<Self, CameraError> {
        if matches!(self.projection, Projection::Fisheye(_)) {
            // A glare rating needs the whole circle, and a picture's
            // projection metadata describes a whole film.
            return Err(CameraError(
                "a fisheye renders its whole film: no crop window".into(),
            ));
        }
        let [w, h] = self.full_size;
        let fits = |o: u32, s: u32, full: u32| s > 0 && o.checked_add(s).is_some_and(|e| e <= full);
        if !(fits(offset[0], size[0], w) && fits(offset[1], size[1], h)) {
            return Err(CameraError(format!(
                "crop window {}×{} at ({}, {}) does not fit the {w}×{h} film",
                size[0], size[1], offset[0], offset[1]
            )));
        }
        self.crop_offset = offset;
        [self.width, self.height] = size;
        Ok(self)
    }

    /// The whole film (before any crop), pixels.
    pub fn full_size(&self) -> [u32; 2] {
        self.full_size
    }

    /// The crop window's top-left pixel on the whole film.
    pub fn crop_offset(&self) -> [u32; 2] {
        self.crop_offset
    }

    fn full_aspect(&self) -> f32 {
        self.full_size[0] as f32 / self.full_size[1] as f32
    }

    /// Horizontal and vertical field of view of the image (the crop
    /// window's when cropped), degrees; (0, 0) for an orthographic camera,
    /// which has none.
    pub fn fov_degrees(&self) -> (f32, f32) {
        match self.projection {
            Projection::Orthographic => return (0.0, 0.0),
            Projection::Fisheye(map) => {
                // Across the width, and up the centre line to the edge
                // (or to the circle, on a film taller than wide).
                let up = (self.height as f32 / self.width as f32).min(1.0);
                let v = 2.0 * map.theta(f64::from(up), f64::from(self.half_fov)) as f32;
                return (2.0 * self.half_fov.to_degrees(), v.to_degrees());
            }
            Projection::Perspective => {}
        }
        let span = |from: f32, to: f32, full: f32, tan_half: f32| {
            // Angles of the window's edges, measured across the film.
            let edge = |p: f32| ((1.0 - 2.0 * p / full) * tan_half).atan();
            (edge(from) - edge(to)).abs().to_degrees()
        };
        let [fw, fh] = self.full_size.map(|v| v as f32);
        let [ox, oy] = self.crop_offset.map(|v| v as f32);
        (
            span(ox, ox + self.width as f32, fw, self.tan_half_x),
            span(
                oy,
                oy + self.height as f32,
                fh,
                self.tan_half_x / self.full_aspect(),
            ),
        )
    }

    /// The camera-space direction (z = 1) through film position `film`
    /// (pixels of the image, so of the crop window).
    #[inline]
    fn direction(&self, film: [f32; 2]) -> Vec3 {
        let [w, h] = self.full_size.map(|v| v as f32);
        let u = (film[0] + self.crop_offset[0] as f32) / w;
        let v = (film[1] + self.crop_offset[1] as f32) / h;
        Vec3::new(
            (1.0 - 2.0 * u) * self.tan_half_x,
            (1.0 - 2.0 * v) * self.tan_half_x / self.full_aspect(),
            1.0,
        )
    }

    /// The film point (a, b) of a fisheye (a right, b up, 1 at the half
    /// width) at film position `film` (pixels).
    #[inline]
    fn fisheye_point(&self, film: [f32; 2]) -> [f32; 2] {
        let half = 0.5 * self.width as f32;
        [
            (film[0] - half) / half,
            (0.5 * self.height as f32 - film[1]) / half,
        ]
    }

    /// The camera-space unit direction of a fisheye at film position
    /// `film`, `None` outside its circle.
    #[inline]
    fn fisheye_direction(&self, map: FisheyeMap, film: [f32; 2]) -> Option<Vec3> {
        let [a, b] = self.fisheye_point(film);
        fisheye::direction(map, a, b, self.half_fov)
    }

    /// Whether film position `film` sees the scene: false outside a
    /// fisheye's circle, whose rays carry nothing.
    #[inline]
    pub fn sees(&self, film: [f32; 2]) -> bool {
        match self.projection {
            Projection::Fisheye(map) => self.fisheye_direction(map, film).is_some(),
            _ => true,
        }
    }

    /// The world-space ray through film position `film` (pixels), with
    /// `lens` ∈ [0, 1)² choosing the point on the aperture. The ray starts at
    /// the near clip plane and ends at the far one, as in Mitsuba.
    #[inline]
    pub fn generate_ray(&self, film: [f32; 2], lens: [f32; 2]) -> Ray {
        self.generate_ray_from_lens(film, lens).0
    }

    /// `generate_ray`, and the world-space lens point the ray comes from.
    #[inline]
    pub fn generate_ray_from_lens(&self, film: [f32; 2], lens: [f32; 2]) -> (Ray, Vec3) {
        if let Projection::Fisheye(map) = self.projection {
            let origin = self.world_from_camera.point(Vec3::ZERO);
            // Outside the circle an empty ray along the axis ([`Self::sees`]).
            let (d, length) = match self.fisheye_direction(map, film) {
                Some(d) => (d, self.far_clip - self.near_clip),
                None => (Vec3::new(0.0, 0.0, 1.0), 0.0),
            };
            let world_dir = self.world_from_camera.vector(d);
            let scale = world_dir.length();
            let ray = Ray {
                o: self.world_from_camera.point(d * self.near_clip),
                d: world_dir / scale,
                t_max: length * scale,
            };
            return (ray, origin);
        }
        let d = self.direction(film);
        if self.projection == Projection::Orthographic {
            // From the film point on the near plane, along +z; Mitsuba's
            // ray length is far − near, unscaled by to_world.
            let o = self
                .world_from_camera
                .point(Vec3::new(d.x, d.y, self.near_clip));
            let dir = self.world_from_camera.vector(Vec3::new(0.0, 0.0, 1.0));
            let ray = Ray {
                o,
                d: dir.normalize(),
                t_max: self.far_clip - self.near_clip,
            };
            return (ray, o);
        }
        let (origin, dir) = if self.aperture_radius > 0.0 {
            // Thin lens: rays through every point of the aperture meet on the
            // plane z = focus_distance.
            let [lx, ly] = square_to_disk_concentric(lens);
            let o = Vec3::new(lx * self.aperture_radius, ly * self.aperture_radius, 0.0);
            let focus = d * self.focus_distance;
            (o, (focus - o).normalize())
        } else {
            (Vec3::ZERO, d.normalize())
        };
        let near = self.near_clip / dir.z;
        let far = self.far_clip / dir.z;
        let o = self.world_from_camera.point(origin + dir * near);
        let world_dir = self.world_from_camera.vector(dir);
        let scale = world_dir.length();
        (
            Ray {
                o,
                d: world_dir / scale,
                t_max: (far - near) * scale,
            },
            self.world_from_camera.point(origin),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn camera(w: u32, h: u32, fov: f32, axis: FovAxis) -> Camera {
        let t = Transform::look_at(
            Vec3::ZERO,
            Vec3::new(0.0, 0.0, -1.0),
            Vec3::new(0.0, 1.0, 0.0),
        )
        .unwrap();
        Camera::new(t, w, h, fov, axis, 1e-2, 1e4, 0.0, 1.0).unwrap()
    }

    #[test]
    fn centre_edges_and_orientation() {
        let c = camera(200, 100, 90.0, FovAxis::X);
        let centre = c.generate_ray([100.0, 50.0], [0.5, 0.5]);
        assert!((centre.d - Vec3::new(0.0, 0.0, -1.0)).length() < 1e-6);
        // The right edge of the film is 45° to the right (+x in the world,
        // looking down −z with +y up); the top edge is atan(0.5) up.
        let right = c.generate_ray([200.0, 50.0], [0.5, 0.5]).d;
        assert!(
            (right - Vec3::new(1.0, 0.0, -1.0).normalize()).length() < 1e-6,
            "{right:?}"
        );
        let top = c.generate_ray([100.0, 0.0], [0.5, 0.5]).d;
        assert!(
            (top - Vec3::new(0.0, 0.5, -1.0).normalize()).length() < 1e-6,
            "{top:?}"
        );
        let (fx, fy) = c.fov_degrees();
        assert!((fx - 90.0).abs() < 1e-4 && (fy - 2.0 * 0.5f32.atan().to_degrees()).abs() < 1e-4);
        // The ray starts on the near plane.
        assert!((centre.o - Vec3::new(0.0, 0.0, -1e-2)).length() < 1e-7);
    }

    #[test]
    fn matches_mitsuba_3() {
        use std::f32::consts::FRAC_1_SQRT_2;
        // Mitsuba 3.9.1 (scalar_spectral) `perspective`, fov 90 along x,
        // 200×100 film, near_clip 0.01, look_at (0,0,0) → (0,0,−1), up +y:
        // sensor.sample_ray(position = film / size, aperture (0.5, 0.5)).
        let c = camera(200, 100, 90.0, FovAxis::X);
        let cases = [
            (
                [0.0, 0.0],
                [-0.01, 0.005, -0.01],
                [-0.666667, 0.333333, -0.666667],
            ),
            (
                [50.0, 80.0],
                [-0.005, -0.003, -0.01],
                [-0.431934, -0.25916, -0.863868],
            ),
            (
                [200.0, 50.0],
                [0.01, 0.0, -0.01],
                [FRAC_1_SQRT_2, 0.0, -FRAC_1_SQRT_2],
            ),
        ];
        for (film, o, d) in cases {
            let r = c.generate_ray(film, [0.5, 0.5]);
            assert!((r.o - Vec3::from(o)).length() < 1e-6, "{film:?}: {:?}", r.o);
            assert!((r.d - Vec3::from(d)).length() < 1e-5, "{film:?}: {:?}", r.d);
        }
    }

    #[test]
    fn fov_axes() {
        let y = camera(200, 100, 40.0, FovAxis::Y).fov_degrees();
        assert!((y.1 - 40.0).abs() < 1e-3);
        let d = camera(300, 400, 60.0, FovAxis::Diagonal);
        let (tx, ty) = (
            (d.fov_degrees().0 / 2.0).to_radians().tan(),
            (d.fov_degrees().1 / 2.0).to_radians().tan(),
        );
        assert!(((tx * tx + ty * ty).sqrt() - 30f32.to_radians().tan()).abs() < 1e-5);
        assert!((camera(300, 400, 50.0, FovAxis::Smaller).fov_degrees().0 - 50.0).abs() < 1e-3);
        assert!((camera(300, 400, 50.0, FovAxis::Larger).fov_degrees().1 - 50.0).abs() < 1e-3);
    }

    #[test]
    fn thin_lens_focuses_on_the_focal_plane() {
        let t = Transform::IDENTITY;
        let c = Camera::new(t, 64, 64, 45.0, FovAxis::X, 1e-3, 1e3, 0.2, 3.0).unwrap();
        let film = [10.3, 50.7];
        let pinhole_dir = c.direction(film);
        let focus = pinhole_dir * 3.0;
        for lens in [[0.1, 0.9], [0.5, 0.5], [0.99, 0.01]] {
            let r = c.generate_ray(film, lens);
            let t = (focus.z - r.o.z) / r.d.z;
            assert!((r.at(t) - focus).length() < 1e-4, "{lens:?}");
        }
    }

    #[test]
    fn a_crop_window_renders_its_part_of_the_film() {
        let full = camera(200, 100, 90.0, FovAxis::X);
        let crop = camera(200, 100, 90.0, FovAxis::X)
            .with_crop([120, 30], [50, 40])
            .unwrap();
        assert_eq!((crop.width, crop.height), (50, 40));
        for film in [[0.0, 0.0], [12.5, 7.25], [50.0, 40.0]] {
            let a = crop.generate_ray(film, [0.5, 0.5]).d;
            let b = full
                .generate_ray([film[0] + 120.0, film[1] + 30.0], [0.5, 0.5])
                .d;
            assert!((a - b).length() < 1e-6, "{film:?}");
        }
        // The window's field: from 20 px right of centre to 70 px, of a
        // film whose half width (100 px) spans tan 45° = 1.
        let fx = (0.7f32.atan() - 0.2f32.atan()).to_degrees();
        assert!((crop.fov_degrees().0 - fx).abs() < 1e-4);
        assert!(camera(20, 10, 45.0, FovAxis::X)
            .with_crop([15, 0], [6, 10])
            .is_err());
        assert!(camera(20, 10, 45.0, FovAxis::X)
            .with_crop([0, 0], [0, 10])
            .is_err());
    }

    #[test]
    fn orthographic_rays_are_parallel_from_the_film_rectangle() {
        // Mitsuba 3's orthographic: x ∈ [−1, 1] (left edge at +1), y ∈
        // [−1/aspect, 1/aspect], rays along +z, scaled by to_world.
        let t = Transform::scale(Vec3::new(2.0, 2.0, 1.0)).unwrap();
        let c = Camera::orthographic(t, 200, 100, 1e-2, 1e4).unwrap();
        let corner = c.generate_ray([0.0, 0.0], [0.5, 0.5]);
        assert!(
            (corner.o - Vec3::new(2.0, 1.0, 1e-2)).length() < 1e-6,
            "{:?}",
            corner.o
        );
        let centre = c.generate_ray([100.0, 50.0], [0.3, 0.9]);
        assert!((centre.o - Vec3::new(0.0, 0.0, 1e-2)).length() < 1e-6);
        assert_eq!(centre.d, Vec3::new(0.0, 0.0, 1.0));
        assert_eq!(corner.d, centre.d);
        assert!((centre.t_max - (1e4 - 1e-2)).abs() < 1e-3);
        assert_eq!(c.fov_degrees(), (0.0, 0.0));
    }

    #[test]
    fn bad_parameters_are_errors() {
        let t = Transform::IDENTITY;
        assert!(Camera::new(t, 0, 10, 45.0, FovAxis::X, 0.1, 10.0, 0.0, 1.0).is_err());
        assert!(Camera::new(t, 10, 10, 180.0, FovAxis::X, 0.1, 10.0, 0.0, 1.0).is_err());
        assert!(Camera::new(t, 10, 10, 45.0, FovAxis::X, 1.0, 0.5, 0.0, 1.0).is_err());
        assert!(Camera::new(t, 10, 10, 45.0, FovAxis::X, 0.1, 10.0, 0.1, 0.0).is_err());
        assert!(Camera::new(t, 10, 10, f32::NAN, FovAxis::X, 0.1, 10.0, 0.0, 1.0).is_err());
    }
}
