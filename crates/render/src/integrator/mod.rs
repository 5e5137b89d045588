//! Rendering a scene onto the film.
//!
//! - `options.rs`: what a render is asked for, each option parsed from and
//!   printed to its text;
//! - `select.rs`: the integrator chosen from the scene and the options,
//!   each variant with its own state (`Integrator`);
//! - `renderer.rs`: the per-scene state every sample shares (`Renderer`)
//!   and a pass of samples over the film;
//! - `driver.rs`: passes until done, checkpoints, shards, the observer and
//!   time limits, knowing nothing of any integrator's insides;
//! - the integrators: `path.rs` (surfaces in clear air), `wavefront/` (the
//!   same paths in batches), `volume.rs` (media), `bdpt/` (bidirectional),
//!   `measure.rs` (illuminance at virtual receivers);
//! - what they share: `direct.rs` (next-event estimation, shadow rays and
//!   their transmittance, MIS), `light_choice/` (which light a path
//!   samples), `reflectors.rs` (aiming diffuse bounces at lamp-lit glossy
//!   surfaces), `manifold/` (light through glass balls to diffuse points:
//!   manifold next-event estimation), `equiangular.rs` (distances aimed at lights in media) and
//!   `guided.rs` (bounces drawn from the learned light field, `guiding`).

mod bdpt;
mod direct;
mod driver;
mod equiangular;
mod guided;
mod halo;
mod learn;
mod light_choice;
mod manifold;
mod measure;
mod options;
mod pass;
mod path;
mod reflectors;
mod renderer;
mod select;
mod volume;
mod wavefront;

pub use bdpt::Splat;
pub use driver::{
    render, render_with, Checkpointing, GuideFacts, Hooks, Observer, Rendered, RunFacts,
};
pub use light_choice::LightChoice;
pub use measure::{
    lights_at_eye, measure, measure_setup, measure_with, AtEye, GridPoint, Measured, Receiver,
    ReceiverShape, Road, RoadError, Setup, EYE_HEIGHT, OBSERVER_DISTANCE,
};
pub use options::{
    checkpoint_interval, time_limit, BdptStrategy, ClusterSize, Guiding, OptionError, Quantity,
    RenderError, RenderOptions, Shard, Tracer, CLUSTER_SIZES, MAX_TIME_LIMIT_SECONDS,
};
pub use path::CameraSample;
pub use reflectors::Reflectors;
pub use renderer::Renderer;
pub use select::{Bidirectional, Integrator};
