//! The instruction-set levels, their detection, the process-wide choice
//! and the dispatch of kernels.

use std::sync::OnceLock;

use super::Wide;

/// The environment variable that forces a level.
pub const ENV_VAR: &str = "SCOTOPIA_SIMD";

/// An instruction-set level, from narrowest to widest (the order is the
/// derive's: a level includes those below it).
///
/// pulp has no SSE2-only kernels (its 128-bit level, `V2`, is x86-64-v2:
/// SSE4.2 and POPCNT, which gives the 32-bit multiply `pmulld` that the
/// hashes need), so the 4-lane level is [`Level::Sse42`]; a CPU with only
/// SSE2 runs [`Level::Scalar`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Level {
    /// The plain scalar code (the reference the others are tested against).
    Scalar,
    /// 4 × 32-bit lanes: SSE up to 4.2 (pulp's `V2`).
    Sse42,
    /// 8 × 32-bit lanes: AVX2 and FMA (pulp's `V3`, x86-64-v3).
    Avx2,
    /// 16 × 32-bit lanes: AVX-512 F/BW/CD/DQ/VL (pulp's `V4`, x86-64-v4).
    Avx512,
}

/// A level that cannot be used; the message names the variable and the
/// levels this CPU has.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum SimdError {
    #[error("{ENV_VAR}={value:?} is not a SIMD level; use one of: {available}")]
    Unknown { value: String, available: String },
    #[error("{ENV_VAR}={value}: this CPU lacks {value}; it has: {available}")]
    Unsupported { value: String, available: String },
}

/// A computation with a scalar form and a wide form; [`Level::run`] picks
/// one. Both must give the same results (tests compare them).
pub trait Kernel {
    type Output;
    /// The plain scalar code.
    fn scalar(self) -> Self::Output;
    /// The wide code, compiled with `W`'s instruction set enabled: what it
    /// calls must be `#[inline(always)]` to be compiled with it too.
    fn wide<W: Wide>(self, simd: W) -> Self::Output;
}

impl Level {
    /// Every level, narrowest first.
    pub const ALL: [Level; 4] = [Level::Scalar, Level::Sse42, Level::Avx2, Level::Avx512];

    /// The name `SCOTOPIA_SIMD` takes.
    pub fn name(self) -> &'static str {
        match self {
            Level::Scalar => "scalar",
            Level::Sse42 => "sse4.2",
            Level::Avx2 => "avx2",
            Level::Avx512 => "avx512",
        }
    }

    /// 32-bit lanes per register.
    pub fn lanes(self) -> usize {
        match self {
            Level::Scalar => 1,
            Level::Sse42 => 4,
            Level::Avx2 => 8,
            Level::Avx512 => 16,
        }
    }

    /// Whether this CPU can run the level.
    pub fn supported(self) -> bool {
        let t = tokens();
        match self {
            Level::Scalar => true,
            Level::Sse42 => t.sse42.is_some(),
            Level::Avx2 => t.avx2.is_some(),
            Level::Avx512 => t.avx512.is_some(),
        }
    }

    /// The levels this CPU can run, narrowest first.
    pub fn available() -> Vec<Level> {
        Self::ALL.into_iter().filter(|l| l.supported()).collect()
    }

    /// The widest level this CPU can run.
    pub fn best() -> Level {
        Self::ALL
            .into_iter()
            .rev()
            .find(|l| l.supported())
            .unwrap_or(Level::Scalar)
    }

    /// The level named `value` (as `SCOTOPIA_SIMD` takes it), if this CPU
    /// has it.
    pub fn parse(value: &str) -> Result<Level, SimdError> {
        let available = || {
            Self::available()
                .iter()
                .map(|l| l.name())
                .collect::<Vec<_>>()
                .join(", ")
        };
        let name = value.trim().to_ascii_lowercase();
        let level = match name.as_str() {
            "scalar" => Level::Scalar,
            "sse4.2" | "sse42" => Level::Sse42,
            "avx2" => Level::Avx2,
            "avx512" | "avx-512" => Level::Avx512,
            // pulp has no SSE2-only level: say so rather than "unknown".
            "sse2" => {
                return Err(SimdError::Unsupported {
                    value: "sse2 (no SSE2-only kernels exist; the 4-lane level is sse4.2)".into(),
                    available: available(),
                })
            }
            _ => {
                return Err(SimdError::Unknown {
                    value: value.into(),
                    available: available(),
                })
            }
        };
        if level.supported() {
            Ok(level)
        } else {
            Err(SimdError::Unsupported {
                value: level.name().into(),
                available: available(),
            })
        }
    }

    /// The level `SCOTOPIA_SIMD` forces, or the best when it is unset or
    /// empty.
    pub fn from_env() -> Result<Level, SimdError> {
        match std::env::var(ENV_VAR) {
            Ok(v) if !v.trim().is_empty() => Self::parse(&v),
            Ok(_) | Err(std::env::VarError::NotPresent) => Ok(Self::best()),
            Err(std::env::VarError::NotUnicode(v)) => Err(SimdError::Unknown {
                value: v.to_string_lossy().into_owned(),
                available: Self::available()
                    .iter()
                    .map(|l| l.name())
                    .collect::<Vec<_>>()
                    .join(", "),
            }),
        }
    }

    /// Fixes the process-wide level from `SCOTOPIA_SIMD` (programs call it
    /// first and report the error); returns the level in use, which is the
    /// one already fixed when [`Level::current`] ran before.
    pub fn init() -> Result<Level, SimdError> {
        let level = Self::from_env()?;
        Ok(*CURRENT.get_or_init(|| level))
    }

    /// The process-wide level: `SCOTOPIA_SIMD`'s, or the best when it is
    /// unset, or invalid and [`Level::init`] was not called to report it.
    #[inline]
    pub fn current() -> Level {
        *CURRENT.get_or_init(|| Self::from_env().unwrap_or_else(|_| Self::best()))
    }

    /// Runs `kernel` at this level, or at the widest level below it that
    /// the CPU has (so a level made by hand cannot fault).
    #[inline]
    pub fn run<K: Kernel>(self, kernel: K) -> K::Output {
        #[cfg(target_arch = "x86_64")]
        {
            let t = tokens();
            if self >= Level::Avx512 {
                if let Some(s) = t.avx512 {
                    return pulp::Simd::vectorize(s, At(s, kernel));
                }
            }
            if self >= Level::Avx2 {
                if let Some(s) = t.avx2 {
                    return pulp::Simd::vectorize(s, At(s, kernel));
                }
            }
            if self >= Level::Sse42 {
                if let Some(s) = t.sse42 {
                    return pulp::Simd::vectorize(s, At(s, kernel));
                }
            }
        }
        kernel.scalar()
    }
}

impl std::fmt::Display for Level {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

static CURRENT: OnceLock<Level> = OnceLock::new();

/// pulp's proof that the CPU has each instruction set, detected once.
#[derive(Clone, Copy)]
struct Tokens {
    #[cfg(target_arch = "x86_64")]
    sse42: Option<pulp::x86::V2>,
    #[cfg(target_arch = "x86_64")]
    avx2: Option<pulp::x86::V3>,
    #[cfg(target_arch = "x86_64")]
    avx512: Option<pulp::x86::V4>,
    #[cfg(not(target_arch = "x86_64"))]
    sse42: Option<()>,
    #[cfg(not(target_arch = "x86_64"))]
    avx2: Option<()>,
    #[cfg(not(target_arch = "x86_64"))]
    avx512: Option<()>,
}

#[inline]
fn tokens() -> &'static Tokens {
    static TOKENS: OnceLock<Tokens> = OnceLock::new();
    TOKENS.get_or_init(|| {
        #[cfg(target_arch = "x86_64")]
        {
            Tokens {
                sse42: pulp::x86::V2::try_new(),
                avx2: pulp::x86::V3::try_new(),
                avx512: pulp::x86::V4::try_new(),
            }
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            Tokens {
                sse42: None,
                avx2: None,
                avx512: None,
            }
        }
    })
}

/// A kernel bound to the level `W` it runs at: pulp enables `W`'s
/// features around `with_simd`, which hands the kernel `W` itself.
#[cfg(target_arch = "x86_64")]
struct At<W, K>(W, K);

#[cfg(target_arch = "x86_64")]
impl<W: Wide, K: Kernel> pulp::WithSimd for At<W, K> {
    type Output = K::Output;
    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _: S) -> K::Output {
        self.1.wide(self.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn levels_parse_and_report_what_the_cpu_has() {
        assert!(Level::Scalar.supported());
        assert_eq!(Level::parse("scalar"), Ok(Level::Scalar));
        assert_eq!(Level::parse(" AVX2 ").is_ok(), Level::Avx2.supported());
        let best = Level::best();
        assert_eq!(Level::parse(best.name()), Ok(best));
        assert_eq!(*Level::available().last().unwrap(), best);
        // A bad value names the variable and the levels available.
        let e = Level::parse("avx9000").unwrap_err().to_string();
        assert!(e.contains(ENV_VAR) && e.contains("scalar"), "{e}");
        let e = Level::parse("sse2").unwrap_err().to_string();
        assert!(e.contains("sse4.2"), "{e}");
        for l in Level::ALL {
            if !l.supported() {
                let e = Level::parse(l.name()).unwrap_err().to_string();
                assert!(e.contains("lacks"), "{e}");
            }
        }
    }

    struct Lanes;
    impl Kernel for Lanes {
        type Output = usize;
        fn scalar(self) -> usize {
            1
        }
        fn wide<W: Wide>(self, _: W) -> usize {
            W::LANES
        }
    }

    #[test]
    fn run_uses_the_level_or_the_widest_below_it() {
        for l in Level::ALL {
            let want = Level::ALL
                .into_iter()
                .filter(|m| *m <= l && m.supported())
                .max()
                .unwrap();
            assert_eq!(l.run(Lanes), want.lanes(), "{l}");
        }
    }
}
