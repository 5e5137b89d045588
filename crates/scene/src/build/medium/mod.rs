//! `<medium>` and `<phase>` (issue 25): Mitsuba 3's homogeneous medium —
//! `sigma_t` (per scene unit) and `albedo` as spectra, RGB or numbers,
//! `scale`, and an `isotropic` or `hg` phase function — and its
//! heterogeneous medium (`heterogeneous.rs`). Media are read and checked,
//! and attached to shapes (`interior`, `exterior`) and to the sensor;
//! `volpath` and `bdpt` trace them.

mod heterogeneous;

use scotopia_color::{Spectrum, LAMBDA_MAX, LAMBDA_MIN};
use scotopia_render::medium::{Homogeneous, Medium, Phase, ShapeMedia};

use super::Builder;
use crate::mitsuba::{Node, Props, SceneError, Usage};

/// A `<medium>` element, or `None` for a kind not built yet.
pub fn build_medium(b: &mut Builder, node: &Node) -> Result<Option<Medium>, SceneError> {
    let kind = node.require("type")?;
    if kind == "heterogeneous" {
        return heterogeneous::build_heterogeneous(b, node).map(Some);
    }
    if kind != "homogeneous" {
        return Ok(None);
    }
    let p = Props::new(node);
    let sigma_t =
        coefficient(b, &p, "sigma_t", Usage::Unbounded)?.unwrap_or(Spectrum::Constant(1.0));
    if let Some((l, v)) = negative(&sigma_t) {
        let at = p.get("sigma_t").unwrap_or(node);
        return Err(at.error(format!("sigma_t must not be negative, found {v} at {l} nm")));
    }
    let albedo =
        coefficient(b, &p, "albedo", Usage::Reflectance)?.unwrap_or(Spectrum::Constant(0.75));
    let scale = p.float("scale", 1.0)?;
    if !(scale.is_finite() && scale >= 0.0) {
        return Err(node.error(format!(
            "scale must be finite and not negative, got {scale}"
        )));
    }
    let phase = phase_and_rest(b, node, &p)?;
    Ok(Some(Medium::Homogeneous(Homogeneous {
        sigma_t,
        albedo,
        scale,
        phase,
    })))
}

/// A homogeneous medium's `name`: a spectrum, `<rgb>` or number, or
/// Mitsuba's `<volume type="constvolume">` holding one as its `value`.
fn coefficient(
    b: &mut Builder,
    p: &Props,
    name: &str,
    usage: Usage,
) -> Result<Option<Spectrum>, SceneError> {
    let volume = p
        .node
        .children
        .iter()
        .find(|c| c.tag == "volume" && c.attr("name") == Some(name));
    let Some(v) = volume else {
        return p.coefficient(name, usage);
    };
    if v.require("type")? != "constvolume" {
        return Err(v.error(format!(
            "a homogeneous medium's {name} is constant: give a spectrum, <rgb>, <float> or a constvolume"
        )));
    }
    let vp = Props::new(v);
    let value = vp.coefficient("value", usage)?;
    b.report_unused(&vp);
    // Mitsuba's constvolume: 1 when no value is given.
    Ok(value.or(Some(Spectrum::Constant(1.0))))
}

/// What every medium ends with: its `<phase>` (isotropic when none), the
/// properties Mitsuba's volpath reads only for its own performance or in
/// other variants, and the warning for what was not read.
pub(super) fn phase_and_rest(b: &mut Builder, node: &Node, p: &Props) -> Result<Phase, SceneError> {
    for name in ["sample_emitters", "has_spectral_extinction"] {
        let _ = p.get(name);
    }
    let mut phase = Phase::Isotropic;
    for c in node.children.iter().filter(|c| c.tag == "phase") {
        phase = build_phase(b, c)?;
    }
    b.report_unused(p);
    Ok(phase)
}

/// `<phase type="isotropic|hg">`.
pub(super) fn build_phase(b: &mut Builder, node: &Node) -> Result<Phase, SceneError> {
    let p = Props::new(node);
    let phase = match node.require("type")? {
        "isotropic" => Phase::Isotropic,
        "hg" => {
            let g = p.float("g", 0.8)?;
            if !(g > -1.0 && g < 1.0) {
                return Err(node.error(format!("hg's g must lie in (−1, 1), got {g}")));
            }
            Phase::HenyeyGreenstein { g }
        }
        other => {
            return Err(node.error(format!(
                "phase function '{other}' is not supported (isotropic, hg)"
            )))
        }
    };
    b.report_unused(&p);
    Ok(phase)
}

/// The first wavelength (5 nm grid and the spectrum's own samples) where
/// `s` is negative.
pub(super) fn negative(s: &Spectrum) -> Option<(f32, f32)> {
    let grid = (LAMBDA_MIN as u32..=LAMBDA_MAX as u32)
        .step_by(5)
        .map(|l| l as f32);
    grid.chain(s.breakpoints().iter().copied())
        .filter(|l| (LAMBDA_MIN..=LAMBDA_MAX).contains(l))
        .map(|l| (l, s.eval(l)))
        .find(|(_, v)| v.is_nan() || *v < 0.0)
}

/// The scene's media as they are attached: built once per id, in the
/// order first used.
#[derive(Debug, Default)]
pub struct Media {
    pub list: Vec<Medium>,
    /// Index of each top-level medium built (`None`: a kind not built).
    ids: std::collections::HashMap<String, Option<u32>>,
    /// Of each top-level shape, in order.
    pub shape_media: Vec<ShapeMedia>,
    pub camera: Option<u32>,
}

impl Media {
    /// The medium a `<medium>` or a `<ref id>` to one names.
    fn resolve(&mut self, b: &mut Builder, node: &Node) -> Result<Option<u32>, SceneError> {
        if node.tag == "ref" {
            let id = node.require("id")?;
            if let Some(&m) = self.ids.get(id) {
                return Ok(m);
            }
            let target = b.named(node, "medium", id)?;
            let m = self.push(build_medium(b, &target)?);
            self.ids.insert(id.to_string(), m);
            return Ok(m);
        }
        let built = build_medium(b, node)?;
        Ok(self.push(built))
    }

    fn push(&mut self, m: Option<Medium>) -> Option<u32> {
        m.map(|m| {
            self.list.push(m);
            (self.list.len() - 1) as u32
        })
    }

    /// Whether `c`, a child of a shape or sensor, is a medium or a
    /// reference to one.
    fn is_medium(b: &Builder, c: &Node) -> bool {
        c.tag == "medium"
            || c.tag == "ref"
                && c.attr("id")
                    .and_then(|id| b.named.get(id))
                    .is_some_and(|t| t.tag == "medium")
    }

    /// A shape's `interior` and `exterior` media (by the child's name).
    pub fn of_shape(&mut self, b: &mut Builder, shape: &Node) -> Result<ShapeMedia, SceneError> {
        let mut media = ShapeMedia::default();
        let children: Vec<&Node> = shape
            .children
            .iter()
            .filter(|c| Self::is_medium(b, c))
            .collect();
        for c in children {
            let slot = match c.attr("name") {
                Some("interior") => &mut media.interior,
                Some("exterior") => &mut media.exterior,
                other => {
                    return Err(c.error(format!(
                        "a shape's medium is its 'interior' or 'exterior' (name=\"…\"), not {}",
                        other.map_or("unnamed".into(), |n| format!("'{n}'"))
                    )))
                }
            };
            *slot = self.resolve(b, c)?;
        }
        Ok(media)
    }

    /// The medium a sensor sits in (Mitsuba: one medium per sensor).
    pub fn of_sensor(&mut self, b: &mut Builder, sensor: &Node) -> Result<Option<u32>, SceneError> {
        let mut found = None;
        let children: Vec<&Node> = sensor
            .children
            .iter()
            .filter(|c| Self::is_medium(b, c))
            .collect();
        for c in children {
            if found.is_some() {
                return Err(c.error("a sensor sits in one medium"));
            }
            found = Some(self.resolve(b, c)?);
        }
        Ok(found.flatten())
    }
}
