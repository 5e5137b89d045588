//! Which integrator a render runs, chosen once from the scene and the
//! options and built with its own state: a combination the integrators do
//! not support is an error that says so (never a silent fallback to
//! another integrator).

use crate::bsdf::Bsdf;
use crate::camera::Projection;
use crate::scene::{IntegratorKind, Scene};

use super::light_choice::LightChoice;
use super::{equiangular, halo, measure, Quantity, RenderError, RenderOptions, Tracer};

/// The light transport of a render.
pub enum Integrator {
    /// Path tracing between surfaces in clear air, one path at a time
    /// (`path.rs`) or in batches run stage by stage (`wavefront/`): the
    /// same image, bit for bit.
    Path(Tracer),
    /// Path tracing through participating media and surfaces that pass
    /// light (`volume.rs`).
    VolPath(Media),
    /// Bidirectional path tracing (`bdpt/`).
    Bdpt(Bidirectional),
    /// The illuminance at the first surface each pixel sees, by the path
    /// tracer's transport at a virtual receiver there (`measure.rs`).
    Illuminance(Receivers),
    /// The scene's sensor is an irradiance meter (`measure.rs`).
    Meter(Receivers),
}

/// The volume path tracer's own state.
pub struct Media {
    /// The lights equi-angular sampling aims at.
    pub(super) targets: equiangular::Targets,
    /// The lamps whose halos bounces are drawn towards (`halo`).
    pub(super) halos: halo::Halos,
}

/// The bidirectional tracer's own state.
pub struct Bidirectional {
    /// One strategy [s, t] alone, unweighted (a check that each converges
    /// to the same image).
    pub(crate) only: Option<[usize; 2]>,
    /// Whether the subpaths are traced through media (`bdpt/media.rs`).
    pub(crate) media: bool,
}

/// The virtual receivers' state: their surface and, where the scene has
/// media, how their paths cross them.
pub struct Receivers {
    /// The white Lambertian surface of a receiver.
    pub(super) white: Bsdf,
    pub(super) media: Option<Media>,
    /// The fourth channel holds the melanopic EDI, not V′
    /// ([`Quantity::MelanopicEdi`]).
    pub(super) melanopic: bool,
}

/// Whether paths in `scene` are traced through media: its integrator
/// traces them and it has media or surfaces that pass light (null lobes,
/// which such an integrator treats as media boundaries).
fn traces_media(scene: &Scene) -> bool {
    scene.integrator.media
        && (!scene.media.is_empty() || scene.materials.iter().any(|m| m.may_pass()))
}

impl Media {
    /// The media state of `scene`, `None` where its paths are not traced
    /// through media.
    pub(super) fn of(scene: &Scene, lights: &LightChoice, scene_radius: f32) -> Option<Self> {
        traces_media(scene).then(|| {
            let lamps = (0..scene.lights.len())
                .filter_map(|i| {
                    let c = scene.lights[i].centre(&scene.geometry.shapes)?;
                    Some((c, lights.power.probability(i)))
                })
                .collect();
            let targets = equiangular::Targets::new(lamps, scene_radius);
            Self {
                halos: halo::Halos::of(&targets),
                targets,
            }
        })
    }
}

impl Receivers {
    pub(super) fn of(scene: &Scene, lights: &LightChoice, scene_radius: f32) -> Self {
        Self {
            white: measure::white(),
            media: Media::of(scene, lights, scene_radius),
            melanopic: false,
        }
    }
}

impl Integrator {
    /// The integrator `options` ask of `scene`, built with its state, and
    /// the integrator as an image's metadata reports it (the options' or
    /// the scene's; the path tracer for an irradiance meter); or why it
    /// cannot run.
    pub(super) fn new(
        scene: &Scene,
        options: &RenderOptions,
        lights: &LightChoice,
        scene_radius: f32,
    ) -> Result<(IntegratorKind, Self), RenderError> {
        // An irradiancemeter is measured by the path tracer's receiver, in lx.
        let (kind, quantity) = match scene.meter {
            Some(_) => (IntegratorKind::Path, Quantity::Illuminance),
            None => (
                options.integrator.unwrap_or(scene.integrator.kind),
                options.quantity,
            ),
        };
        if kind == IntegratorKind::Bdpt && scene.camera.projection == Projection::Orthographic {
            return Err(RenderError::BdptProjection);
        }
        // The strategy exists (`BdptStrategy`); only bdpt has strategies.
        if let Some(strategy) = options.only_strategy {
            if kind != IntegratorKind::Bdpt {
                return Err(RenderError::Strategy(strategy));
            }
        }
        let integrator = if scene.meter.is_some() {
            Self::Meter(Receivers::of(scene, lights, scene_radius))
        } else if quantity.at_surfaces() {
            Self::Illuminance(Receivers {
                melanopic: quantity == Quantity::MelanopicEdi,
                ..Receivers::of(scene, lights, scene_radius)
            })
        } else if kind == IntegratorKind::Bdpt {
            Self::Bdpt(Bidirectional {
                only: options.only_strategy.map(|s| s.pair()),
                media: traces_media(scene),
            })
        } else {
            match Media::of(scene, lights, scene_radius) {
                Some(media) => Self::VolPath(media),
                None => Self::Path(options.tracer),
            }
        };
        if options.tracer == Tracer::Wavefront {
            let refused = match integrator {
                Self::Path(_) => None,
                Self::Meter(_) => Some("an irradiance meter"),
                Self::Illuminance(_) => Some("illuminance"),
                Self::Bdpt(_) => Some("the bidirectional integrator"),
                Self::VolPath(_) => {
                    Some("participating media or surfaces that pass light (null, thin dielectrics)")
                }
            };
            if let Some(what) = refused {
                return Err(RenderError::Wavefront(what));
            }
        }
        Ok((kind, integrator))
    }

    /// What its pixels hold.
    pub fn quantity(&self) -> Quantity {
        match self {
            Self::Illuminance(r) if r.melanopic => Quantity::MelanopicEdi,
            Self::Illuminance(_) | Self::Meter(_) => Quantity::Illuminance,
            _ => Quantity::Radiance,
        }
    }

    /// The name of what runs, for messages.
    pub fn name(&self) -> &'static str {
        match self {
            Self::Path(Tracer::Scalar) => "path",
            Self::Path(Tracer::Wavefront) => "path (wavefront)",
            Self::VolPath(_) => "volpath",
            Self::Bdpt(_) => "bdpt",
            Self::Illuminance(_) => "illuminance",
            Self::Meter(_) => "irradiance meter",
        }
    }
}
