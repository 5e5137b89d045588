//! `<emitter type="ies">`: a luminaire from its photometric file (IES
//! LM-63 or EULUMDAT, recognised by content) as a goniometric point light.
//!
//! Parameters: `filename`; `spectrum` (the lamp's relative spectral
//! distribution; default Planck at 4000 K), scaled so that the rendered
//! luminous intensity is the file's candela; `scale` (× after the file's
//! own multipliers and ballast factor, default 1); `to_world` (the
//! photometric nadir is local +z, C = 0° along +x, C = 90° along +y).
//! The luminous opening is not used: the lamp is a point (docs/lighting.md).

use std::sync::Arc;

use scotopia_color::Spectrum;
use scotopia_render::light::{spectral_power, GoniometricLight, IntensityGrid};
use scotopia_render::math::{Frame, Vec3};

use crate::luminaire::{read_luminaire, Symmetry};
use crate::mitsuba::{resolve, Node, Props, SceneError, Usage};

/// γ steps of the rendering grid over 0–180° (0.5°) and C steps over
/// 0–360° (0.5°); a rotationally symmetric lamp needs one C column.
const ROWS: usize = 360;
const COLUMNS: usize = 720;

/// The least total flux a photometric file may give, lm: a millionth of
/// the faintest indicator LED's (~1 mlm). A file under it lights nothing
/// anyone could see, and its candela may be subnormal in f32, where the
/// renderer works.
const MIN_LUMENS: f64 = 1e-9;

/// The default spectral distribution's colour temperature, K.
const DEFAULT_KELVIN: f32 = 4000.0;

pub fn build_ies(p: &Props, node: &Node) -> Result<GoniometricLight, SceneError> {
    let file = p
        .string("filename")?
        .ok_or_else(|| node.error("an ies emitter needs a 'filename' (an IES or EULUMDAT file)"))?;
    let photometry =
        read_luminaire(resolve(&node.dir, file)).map_err(|e| node.error(e.to_string()))?;
    // A file whose candela are all tiny (1e-40: subnormal in f32) is a
    // ~0 lm lamp that renders black, as an all-zero one would: refused
    // alike, with its flux.
    let flux = photometry.total_flux_lm();
    if flux.is_nan() || flux < MIN_LUMENS {
        return Err(node.error(format!(
            "{file}: the luminaire emits nothing (its candela give {flux:e} lm, under \
             {MIN_LUMENS:e} lm: a unit mistake or a broken export?)"
        )));
    }
    let spectrum = match p.spectrum("spectrum", Usage::Emission)? {
        Some(s) => s,
        None => Spectrum::blackbody(DEFAULT_KELVIN).map_err(|e| node.error(e.to_string()))?,
    };
    let scale = p.float("scale", 1.0)?;
    if !(scale.is_finite() && scale >= 0.0) {
        return Err(node.error(format!("scale must be non-negative, got {scale}")));
    }
    // 683 ∫ S ȳ dλ = 1: the grid's candela are the rendered intensity.
    let lumens = spectral_power(&spectrum).lumens;
    if !(lumens.is_finite() && lumens > 0.0) {
        return Err(node.error(
            "the spectrum has no luminous content (683 ∫ S ȳ dλ is 0): it cannot carry the file's candela",
        ));
    }
    let spectrum = spectrum.scaled((scale as f64 / lumens) as f32);
    let columns = if photometry.symmetry == Symmetry::Rotational {
        1
    } else {
        COLUMNS
    };
    let grid = IntensityGrid::new(ROWS, columns, |g, c| photometry.intensity(g, c))
        .ok_or_else(|| node.error(format!("{file}: the luminaire emits nothing")))?;
    let to_world = p.transform("to_world")?;
    let axis = |v: Vec3| to_world.vector(v).normalize();
    // The nadir is where to_world sends +z, C 0° towards its +x; C 90°
    // completes a right-handed frame (a shear or a mirror in to_world
    // must not skew or swap the C planes).
    let n = axis(Vec3::new(0.0, 0.0, 1.0));
    let x = axis(Vec3::new(1.0, 0.0, 0.0));
    let s = (x - n * x.dot(n)).normalize();
    let t = n.cross(s);
    if !(s.is_finite() && t.is_finite() && n.is_finite()) {
        return Err(node.error("to_world collapses the luminaire's axes"));
    }
    Ok(GoniometricLight {
        position: to_world.point(Vec3::ZERO),
        frame: Frame { s, t, n },
        spectrum,
        grid: Arc::new(grid),
    })
}
