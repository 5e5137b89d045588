//! A scene ready to render: camera, film settings, geometry with its
//! materials and emitters, and lights.

use crate::accel::Aggregate;
use crate::bsdf::Bsdf;
use crate::camera::{Camera, IrradianceMeter};
use crate::light::Light;
use crate::medium::{Medium, ShapeMedia};

/// The film's filter, named here too: a scene file sets it.
pub use crate::film::Filter;

/// Which light transport algorithm renders the scene.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum IntegratorKind {
    /// Unidirectional path tracing with next-event estimation.
    #[default]
    Path,
    /// Bidirectional path tracing with MIS over every strategy.
    Bdpt,
}

impl IntegratorKind {
    pub const ALL: [IntegratorKind; 2] = [Self::Path, Self::Bdpt];

    /// The name in scene files and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Self::Path => "path",
            Self::Bdpt => "bdpt",
        }
    }

    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|k| k.name() == name.trim())
    }
}

/// Integrator settings read from the scene.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IntegratorSettings {
    pub kind: IntegratorKind,
    /// Longest path; −1 is unlimited (Mitsuba's convention).
    pub max_depth: i32,
    /// Depth from which Russian roulette starts.
    pub rr_depth: i32,
    /// Bidirectional: whether lights at infinity aim part of their light
    /// subpaths at the shapes that cast caustics (`light::emit_disk`).
    /// Always on when a scene is read; off only to check that it leaves
    /// the image's expectation as it was.
    pub aim_at_casters: bool,
    /// Whether participating media are traced (Mitsuba's `volpath`):
    /// then null surfaces bound media, neither counting towards
    /// `max_depth` nor blocking shadow rays. Mitsuba's `path` ignores
    /// media, and so does scotopia's.
    pub media: bool,
}

#[derive(Debug, Clone)]
pub struct Scene {
    /// The film's size; its rays unless `meter` is set.
    pub camera: Camera,
    /// An irradiancemeter measures instead of the camera: the image is its
    /// one value, the illuminance over its shape.
    pub meter: Option<IrradianceMeter>,
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
    /// Participating media (traced when `integrator.media`).
    pub media: Vec<Medium>,
    /// The media inside and outside each shape (empty: all vacuum).
    pub shape_media: Vec<ShapeMedia>,
    /// The medium the camera sits in.
    pub camera_medium: Option<u32>,
    /// What the loader ignored or approximated, one line each.
    pub warnings: Vec<String>,
}
