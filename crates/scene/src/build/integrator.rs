//! `<integrator>`: the light-transport settings. Mitsuba's wrappers
//! (`moment`, `aov`, `stokes`) are unwrapped to the integrator they hold;
//! integrators whose image the path tracer converges to are read as `path`
//! with a note of what differs.

use scotopia_render::scene::{IntegratorKind, IntegratorSettings};

use super::Builder;
use crate::mitsuba::{Node, Props, SceneError};

/// Settings when a scene names no integrator (Mitsuba's `path` defaults).
pub const DEFAULT: IntegratorSettings = IntegratorSettings {
    kind: IntegratorKind::Path,
    max_depth: -1,
    rr_depth: 5,
    aim_at_casters: true,
    media: false,
};

/// Integrators that only add outputs around the one they hold.
pub(crate) const WRAPPERS: [&str; 3] = ["moment", "aov", "stokes"];

pub fn build_integrator(b: &mut Builder, node: &Node) -> Result<IntegratorSettings, SceneError> {
    let name = node.require("type")?;
    if WRAPPERS.contains(&name) {
        let inner: Vec<&Node> = node
            .children
            .iter()
            .filter(|c| c.tag == "integrator")
            .collect();
        let what = match name {
            "moment" => "the second moment it adds is not written",
            "aov" => "its AOV channels are not written",
            _ => "scotopia does not track polarisation; the Stokes channels are not written",
        };
        b.warn(
            node,
            format!("integrator '{name}' renders the integrator it holds; {what}"),
        );
        // Mitsuba's `aov` may hold none: the AOVs alone, over a black image.
        return match inner.first() {
            Some(first) => {
                if inner.len() > 1 {
                    b.warn(
                        inner[1],
                        "more than one nested integrator: rendering the first".into(),
                    );
                }
                build_integrator(b, first)
            }
            None => Err(node.error(format!(
                "integrator '{name}' holds no nested <integrator> to render"
            ))),
        };
    }
    let p = Props::new(node);
    let max_depth = p.integer("max_depth", -1)?;
    let rr_depth = p.integer("rr_depth", 5)?;
    let depth = |v: i64, what: &str| {
        i32::try_from(v)
            .ok()
            .filter(|&d| d >= -1)
            .ok_or_else(|| node.error(format!("{what} {v}: use −1 (unlimited) or a depth ≥ 0")))
    };
    let (kind, max_depth) = match name {
        "path" | "bdpt" => (
            IntegratorKind::from_name(name).unwrap_or(IntegratorKind::Path),
            depth(max_depth, "max_depth")?,
        ),
        // Direct illumination is the path tracer's paths of up to two
        // segments: camera → surface → light (emission seen directly too).
        "direct" => {
            b.warn(
                node,
                "integrator 'direct' is rendered as path with max_depth 2 (the same image; \
                 emitter_samples and bsdf_samples only change the noise)"
                    .into(),
            );
            (IntegratorKind::Path, 2)
        }
        // One volume path tracer serves them: its spectral MIS over the
        // cluster is what volpathmis adds to volpath.
        "volpath" | "volpathmis" | "prbvolpath" => {
            if name != "volpath" {
                b.warn(
                    node,
                    format!("integrator '{name}' is rendered as volpath (the same expected image)"),
                );
            }
            (IntegratorKind::Path, depth(max_depth, "max_depth")?)
        }
        // The differentiable variants and the particle tracer converge to
        // the path tracer's image.
        "prb" | "prb_basic" | "ptracer" => {
            b.warn(
                node,
                format!("integrator '{name}' is rendered as path (the same expected image)"),
            );
            (IntegratorKind::Path, depth(max_depth, "max_depth")?)
        }
        other => {
            b.warn(
                node,
                format!("integrator '{other}' is not supported, using path"),
            );
            (IntegratorKind::Path, depth(max_depth, "max_depth")?)
        }
    };
    if name == "direct" {
        // Its sample counts set no depth; do not report them as unused twice.
        for key in ["emitter_samples", "bsdf_samples", "shading_samples"] {
            p.get(key);
        }
    }
    let settings = IntegratorSettings {
        kind,
        max_depth,
        rr_depth: depth(rr_depth, "rr_depth")?,
        aim_at_casters: true,
        // The bidirectional tracer is scotopia's own: it traces media.
        media: matches!(name, "volpath" | "volpathmis" | "prbvolpath" | "bdpt"),
    };
    b.report_unused(&p);
    Ok(settings)
}
