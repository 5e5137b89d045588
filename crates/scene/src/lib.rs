//! scotopia-scene: scene loading (the Mitsuba 3 XML loader arrives with the
//! rest of issue 3) and the named material data scenes refer to: measured
//! metal indices and dispersive glasses.

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
