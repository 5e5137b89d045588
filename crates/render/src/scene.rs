//! A scene ready to render: camera, film settings, geometry with its
//! materials and emitters, and lights.

use crate::accel::Aggregate;
use crate::bsdf::Bsdf;
use crate::camera::Camera;
use crate::light::Light;

/// The film's reconstruction filter (Mitsuba's `rfilter`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Filter {
    Box,
    Gaussian { stddev: f32 },
}

/// Integrator settings read from the scene.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IntegratorSettings {
    /// Longest path; −1 is unlimited (Mitsuba's convention).
    pub max_depth: i32,
    /// Depth from which Russian roulette starts.
    pub rr_depth: i32,
}

#[derive(Debug, Clone)]
pub struct Scene {
    pub camera: Camera,
    pub filter: Filter,
    pub samples_per_pixel: u32,
    pub integrator: IntegratorSettings,
    pub geometry: Aggregate,
    pub materials: Vec<Bsdf>,
    /// Material of each shape.
    pub shape_material: Vec<u32>,
    /// Area light of each shape, if it emits.
    pub shape_light: Vec<Option<u32>>,
    pub lights: Vec<Light>,
    /// What the loader ignored or approximated, one line each.
    pub warnings: Vec<String>,
}
