//! What a render is asked for beyond the scene: the options, their
//! errors and the time limit.

use std::time::Duration;

use crate::scene::IntegratorKind;
use crate::wavelength::WavelengthStrategy;

/// Cluster sizes K the renderer is compiled for.
pub const CLUSTER_SIZES: [usize; 5] = [1, 2, 4, 8, 16];

/// What to render, beyond the scene.
#[derive(Debug, Clone, PartialEq)]
pub struct RenderOptions {
    /// Samples per pixel (the scene's when `None`).
    pub spp: Option<u32>,
    /// Stop after this long, even before `spp` is reached.
    pub time_limit: Option<Duration>,
    pub seed: u32,
    pub strategy: WavelengthStrategy,
    /// Wavelengths per path, one of `CLUSTER_SIZES`.
    pub cluster: usize,
    /// Also accumulate spectral radiance in this many bands.
    pub bands: Option<usize>,
    /// The integrator (the scene's when `None`).
    pub integrator: Option<IntegratorKind>,
    /// Bidirectional only: render strategy [s, t] alone, without MIS (a
    /// check that each strategy converges to the same image).
    pub only_strategy: Option<[usize; 2]>,
    /// Which tracer runs the path integrator.
    pub tracer: Tracer,
    /// What each pixel holds: the radiance reaching the camera, or the
    /// illuminance at the first surface the pixel sees.
    pub quantity: Quantity,
    /// Render only part of the work (distributed rendering): the film
    /// holds that part's raw sums, to be merged with the others'.
    pub shard: Option<Shard>,
}

/// A part of a render: sample indices `samples` of the pixels in `rows`
/// (all rows if `None`). A pixel's random numbers depend only on (seed,
/// pixel, index), so shards merged by adding their sums give the whole
/// render: bit for bit when each pixel's samples are in one shard (its
/// sum is the same additions in the same order), else within f64
/// rounding (the sums are added in another order).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Shard {
    pub samples: std::ops::Range<u32>,
    pub rows: Option<std::ops::Range<u32>>,
}

/// What a render measures at each pixel.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Quantity {
    /// X, Y, Z (cd/m²) and V′ (scotopic cd/m²) of the light reaching the
    /// camera.
    #[default]
    Radiance,
    /// X, Y, Z (Y in lx) and V′ (scotopic lx) of the light falling on the
    /// first surface each pixel sees, on the side facing the camera (the
    /// path tracer's own transport at a virtual receiver there,
    /// `measure.rs`); zero where the pixel sees no surface.
    Illuminance,
}

impl Quantity {
    /// `radiance` or `illuminance`.
    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "radiance" => Some(Self::Radiance),
            "illuminance" => Some(Self::Illuminance),
            _ => None,
        }
    }

    /// Its name, as `from_name` reads it and the EXR's metadata says.
    pub fn name(self) -> &'static str {
        match self {
            Self::Radiance => "radiance",
            Self::Illuminance => "illuminance",
        }
    }
}

/// The two forms of the path tracer: one path at a time (the reference)
/// or batches of paths run stage by stage (`wavefront`). They give the
/// same image, bit for bit; the bidirectional tracer has one form. The
/// scalar one is the default while it is the faster (docs/performance.md:
/// the wavefront's stages are not yet vectorised beyond its samplers).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Tracer {
    Wavefront,
    #[default]
    Scalar,
}

impl Tracer {
    /// `wavefront` or `scalar`.
    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "wavefront" => Some(Self::Wavefront),
            "scalar" => Some(Self::Scalar),
            _ => None,
        }
    }
}

impl Default for RenderOptions {
    fn default() -> Self {
        Self {
            spp: None,
            time_limit: None,
            seed: 0,
            strategy: WavelengthStrategy::Swc,
            cluster: 4,
            bands: None,
            integrator: None,
            only_strategy: None,
            tracer: Tracer::default(),
            quantity: Quantity::default(),
            shard: None,
        }
    }
}

/// Errors in the options.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RenderError {
    #[error("cluster size {0} is not supported (use one of 1, 2, 4, 8, 16)")]
    Cluster(usize),
    #[error("samples per pixel must be positive")]
    Spp,
    #[error("spectral bands must number 1 to 471 (at least 1 nm wide)")]
    Bands,
    #[error("strategy s={0}, t={1} does not exist (t ≥ 1, s + t ≥ 2) or needs --integrator bdpt")]
    Strategy(usize, usize),
    #[error("the wavefront tracer runs the path tracer between surfaces only, not {0}: render with the scalar tracer")]
    Wavefront(&'static str),
    #[error("the bidirectional tracer needs a perspective or thin-lens camera (an orthographic camera cannot be reached from a light); render with path")]
    BdptProjection,
    #[error("{0}")]
    TooLarge(Box<scotopia_image::TooLarge>),
    #[error("{0}")]
    Checkpoint(String),
    #[error("receiver {0}: its point and normal must be finite and the normal not zero")]
    Receiver(usize),
}

/// The longest time limit accepted, seconds (≈ 31.7 years): longer ones
/// would overflow the clock's arithmetic, and no render is meant to last
/// them.
pub const MAX_TIME_LIMIT_SECONDS: f64 = 1e9;

/// A render time limit of `seconds`, or why it cannot be one (not a
/// positive finite number, or over `MAX_TIME_LIMIT_SECONDS`).
pub fn time_limit(seconds: f64) -> Result<Duration, String> {
    if !(seconds.is_finite() && seconds > 0.0) {
        return Err(format!("{seconds}: must be a positive number of seconds"));
    }
    if seconds > MAX_TIME_LIMIT_SECONDS {
        return Err(format!(
            "{seconds:e}: must be at most {MAX_TIME_LIMIT_SECONDS:e} seconds (about 31 years)"
        ));
    }
    Duration::try_from_secs_f64(seconds).map_err(|e| format!("{seconds}: {e}"))
}

#[cfg(test)]
mod time_limit_tests {
    use super::*;

    #[test]
    fn time_limits_out_of_range_are_errors_not_panics() {
        assert_eq!(time_limit(2.5), Ok(Duration::from_millis(2500)));
        assert!(time_limit(MAX_TIME_LIMIT_SECONDS).is_ok());
        for t in [1e20, 1e30, f64::INFINITY] {
            let e = time_limit(t).unwrap_err();
            assert!(e.contains("at most") || e.contains("positive"), "{t}: {e}");
        }
        for t in [0.0, -1.0, f64::NAN, f64::NEG_INFINITY] {
            assert!(time_limit(t).unwrap_err().contains("positive"), "{t}");
        }
    }
}
