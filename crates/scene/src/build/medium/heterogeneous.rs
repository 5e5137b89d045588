//! `<medium type="heterogeneous">` (issue 25): Mitsuba 3's heterogeneous
//! medium. `sigma_t` (default 1) and `albedo` (default 0.75) are each a
//! nested `<volume>` — `gridvolume` (alias `grid`) over a `.vol` file, or
//! `constvolume` — a `<ref name="…" id="…"/>` to a top-level `<volume>`,
//! or a plain spectrum, `<rgb>` or number; `scale` multiplies σ_t; a nested
//! `<phase>`. As in Mitsuba the medium fills the unit cube of σ_t's volume
//! placed by its `to_world` (a plain σ_t spans [0, 1]³, Mitsuba's default
//! constvolume).

use scotopia_color::Spectrum;
use scotopia_render::math::Transform;
use scotopia_render::medium::{Field, Filter, GridVolume, Heterogeneous, Medium};

use super::{negative, phase_and_rest};
use crate::build::Builder;
use crate::mitsuba::{resolve, Node, Props, SceneError, Usage};
use crate::volume::read_vol;

pub fn build_heterogeneous(b: &mut Builder, node: &Node) -> Result<Medium, SceneError> {
    let p = Props::new(node);
    let sigma_t = field(b, &p, "sigma_t", Usage::Unbounded, 1.0)?;
    let albedo = field(b, &p, "albedo", Usage::Reflectance, 0.75)?;
    let scale = p.float("scale", 1.0)?;
    if !(scale.is_finite() && scale >= 0.0) {
        return Err(node.error(format!(
            "scale must be finite and not negative, got {scale}"
        )));
    }
    if let Field::Constant { value, .. } = &sigma_t {
        if let Some((l, v)) = negative(value) {
            let at = p.get("sigma_t").unwrap_or(node);
            return Err(at.error(format!("sigma_t must not be negative, found {v} at {l} nm")));
        }
    }
    if let Field::Grid(g) = &sigma_t {
        if !(g.max() * scale).is_finite() {
            return Err(node.error(format!(
                "sigma_t's largest value {} times scale {scale} is not a finite number",
                g.max()
            )));
        }
    }
    let phase = phase_and_rest(b, node, &p)?;
    Ok(Medium::Heterogeneous(Box::new(Heterogeneous::new(
        sigma_t, albedo, scale, phase,
    ))))
}

/// The medium's `name`: a nested `<volume>`, a reference to a top-level
/// one, or a constant spectrum (`default` when absent).
fn field(
    b: &mut Builder,
    p: &Props,
    name: &str,
    usage: Usage,
    default: f32,
) -> Result<Field, SceneError> {
    let nested = p
        .node
        .children
        .iter()
        .find(|c| c.tag == "volume" && c.attr("name") == Some(name));
    if let Some(v) = nested {
        return volume(b, v, name, usage);
    }
    if let Some(r) = p.get(name).filter(|n| n.tag == "ref") {
        let target = b.named(r, "volume", r.require("id")?)?;
        return volume(b, &target, name, usage);
    }
    Ok(Field::constant(
        p.coefficient(name, usage)?
            .unwrap_or(Spectrum::Constant(default)),
    ))
}

/// A `<volume>` as the medium's `name`.
fn volume(b: &mut Builder, v: &Node, name: &str, usage: Usage) -> Result<Field, SceneError> {
    let vp = Props::new(v);
    let to_world = vp.transform("to_world")?;
    let field = match v.require("type")? {
        "constvolume" => {
            // Mitsuba's constvolume: 1 when no value is given.
            let value = vp
                .coefficient("value", usage)?
                .unwrap_or(Spectrum::Constant(1.0));
            Field::Constant {
                value,
                to_local: to_world.inverse(),
            }
        }
        "gridvolume" | "grid" => Field::Grid(grid_volume(b, &vp, v, name, usage, to_world)?),
        other => {
            return Err(v.error(format!(
                "volume '{other}' is not supported (gridvolume, constvolume)"
            )))
        }
    };
    b.report_unused(&vp);
    Ok(field)
}

/// A `gridvolume`: its file, `filter_type`, `use_grid_bbox`, `raw`;
/// `wrap_mode` read as clamp (warned otherwise), `accel` (a GPU option)
/// read and ignored.
fn grid_volume(
    b: &mut Builder,
    vp: &Props,
    v: &Node,
    name: &str,
    usage: Usage,
    to_world: Transform,
) -> Result<GridVolume, SceneError> {
    let file = vp
        .string("filename")?
        .ok_or_else(|| v.error("a gridvolume needs a 'filename' (a .vol file)"))?;
    let filter = match vp.string("filter_type")?.unwrap_or("trilinear") {
        "trilinear" => Filter::Trilinear,
        "nearest" => Filter::Nearest,
        other => {
            return Err(v.error(format!(
                "filter_type '{other}' is not one of trilinear, nearest"
            )))
        }
    };
    match vp.string("wrap_mode")?.unwrap_or("clamp") {
        "clamp" => {}
        mode @ ("repeat" | "mirror") => b.warn(
            v,
            format!(
                "wrap_mode '{mode}' is read as clamp: the medium is its grid's box, and only \
                 the half cell at its faces would differ"
            ),
        ),
        other => {
            return Err(v.error(format!(
                "wrap_mode '{other}' is not one of clamp, repeat, mirror"
            )))
        }
    }
    let use_grid_bbox = vp.boolean("use_grid_bbox", false)?;
    let raw = vp.boolean("raw", false)?;
    // Mitsuba's hardware interpolation on CUDA: no meaning here.
    let _ = vp.boolean("accel", true)?;
    let path = resolve(&v.dir, file);
    if !path.is_file() {
        let looked: Vec<String> = v
            .dir
            .folders()
            .iter()
            .map(|f| f.display().to_string())
            .collect();
        return Err(v.error(format!(
            "volume file '{file}' not found (looked in {})",
            looked.join(", ")
        )));
    }
    let grid = read_vol(&path).map_err(|e| v.error(e.to_string()))?;
    let channels = grid.channels();
    if channels == 3 && raw {
        return Err(v.error(format!(
            "{}: a raw 3-channel grid is not a spectrum; {name} needs 1 channel, or RGB without raw",
            path.display()
        )));
    }
    if channels != 1 && channels != 3 {
        return Err(v.error(format!(
            "{}: {channels} channels; {name} needs 1 (grey) or 3 (RGB)",
            path.display()
        )));
    }
    if usage == Usage::Reflectance {
        let top = (0..channels).map(|c| grid.max(c)).fold(0.0f32, f32::max);
        if top > 1.0 {
            return Err(v.error(format!(
                "{}: {name} must lie in [0, 1], the grid holds {top}",
                path.display()
            )));
        }
    }
    GridVolume::new(grid, filter, to_world, use_grid_bbox)
        .map_err(|e| v.error(format!("{}: {e}", path.display())))
}
