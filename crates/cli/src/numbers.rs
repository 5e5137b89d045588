//! Parsers for the numeric flags, run by clap: a value out of range is a
//! usage error (exit code 2) naming the flag, before any work starts.

use std::time::Duration;

use scotopia_vision::screen::ABSURD_LUMINANCE;
use scotopia_vision::Observer;

/// The most worker threads `--threads` accepts.
pub const MAX_THREADS: usize = 4096;

/// `--time`: positive, finite, at most `MAX_TIME_LIMIT_SECONDS`.
pub fn seconds(text: &str) -> Result<Duration, String> {
    let v: f64 = text
        .trim()
        .parse()
        .map_err(|_| format!("'{text}' is not a number of seconds"))?;
    scotopia_render::integrator::time_limit(v)
}

/// `--threads`: 1 to `MAX_THREADS`.
pub fn threads(text: &str) -> Result<usize, String> {
    text.trim()
        .parse::<usize>()
        .ok()
        .filter(|n| (1..=MAX_THREADS).contains(n))
        .ok_or_else(|| format!("'{text}': give a count from 1 to {MAX_THREADS}"))
}

/// `--fov`: degrees in (0, 360); the per-pixel limit is checked once the
/// image's width is known.
pub fn fov(text: &str) -> Result<f64, String> {
    let v: f64 = text
        .trim()
        .parse()
        .map_err(|_| format!("'{text}' is not a number of degrees"))?;
    if v.is_finite() && v > 0.0 && v < 360.0 {
        Ok(v)
    } else {
        Err(format!("{v}: must be between 0 and 360 degrees"))
    }
}

/// `--age`: years, as `scotopia_vision::Observer::new` accepts them.
pub fn age(text: &str) -> Result<f64, String> {
    let v: f64 = text
        .trim()
        .parse()
        .map_err(|_| format!("'{text}' is not a number of years"))?;
    Observer::new(v, Observer::DEFAULT_PIGMENTATION)
        .map(|o| o.age)
        .map_err(|e| e.to_string())
}

/// `--pigmentation`: CIE 146's factor, as `Observer::new` accepts it.
pub fn pigmentation(text: &str) -> Result<f64, String> {
    let v: f64 = text
        .trim()
        .parse()
        .map_err(|_| format!("'{text}' is not a number from 0 to 1"))?;
    Observer::new(Observer::DEFAULT_AGE, v)
        .map(|o| o.pigmentation)
        .map_err(|e| e.to_string())
}

/// The most a light level (`--scale`, the viewer's `scale`) may multiply
/// the image by: a pixel at the brightest luminance a scene can have
/// (`ABSURD_LUMINANCE`, 1e10 cd/m²) times it stays finite in f32, in
/// which the pipeline multiplies (1e38 made every lit pixel ∞: black).
pub const MAX_SCALE: f64 = f32::MAX as f64 / ABSURD_LUMINANCE as f64;

/// A light level K, checked in f32 where it is used: positive, a normal
/// f32 (not 0 or subnormal there) and at most [`MAX_SCALE`]. The error
/// names the flag.
pub fn light_scale(k: f64) -> Result<f32, String> {
    if k.is_finite() && k > 0.0 && (k as f32).is_normal() && k <= MAX_SCALE {
        Ok(k as f32)
    } else {
        Err(format!(
            "--scale {k}: must be a positive factor from {:e} to {MAX_SCALE:.1e}",
            f32::MIN_POSITIVE
        ))
    }
}

/// A point `X,Y,Z`: three finite numbers.
pub fn point(text: &str) -> Result<[f32; 3], String> {
    let v: Vec<f32> = text
        .split(',')
        .map(|t| t.trim().parse::<f32>())
        .collect::<Result<_, _>>()
        .map_err(|_| format!("'{text}': give a point X,Y,Z"))?;
    match v[..] {
        [x, y, z] if v.iter().all(|c| c.is_finite()) => Ok([x, y, z]),
        _ => Err(format!("'{text}': give a point X,Y,Z of finite numbers")),
    }
}

/// A direction `X,Y,Z`: three finite numbers, not all zero.
pub fn direction(text: &str) -> Result<[f32; 3], String> {
    match point(text) {
        Ok(v) if v.iter().any(|&c| c != 0.0) => Ok(v),
        _ => Err(format!(
            "'{text}': give a direction X,Y,Z, finite and not zero"
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn out_of_range_numbers_are_errors() {
        assert_eq!(seconds("1.5"), Ok(Duration::from_millis(1500)));
        for bad in ["1e20", "inf", "nan", "-3", "0", "soon"] {
            assert!(seconds(bad).is_err(), "{bad}");
        }
        assert_eq!(direction(" 0, 1,0"), Ok([0.0, 1.0, 0.0]));
        for bad in ["0,0,0", "1,2", "1,2,3,4", "up", "nan,1,0", "1e40,0,0"] {
            assert!(direction(bad).is_err(), "{bad}");
        }
        assert_eq!(threads("8"), Ok(8));
        for bad in ["0", "100000", "-1", "18446744073709551616"] {
            assert!(threads(bad).is_err(), "{bad}");
        }
        assert_eq!(fov("40"), Ok(40.0));
        for bad in ["0", "360", "1e300", "NaN", "-5"] {
            assert!(fov(bad).is_err(), "{bad}");
        }
        assert_eq!(age("70"), Ok(70.0));
        assert_eq!(pigmentation("1"), Ok(1.0));
        for bad in ["0", "-3", "1e300", "NaN", "inf", "old"] {
            assert!(age(bad).is_err(), "{bad}");
        }
        for bad in ["-0.1", "1.5", "NaN", "blue"] {
            assert!(pigmentation(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn a_light_level_that_is_0_or_infinite_in_f32_is_an_error_naming_the_flag() {
        assert_eq!(light_scale(0.02), Ok(0.02));
        assert_eq!(light_scale(1e20), Ok(1e20));
        for bad in [
            1e38,
            1e39,
            1e-39,
            1e-300,
            0.0,
            -1.0,
            f64::NAN,
            f64::INFINITY,
        ] {
            let e = light_scale(bad).unwrap_err();
            assert!(e.starts_with("--scale "), "{bad}: {e}");
        }
        // A pixel at the brightest a scene can be stays finite.
        let k = light_scale(MAX_SCALE).unwrap();
        assert!((ABSURD_LUMINANCE * k).is_finite());
    }
}
