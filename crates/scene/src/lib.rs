//! scotopia-scene: reading scene files into a `scotopia_render::scene::Scene`.
//! Parse, describe, build: `mitsuba` parses Mitsuba 3 XML into plain nodes
//! that remember file and line; `build` makes the renderer's objects from
//! them (one file per element type; `registry` records how far each
//! Mitsuba plugin is followed). What a scene refers to is read here too:
//! meshes (`mesh`: OBJ, PLY, Mitsuba's serialized), voxel grids (`volume`),
//! photometric files (`luminaire`: IES, EULUMDAT) and named materials
//! (`materials`: measured metals, dispersive glasses). `info` describes a
//! loaded scene for `scotopia info`; `checkpoint_key` is the fingerprint a
//! checkpoint is stamped with.

mod build;
mod checkpoint_key;
mod info;
pub mod luminaire;
pub mod materials;
pub mod mesh;
pub mod mitsuba;
pub mod volume;

pub use build::registry;
pub use build::{
    bsdf_from_xml, load_scene, load_scene_tracked, load_scene_with, LoadOptions, Resolution,
};
pub use checkpoint_key::{checkpoint_key, CheckpointKey};
pub use info::{CameraInfo, FilmInfo, GridInfo, LightInfo, MediumInfo, SceneInfo};
