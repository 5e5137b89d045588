//! What a render is asked for beyond the scene: the options, their
//! errors and the time limit. Each option a user names in text parses
//! from it (`FromStr`) and prints back to the same text (`Display`), and
//! is checked here, so that the CLI and Python only pass strings through
//! and report the errors.

use std::fmt;
use std::str::FromStr;
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
    /// Wavelengths per path.
    pub cluster: ClusterSize,
    /// Also accumulate spectral radiance in this many bands.
    pub bands: Option<usize>,
    /// The integrator (the scene's when `None`).
    pub integrator: Option<IntegratorKind>,
    /// Bidirectional only: render this strategy alone, without MIS (a
    /// check that each strategy converges to the same image).
    pub only_strategy: Option<BdptStrategy>,
    /// Which tracer runs the path integrator.
    pub tracer: Tracer,
    /// What each pixel holds: the radiance reaching the camera, or the
    /// illuminance at the first surface the pixel sees.
    pub quantity: Quantity,
    /// Render only part of the work (distributed rendering): the film
    /// holds that part's raw sums, to be merged with the others'.
    pub shard: Option<Shard>,
    /// Whether bounces draw directions from the light learned while
    /// rendering (`guiding`).
    pub guiding: Guiding,
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
    /// As [`Quantity::Illuminance`], with the melanopic equivalent
    /// daylight (D65) illuminance of CIE S 026 (lx) in place of V′: the
    /// EXR's fourth channel is `mEDI` (`scotopia_color::alpha_opic`).
    MelanopicEdi,
}

impl Quantity {
    /// `radiance`, `illuminance` or `melanopic-edi`.
    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "radiance" => Some(Self::Radiance),
            "illuminance" => Some(Self::Illuminance),
            "melanopic-edi" => Some(Self::MelanopicEdi),
            _ => None,
        }
    }

    /// Its name, as `from_name` reads it and the EXR's metadata says.
    pub fn name(self) -> &'static str {
        match self {
            Self::Radiance => "radiance",
            Self::Illuminance => "illuminance",
            Self::MelanopicEdi => "melanopic-edi",
        }
    }

    /// Whether its pixels are illuminances at the surfaces seen.
    pub fn at_surfaces(self) -> bool {
        self != Self::Radiance
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

    /// Its name, as `from_name` reads it.
    pub fn name(self) -> &'static str {
        match self {
            Self::Wavefront => "wavefront",
            Self::Scalar => "scalar",
        }
    }
}

/// Path guiding (`crate::guiding`): bounces in the path and volume path
/// tracers draw half their directions from the light field learned in the
/// first 16 samples per pixel.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Guiding {
    #[default]
    Off,
    On,
}

impl Guiding {
    /// `on` or `off`.
    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "on" => Some(Self::On),
            "off" => Some(Self::Off),
            _ => None,
        }
    }

    /// Its name, as `from_name` reads it.
    pub fn name(self) -> &'static str {
        match self {
            Self::On => "on",
            Self::Off => "off",
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
            cluster: ClusterSize::default(),
            bands: None,
            integrator: None,
            only_strategy: None,
            tracer: Tracer::default(),
            quantity: Quantity::default(),
            shard: None,
            guiding: Guiding::default(),
        }
    }
}

/// Wavelengths per path, one of `CLUSTER_SIZES`: the renderer is
/// compiled for those alone. An enum so that no other size can be made
/// and a match on it needs no arm for one.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum ClusterSize {
    K1,
    K2,
    #[default]
    K4,
    K8,
    K16,
}

impl ClusterSize {
    /// Every size, in the order of `CLUSTER_SIZES`.
    pub const ALL: [Self; 5] = [Self::K1, Self::K2, Self::K4, Self::K8, Self::K16];

    /// The number of wavelengths.
    pub fn get(self) -> usize {
        match self {
            Self::K1 => 1,
            Self::K2 => 2,
            Self::K4 => 4,
            Self::K8 => 8,
            Self::K16 => 16,
        }
    }
}

impl TryFrom<usize> for ClusterSize {
    type Error = OptionError;

    fn try_from(k: usize) -> Result<Self, OptionError> {
        Self::ALL
            .into_iter()
            .find(|c| c.get() == k)
            .ok_or_else(|| OptionError::Cluster(k.to_string()))
    }
}

/// A bidirectional strategy rendered alone (`--bdpt-strategy S,T`): S
/// light and T camera vertices. T = 1 is light tracing; a path needs two
/// vertices, so T ≥ 1 and S + T ≥ 2. Its counts are private, so that
/// only `new` (or parsing) makes one.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct BdptStrategy {
    s: usize,
    t: usize,
}

impl BdptStrategy {
    pub fn new(s: usize, t: usize) -> Result<Self, OptionError> {
        if t >= 1 && s + t >= 2 {
            Ok(Self { s, t })
        } else {
            Err(OptionError::Strategy(s, t))
        }
    }

    /// Light vertices.
    pub fn s(self) -> usize {
        self.s
    }

    /// Camera vertices.
    pub fn t(self) -> usize {
        self.t
    }

    /// [S, T], as the bidirectional tracer takes it.
    pub fn pair(self) -> [usize; 2] {
        [self.s, self.t]
    }
}

/// Why the text of an option is none of its values: the message users
/// see (the CLI names the flag before it).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum OptionError {
    #[error("'{given}' is not {what}: use {choices}")]
    Name {
        what: &'static str,
        given: String,
        choices: &'static str,
    },
    #[error("cluster size {0} is not supported (use one of 1, 2, 4, 8, 16)")]
    Cluster(String),
    #[error("'{0}': give two counts S,T, e.g. 2,1")]
    StrategyText(String),
    #[error("strategy s={0}, t={1} does not exist (t ≥ 1, s + t ≥ 2)")]
    Strategy(usize, usize),
}

/// `FromStr` and `Display` of an option named by a word: `name` prints
/// it, `from_name` reads it, `what` and `choices` explain a wrong one.
macro_rules! named_option {
    ($type:ty, $what:literal, $choices:literal) => {
        impl FromStr for $type {
            type Err = OptionError;

            fn from_str(text: &str) -> Result<Self, OptionError> {
                <$type>::from_name(text).ok_or_else(|| OptionError::Name {
                    what: $what,
                    given: text.to_string(),
                    choices: $choices,
                })
            }
        }

        impl fmt::Display for $type {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str(self.name())
            }
        }
    };
}

named_option!(
    Quantity,
    "a quantity",
    "radiance, illuminance or melanopic-edi"
);
named_option!(Tracer, "a tracer", "wavefront or scalar");
named_option!(Guiding, "a guiding setting", "on or off");
named_option!(
    WavelengthStrategy,
    "a wavelength strategy",
    "swc, hero or single"
);
named_option!(IntegratorKind, "an integrator", "path or bdpt");

impl FromStr for ClusterSize {
    type Err = OptionError;

    fn from_str(text: &str) -> Result<Self, OptionError> {
        let k = text
            .trim()
            .parse::<usize>()
            .map_err(|_| OptionError::Cluster(format!("'{text}'")))?;
        Self::try_from(k)
    }
}

impl fmt::Display for ClusterSize {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.get())
    }
}

impl FromStr for BdptStrategy {
    type Err = OptionError;

    /// `S,T`, spaces allowed around either count.
    fn from_str(text: &str) -> Result<Self, OptionError> {
        let bad = || OptionError::StrategyText(text.to_string());
        let (s, t) = text.split_once(',').ok_or_else(bad)?;
        let count = |v: &str| v.trim().parse::<usize>().map_err(|_| bad());
        Self::new(count(s)?, count(t)?)
    }
}

impl fmt::Display for BdptStrategy {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{},{}", self.s, self.t)
    }
}

/// Errors in the options.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RenderError {
    #[error("samples per pixel must be positive")]
    Spp,
    #[error("spectral bands must number 1 to 471 (at least 1 nm wide)")]
    Bands,
    /// A strategy asked of another integrator than bdpt.
    #[error("strategy s={}, t={} needs --integrator bdpt", .0.s, .0.t)]
    Strategy(BdptStrategy),
    #[error("the wavefront tracer runs the path tracer between surfaces only, not {0}: render with the scalar tracer")]
    Wavefront(&'static str),
    #[error("path guiding serves the scalar path, volume path and bidirectional tracers' radiance, not {0}: render with --guiding off")]
    Guiding(&'static str),
    #[error("the bidirectional tracer needs a perspective, thin-lens or fisheye camera (an orthographic camera cannot be reached from a light); render with path")]
    BdptProjection,
    #[error("{0}")]
    TooLarge(Box<scotopia_image::TooLarge>),
    #[error("{0}")]
    Checkpoint(String),
    #[error("receiver {0}: its point and normal must be finite and the normal not zero")]
    Receiver(usize),
    #[error("receiver {0}: a semi-cylinder faces across its axis, and this normal lies along it")]
    Facing(usize),
    #[error("the cylinders' axis must be finite and not zero")]
    Axis,
    #[error("the observer must be a finite point")]
    Observer,
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

/// The longest interval between checkpoints accepted, seconds.
pub const MAX_CHECKPOINT_SECONDS: f64 = 1e9;

/// An interval between checkpoints of `seconds` (0: at every pass), or
/// why it cannot be one.
pub fn checkpoint_interval(seconds: f64) -> Result<Duration, String> {
    if seconds.is_finite() && (0.0..=MAX_CHECKPOINT_SECONDS).contains(&seconds) {
        Ok(Duration::from_secs_f64(seconds))
    } else {
        Err(format!("{seconds}: give 0 to 1e9 seconds"))
    }
}

#[cfg(test)]
mod text_tests {
    use super::*;

    /// Every value prints to text that parses back to it.
    fn round_trips<T>(values: impl IntoIterator<Item = T>)
    where
        T: FromStr<Err = OptionError> + fmt::Display + PartialEq + fmt::Debug,
    {
        for v in values {
            let text = v.to_string();
            assert_eq!(text.parse::<T>(), Ok(v), "{text}");
        }
    }

    #[test]
    fn every_option_prints_to_the_text_it_reads() {
        round_trips([
            Quantity::Radiance,
            Quantity::Illuminance,
            Quantity::MelanopicEdi,
        ]);
        round_trips([Tracer::Wavefront, Tracer::Scalar]);
        round_trips([Guiding::On, Guiding::Off]);
        round_trips(WavelengthStrategy::ALL);
        round_trips(IntegratorKind::ALL);
        round_trips(ClusterSize::ALL);
        assert_eq!(ClusterSize::ALL.map(ClusterSize::get), CLUSTER_SIZES);
        for k in CLUSTER_SIZES {
            assert_eq!(ClusterSize::try_from(k).map(ClusterSize::get), Ok(k));
        }
        round_trips([[0, 2], [1, 1], [2, 1], [3, 4]].map(|[s, t]| BdptStrategy { s, t }));
        assert_eq!(Quantity::default().to_string(), "radiance");
        assert_eq!(Tracer::default().to_string(), "scalar");
        assert_eq!(ClusterSize::default().to_string(), "4");
        assert_eq!(" 2, 1".parse(), Ok(BdptStrategy { s: 2, t: 1 }));
    }

    #[test]
    fn wrong_values_say_what_to_use() {
        let e = |r: Result<(), OptionError>| r.unwrap_err().to_string();
        assert_eq!(
            e("light".parse::<IntegratorKind>().map(drop)),
            "'light' is not an integrator: use path or bdpt"
        );
        assert!(
            e("rgb".parse::<WavelengthStrategy>().map(drop)).contains("use swc, hero or single")
        );
        assert!(e("gpu".parse::<Tracer>().map(drop)).contains("use wavefront or scalar"));
        assert!(e("lux".parse::<Quantity>().map(drop))
            .contains("use radiance, illuminance or melanopic-edi"));
        for bad in ["3", "0", "32", "four", "-4"] {
            let m = e(bad.parse::<ClusterSize>().map(drop));
            assert!(m.contains("use one of 1, 2, 4, 8, 16"), "{bad}: {m}");
        }
        assert!(e(ClusterSize::try_from(3).map(drop)).starts_with("cluster size 3 "));
        for bad in ["2", "2,1,0", "a,b", "-1,2", ""] {
            let m = e(bad.parse::<BdptStrategy>().map(drop));
            assert!(m.contains("give two counts S,T"), "{bad}: {m}");
        }
        for bad in ["0,0", "1,0", "2,0", "0,1"] {
            let m = e(bad.parse::<BdptStrategy>().map(drop));
            assert!(m.contains("does not exist"), "{bad}: {m}");
        }
    }
}

#[cfg(test)]
mod time_limit_tests {
    use super::*;

    #[test]
    fn checkpoint_intervals_out_of_range_are_errors_not_panics() {
        assert_eq!(checkpoint_interval(0.0), Ok(Duration::ZERO));
        assert_eq!(checkpoint_interval(60.0), Ok(Duration::from_secs(60)));
        for t in [-1.0, 2e9, f64::NAN, f64::INFINITY] {
            assert!(
                checkpoint_interval(t)
                    .unwrap_err()
                    .contains("give 0 to 1e9"),
                "{t}"
            );
        }
    }

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
