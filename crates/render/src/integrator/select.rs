//! Which integrator a render runs, chosen once from the scene and the
//! options: each variant holds only its own settings, and a combination
//! the integrators do not support is an error that says so (never a
//! silent fallback to another integrator).

use crate::camera::Projection;
use crate::scene::{IntegratorKind, Scene};

use super::bdpt::LightSpectra;
use super::{Quantity, RenderError, RenderOptions, Tracer};

/// The light transport of a render.
pub enum Integrator {
    /// Path tracing between surfaces, one path at a time (`path.rs`) or
    /// in batches run stage by stage (`wavefront/`): the same image, bit
    /// for bit.
    Path(Tracer),
    /// Path tracing through participating media and surfaces that pass
    /// light (`volume.rs`).
    VolPath,
    /// Bidirectional path tracing (`bdpt/`).
    Bdpt(Box<Bidirectional>),
    /// The illuminance at the first surface each pixel sees, by the path
    /// tracer's transport at a virtual receiver there (`measure.rs`).
    Illuminance,
    /// The scene's sensor is an irradiance meter (`measure.rs`).
    Meter,
}

/// The bidirectional tracer's own state.
pub struct Bidirectional {
    /// The lights' spectra, to choose a light by the camera's cluster.
    pub(crate) spectra: LightSpectra,
    /// One strategy [s, t] alone, unweighted (a check that each converges
    /// to the same image).
    pub(crate) only: Option<[usize; 2]>,
}

/// What the options and the scene ask for, before the integrator's state
/// is built: the integrator as reported in an image's metadata, and the
/// integrator that runs.
pub(super) struct Choice {
    pub kind: IntegratorKind,
    pub run: Run,
}

/// [`Integrator`] without its state.
#[derive(Clone, Copy, PartialEq, Eq)]
pub(super) enum Run {
    Path(Tracer),
    VolPath,
    Bdpt(Option<[usize; 2]>),
    Illuminance,
    Meter,
}

/// Whether paths in `scene` are traced through media: its integrator
/// traces them and it has media or surfaces that pass light (null lobes,
/// which such an integrator treats as media boundaries).
pub(super) fn traces_media(scene: &Scene) -> bool {
    scene.integrator.media
        && (!scene.media.is_empty() || scene.materials.iter().any(|m| m.may_pass()))
}

impl Choice {
    /// The integrator `options` ask of `scene`, or why it cannot run.
    pub fn new(scene: &Scene, options: &RenderOptions) -> Result<Self, RenderError> {
        // An irradiancemeter is measured by the path tracer's receiver, in lx.
        let (kind, quantity) = match scene.meter {
            Some(_) => (IntegratorKind::Path, Quantity::Illuminance),
            None => (
                options.integrator.unwrap_or(scene.integrator.kind),
                options.quantity,
            ),
        };
        if kind == IntegratorKind::Bdpt && scene.camera.projection != Projection::Perspective {
            return Err(RenderError::BdptProjection);
        }
        // The strategy exists (`BdptStrategy`); only bdpt has strategies.
        if let Some(strategy) = options.only_strategy {
            if kind != IntegratorKind::Bdpt {
                return Err(RenderError::Strategy(strategy));
            }
        }
        let media = traces_media(scene);
        let run = if scene.meter.is_some() {
            Run::Meter
        } else if quantity == Quantity::Illuminance {
            Run::Illuminance
        } else if kind == IntegratorKind::Bdpt {
            Run::Bdpt(options.only_strategy.map(|s| s.pair()))
        } else if media {
            Run::VolPath
        } else {
            Run::Path(options.tracer)
        };
        if options.tracer == Tracer::Wavefront && run != Run::Path(Tracer::Wavefront) {
            let what = match run {
                Run::Meter => "an irradiance meter",
                Run::Illuminance => "illuminance",
                Run::Bdpt(_) => "the bidirectional integrator",
                _ => "participating media or surfaces that pass light (null, thin dielectrics)",
            };
            return Err(RenderError::Wavefront(what));
        }
        Ok(Self { kind, run })
    }
}

impl Integrator {
    /// What its pixels hold.
    pub fn quantity(&self) -> Quantity {
        match self {
            Self::Illuminance | Self::Meter => Quantity::Illuminance,
            _ => Quantity::Radiance,
        }
    }

    /// The name of what runs, for messages.
    pub fn name(&self) -> &'static str {
        match self {
            Self::Path(Tracer::Scalar) => "path",
            Self::Path(Tracer::Wavefront) => "path (wavefront)",
            Self::VolPath => "volpath",
            Self::Bdpt(_) => "bdpt",
            Self::Illuminance => "illuminance",
            Self::Meter => "irradiance meter",
        }
    }
}
