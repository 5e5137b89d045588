//! `<sensor>` with its `<film>`, `<sampler>` and `<rfilter>`.

use scotopia_render::camera::{Camera, FovAxis};
use scotopia_render::scene::Filter;

use super::Builder;
use crate::mitsuba::{Node, Props, SceneError};

pub struct Sensor {
    pub camera: Camera,
    pub filter: Filter,
    pub spp: u32,
}

pub fn build_sensor(b: &mut Builder, node: &Node) -> Result<Sensor, SceneError> {
    let kind = node.require("type")?;
    if kind != "perspective" && kind != "thinlens" {
        return Err(node.error(format!(
            "sensor type '{kind}' is not supported (perspective, thinlens)"
        )));
    }
    let p = Props::new(node);
    let (fov, axis) = field_of_view(&p, node)?;
    let near = p.float("near_clip", 1e-2)?;
    let far = p.float("far_clip", 1e4)?;
    let to_world = p.transform("to_world")?;
    let (aperture, focus) = if kind == "thinlens" {
        (
            p.float("aperture_radius", 0.03)?,
            p.float("focus_distance", 0.0)?,
        )
    } else {
        (0.0, 1.0)
    };
    // Film and sampler, with Mitsuba's defaults.
    let (mut width, mut height, mut filter) = (768, 576, Filter::Gaussian { stddev: 0.5 });
    let mut spp = 4;
    for child in &node.children {
        match child.tag.as_str() {
            "film" => {
                let fp = Props::new(child);
                width = positive(child, fp.integer("width", 768)?)?;
                height = positive(child, fp.integer("height", 576)?)?;
                for f in child.children.iter().filter(|c| c.tag == "rfilter") {
                    let t = f.require("type")?;
                    let rp = Props::new(f);
                    filter = match t {
                        "box" => Filter::Box,
                        "gaussian" => {
                            let stddev = rp.float("stddev", 0.5)?;
                            if !(stddev.is_finite() && stddev > 0.0) {
                                return Err(f.error(format!(
                                    "gaussian stddev must be positive, got {stddev}"
                                )));
                            }
                            Filter::Gaussian { stddev }
                        }
                        other => {
                            b.warn(
                                f,
                                format!("rfilter '{other}' is not supported, using gaussian"),
                            );
                            Filter::Gaussian { stddev: 0.5 }
                        }
                    };
                    b.report_unused(&rp);
                }
                b.report_unused(&fp);
            }
            "sampler" => {
                let sp = Props::new(child);
                spp = positive(child, sp.integer("sample_count", 4)?)?;
                b.report_unused(&sp);
            }
            _ => {}
        }
    }
    b.report_unused(&p);
    let camera = Camera::new(
        to_world, width, height, fov, axis, near, far, aperture, focus,
    )
    .map_err(|e| node.error(e.to_string()))?;
    Ok(Sensor {
        camera,
        filter,
        spp,
    })
}

/// `fov` along `fov_axis`, or Mitsuba's `focal_length` ("50mm" by default)
/// of a 36 × 24 mm film, which sets the field along the diagonal.
fn field_of_view(p: &Props, node: &Node) -> Result<(f32, FovAxis), SceneError> {
    let fov = p.float("fov", f32::NAN)?;
    let focal = p.string("focal_length")?;
    if !fov.is_nan() {
        if focal.is_some() {
            return Err(node.error("give either 'fov' or 'focal_length', not both"));
        }
        let axis_name = p.string("fov_axis")?.unwrap_or("x");
        let axis = FovAxis::from_name(axis_name)
            .ok_or_else(|| node.error(format!("unknown fov_axis '{axis_name}'")))?;
        return Ok((fov, axis));
    }
    let text = focal.unwrap_or("50mm");
    let mm = text
        .trim()
        .trim_end_matches("mm")
        .parse::<f32>()
        .ok()
        .filter(|f| f.is_finite() && *f > 0.0)
        .ok_or_else(|| node.error(format!("focal_length '{text}' is not like '50mm'")))?;
    let diagonal = (36.0f32 * 36.0 + 24.0 * 24.0).sqrt();
    Ok((
        2.0 * (diagonal / (2.0 * mm)).atan().to_degrees(),
        FovAxis::Diagonal,
    ))
}

fn positive(node: &Node, v: i64) -> Result<u32, SceneError> {
    u32::try_from(v)
        .ok()
        .filter(|&v| v > 0)
        .ok_or_else(|| node.error(format!("{v} must be a positive integer")))
}
