//! Rendering a scene onto the film: the options (`options.rs`), the
//! per-scene state the integrators share (`renderer.rs`) and the pass
//! driver (`driver.rs`).

mod bdpt;
mod direct;
mod driver;
mod equiangular;
mod light_choice;
mod measure;
mod options;
mod path;
mod reflectors;
mod renderer;
mod select;
mod volume;
mod wavefront;

pub use bdpt::Splat;
pub use driver::{render, render_with, Checkpointing, Hooks, Observer, Rendered, RunFacts};
pub use light_choice::LightChoice;
pub use measure::{measure, Measured, Receiver};
pub use options::{
    checkpoint_interval, time_limit, BdptStrategy, ClusterSize, OptionError, Quantity, RenderError,
    RenderOptions, Shard, Tracer, CLUSTER_SIZES, MAX_TIME_LIMIT_SECONDS,
};
pub use path::CameraSample;
pub use reflectors::Reflectors;
pub use renderer::Renderer;
pub use select::{Bidirectional, Integrator};
