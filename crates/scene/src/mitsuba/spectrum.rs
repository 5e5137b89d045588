//! `<spectrum>` values: constants, `λ:value` pairs, files, blackbodies,
//! CIE illuminants by name, and Mitsuba's spectrum plugins (`regular`,
//! `irregular`, `uniform`, `srgb`, `rawconstant`), with `scale` or
//! scotopia's `luminance`; and an object's spectral properties
//! (`Props::spectrum`, `Props::coefficient`), which may be such values.

use scotopia_color::photometry::{integrate_observers, spectrum_to_xyzv};
use scotopia_color::{
    cie, io, rgb_to_spectrum, RgbSpace, Spectrum, SpectrumKind, Tabulated, UpsampleMethod,
};

use super::error::SceneError;
use super::parse::Node;
use super::props::{Props, Usage};
use super::search::resolve;
use super::values::{parse_floats, parse_rgb};

/// `<spectrum>`: `value="0.5"`, `value="400:0.1, 500:0.3"`, `filename`,
/// `type="blackbody"` (with `temperature`), or `type` = any CIE illuminant
/// name (`d65` as in Mitsuba; `a`, `d50`, `f11`, … are scotopia's extension).
/// `<float name="scale">` multiplies any spectrum (as Mitsuba's `d65`);
/// scotopia's extension `<float name="luminance" value="Y"/>` instead scales
/// the spectrum so that 683 ∫ S ȳ dλ = Y: cd/m² for a radiance, cd for an
/// intensity, lx for an irradiance — the absolute level of a lamp whose
/// spectrum is known only in relative units.
pub fn read_spectrum(n: &Node) -> Result<Spectrum, SceneError> {
    read_spectrum_as(n, Usage::Unbounded)
}

/// [`read_spectrum`] for a use (which decides how an `srgb` colour is
/// upsampled).
pub fn read_spectrum_as(n: &Node, usage: Usage) -> Result<Spectrum, SceneError> {
    let s = read_spectrum_shape(n, usage)?;
    let props = Props::new(n);
    let scale = props.float("scale", f32::NAN)?;
    let target = props.float("luminance", f32::NAN)?;
    if !scale.is_nan() {
        if !target.is_nan() {
            return Err(n.error("give 'scale' or 'luminance', not both"));
        }
        if !(scale.is_finite() && scale >= 0.0) {
            return Err(n.error(format!("scale must be non-negative, got {scale}")));
        }
        return check_finite(n, s.scaled(scale), &format!("× scale {scale}"));
    }
    if target.is_nan() {
        return check_finite(n, s, "");
    }
    if !(target.is_finite() && target >= 0.0) {
        return Err(n.error(format!("luminance must be non-negative, got {target}")));
    }
    let y = spectrum_to_xyzv(&s).y;
    if y.is_nan() || y <= 0.0 {
        return Err(n.error(format!(
            "{}the spectrum has no luminance to scale to 'luminance'",
            source(n)
        )));
    }
    // A spectrum of tiny (e.g. subnormal) values needs a factor beyond
    // single precision: ∞ × 0 would make the light NaN.
    let factor = target as f64 / y;
    if !(factor as f32).is_finite() {
        return Err(n.error(format!(
            "{}the spectrum's luminance {y:e} is too small to scale to luminance {target}: \
             the factor {factor:e} exceeds single precision; give the values in larger units",
            source(n)
        )));
    }
    check_finite(
        n,
        s.scaled(factor as f32),
        &format!("scaled to luminance {target}"),
    )
}

/// `file.csv: ` for a spectrum read from a file, else nothing: errors
/// about its values name the file as well as the element.
fn source(n: &Node) -> String {
    n.attr("filename")
        .map(|f| format!("{}: ", resolve(&n.dir, f).display()))
        .unwrap_or_default()
}

/// A spectrum whose values or integrals are not finite numbers would make
/// NaN or infinite light power, reflectance or index, and a black or
/// blank image: an error naming the element (and its file). Checked at its
/// own samples and on the 1 nm grid the photometric integrals use.
fn check_finite(n: &Node, s: Spectrum, how: &str) -> Result<Spectrum, SceneError> {
    // A constant (most spectra in a large scene) is its one value.
    if matches!(s, Spectrum::Constant(v) if v.is_finite()) {
        return Ok(s);
    }
    let grid = s.on_grid(scotopia_color::LAMBDA_MIN, scotopia_color::LAMBDA_MAX, 1.0);
    let at_samples = s.breakpoints().iter().map(|&l| s.eval(l));
    let value = grid.into_iter().chain(at_samples).find(|v| !v.is_finite());
    let integral = integrate_observers(&s).into_iter().find(|v| !v.is_finite());
    match value.map(f64::from).or(integral) {
        None => Ok(s),
        Some(v) => Err(n.error(format!(
            "{}the spectrum{} has a value or integral of {v}: it must be finite",
            source(n),
            if how.is_empty() {
                String::new()
            } else {
                format!(" {how}")
            }
        ))),
    }
}

/// The spectrum's shape, before any `luminance` scaling.
fn read_spectrum_shape(n: &Node, usage: Usage) -> Result<Spectrum, SceneError> {
    if let Some(t) = n.attr("type") {
        if let Some(s) = spectrum_plugin(n, t, usage)? {
            return Ok(s);
        }
        return normalised_illuminant(t).map_err(|e| n.error(e));
    }
    if let Some(file) = n.attr("filename") {
        let path = resolve(&n.dir, file);
        return io::read_spectrum_file(&path)
            .map(Spectrum::from)
            .map_err(|e| n.error(e.to_string()));
    }
    let value = n.require("value")?;
    if !value.contains(':') {
        return match parse_floats(n, value)?.as_slice() {
            [v] => Ok(Spectrum::Constant(*v)),
            _ => Err(n.error("a constant spectrum is one number; use 'λ:value' pairs for a curve")),
        };
    }
    let mut lambda = Vec::new();
    let mut values = Vec::new();
    for pair in value.split(',').map(str::trim).filter(|p| !p.is_empty()) {
        let (l, v) = pair
            .split_once(':')
            .ok_or_else(|| n.error(format!("'{pair}' is not 'wavelength:value'")))?;
        let num = |s: &str| -> Result<f32, SceneError> {
            s.trim()
                .parse::<f32>()
                .ok()
                .filter(|x| x.is_finite())
                .ok_or_else(|| n.error(format!("'{s}' is not a finite number")))
        };
        lambda.push(num(l)?);
        values.push(num(v)?);
    }
    Tabulated::new(lambda, values)
        .map(Spectrum::from)
        .map_err(|e| n.error(e.to_string()))
}

/// A CIE illuminant normalised as Mitsuba's `d65`: unit luminance-weighted
/// mean, so an emitter of this spectrum is as bright as a constant
/// radiance 1. Mitsuba's spectral variants multiply an emitter's plain
/// number or RGB by this, and use it alone where an emitter names none.
pub fn normalised_illuminant(name: &str) -> Result<Spectrum, String> {
    let s = cie::illuminant(name).map_err(|e| e.to_string())?;
    let y = integrate_observers(&s)[1];
    let y_unit = integrate_observers(&Spectrum::Constant(1.0))[1];
    Ok(s.scaled((y_unit / y) as f32))
}

/// Mitsuba's spectrum plugins other than the illuminants; `None` for a
/// type that is not one of them.
fn spectrum_plugin(n: &Node, kind: &str, usage: Usage) -> Result<Option<Spectrum>, SceneError> {
    let props = Props::new(n);
    let number_list = |name: &str| -> Result<Vec<f32>, SceneError> {
        let text = props
            .string(name)?
            .ok_or_else(|| n.error(format!("a '{kind}' spectrum needs '{name}'")))?;
        parse_floats(n, text)
    };
    let tabulated = |lambda: Vec<f32>, values: Vec<f32>| {
        Tabulated::new(lambda, values)
            .map(Spectrum::from)
            .map_err(|e| n.error(e.to_string()))
    };
    let s = match kind {
        "blackbody" => {
            let k = props.float("temperature", f32::NAN)?;
            Spectrum::blackbody(k).map_err(|e| n.error(e.to_string()))?
        }
        // Values at equal steps from wavelength_min to wavelength_max.
        "regular" => {
            let values = number_list("values")?;
            let (lo, hi) = (
                props.float("wavelength_min", f32::NAN)?,
                props.float("wavelength_max", f32::NAN)?,
            );
            if lo.partial_cmp(&hi) != Some(std::cmp::Ordering::Less) || values.len() < 2 {
                return Err(n.error(format!(
                    "a regular spectrum needs wavelength_min < wavelength_max and two or more values (got {lo}, {hi}, {} values)",
                    values.len()
                )));
            }
            let step = (hi - lo) / (values.len() - 1) as f32;
            let lambda = (0..values.len()).map(|i| lo + step * i as f32).collect();
            tabulated(lambda, values)?
        }
        "irregular" => {
            let (lambda, values) = (number_list("wavelengths")?, number_list("values")?);
            if lambda.len() != values.len() {
                return Err(n.error(format!(
                    "{} wavelengths but {} values",
                    lambda.len(),
                    values.len()
                )));
            }
            tabulated(lambda, values)?
        }
        // A constant, zero outside [wavelength_min, wavelength_max].
        "uniform" => {
            let v = props.float("value", f32::NAN)?;
            if v.is_nan() {
                return Err(n.error("a uniform spectrum needs 'value'"));
            }
            let (lo, hi) = (
                props.float("wavelength_min", scotopia_color::LAMBDA_MIN)?,
                props.float("wavelength_max", scotopia_color::LAMBDA_MAX)?,
            );
            if lo <= scotopia_color::LAMBDA_MIN && hi >= scotopia_color::LAMBDA_MAX {
                Spectrum::Constant(v)
            } else {
                tabulated(vec![lo, hi], vec![v, v])?
            }
        }
        // The value as given, without upsampling (Mitsuba uses it for
        // monochrome quantities).
        "rawconstant" => Spectrum::Constant(props.float("value", f32::NAN)?),
        "srgb" => {
            let c = props
                .get("color")
                .ok_or_else(|| n.error("an srgb spectrum needs <rgb name=\"color\">"))?;
            let rgb = parse_rgb(c)?;
            let kind = match usage {
                Usage::Emission => SpectrumKind::Illuminant,
                _ if props.boolean("unbounded", false)? => SpectrumKind::Unbounded,
                Usage::Unbounded => SpectrumKind::Unbounded,
                Usage::Reflectance => SpectrumKind::Reflectance,
            };
            rgb_to_spectrum(rgb, RgbSpace::Srgb, UpsampleMethod::Jakob2019, kind)
                .map_err(|e| c.error(e.to_string()))?
        }
        _ => return Ok(None),
    };
    if s.eval(550.0).is_nan() {
        return Err(n.error(format!("the '{kind}' spectrum has no value")));
    }
    Ok(Some(s))
}

impl<'a> Props<'a> {
    /// A medium's coefficient (σ_t, albedo) from `<spectrum>`, `<rgb>` or a
    /// number, read for `usage`, except that an RGB within [0, 1] is
    /// upsampled as a reflectance whatever the usage, as Mitsuba's spectral
    /// variants upsample every volume's colour (its `srgb`); a brighter one,
    /// which Mitsuba refuses there, as `usage` says.
    pub fn coefficient(&self, name: &str, usage: Usage) -> Result<Option<Spectrum>, SceneError> {
        match self.get(name) {
            Some(n) if n.tag == "rgb" && usage == Usage::Unbounded => self
                .spectrum(name, Usage::Reflectance)
                .or_else(|_| self.spectrum(name, usage)),
            _ => self.spectrum(name, usage),
        }
    }

    /// A spectral property from `<spectrum>`, `<rgb>` or a number.
    pub fn spectrum(&self, name: &str, usage: Usage) -> Result<Option<Spectrum>, SceneError> {
        let Some(n) = self.get(name) else {
            return Ok(None);
        };
        let s = match n.tag.as_str() {
            "float" => Spectrum::Constant(self.number(n)?),
            "rgb" => {
                let mut rgb = parse_rgb(n)?;
                // Mitsuba's spectral upsampling clamps an unbounded colour
                // (an index fitted in RGB) to non-negative values.
                if usage == Usage::Unbounded && rgb.iter().any(|&v| v < 0.0) {
                    let given = format!("{}, {}, {}", rgb[0], rgb[1], rgb[2]);
                    rgb = rgb.map(|v| v.max(0.0));
                    self.notes.borrow_mut().push((
                        n,
                        format!(
                            "'{name}' = ({given}) has a negative component: read as ({}, {}, {}), as Mitsuba's spectral upsampling does",
                            rgb[0], rgb[1], rgb[2]
                        ),
                    ));
                }
                let kind = match usage {
                    Usage::Reflectance => SpectrumKind::Reflectance,
                    Usage::Unbounded => SpectrumKind::Unbounded,
                    Usage::Emission => SpectrumKind::Illuminant,
                };
                rgb_to_spectrum(rgb, RgbSpace::Srgb, UpsampleMethod::Jakob2019, kind)
                    .map_err(|e| n.error(e.to_string()))?
            }
            "spectrum" => read_spectrum_as(n, usage)?,
            "texture" | "ref" => {
                return Err(n.error(format!(
                    "'{name}' cannot be a texture here: give a <spectrum>, <rgb> or <float>"
                )))
            }
            other => {
                return Err(n.error(format!(
                    "'{name}' must be a spectrum, <rgb> or <float>, not <{other}>"
                )))
            }
        };
        if usage == Usage::Reflectance {
            check_reflectance(n, &s)?;
        }
        Ok(Some(s))
    }
}

/// Reflectances above 1 or below 0 create energy: an error. Checked on a
/// 5 nm grid and at the spectrum's own samples (a tabulated spectrum is
/// piecewise linear, so its extremes lie there: a spike between grid
/// points is caught).
fn check_reflectance(n: &Node, s: &Spectrum) -> Result<(), SceneError> {
    let range = scotopia_color::LAMBDA_MIN..=scotopia_color::LAMBDA_MAX;
    let grid = (360..=830).step_by(5).map(|l| l as f32);
    let samples = s
        .breakpoints()
        .iter()
        .copied()
        .filter(|l| range.contains(l));
    let bad = grid
        .chain(samples)
        .map(|l| (l, s.eval(l)))
        .find(|(_, v)| !(0.0..=1.0 + 1e-4).contains(v));
    match bad {
        Some((l, v)) => Err(n.error(format!(
            "a reflectance must lie in [0, 1], found {v} at {l} nm"
        ))),
        None => Ok(()),
    }
}
