//! `<sensor>` with its `<film>`, `<sampler>` and `<rfilter>`, and the
//! `irradiancemeter` a shape can hold.

use scotopia_render::camera::{Camera, FisheyeMap, FovAxis};
use scotopia_render::film::Film;
use scotopia_render::math::Transform;
use scotopia_render::scene::Filter;

use super::Builder;
use crate::mitsuba::{Node, Props, SceneError};

pub struct Sensor {
    pub camera: Camera,
    pub filter: Filter,
    pub spp: u32,
    /// An irradiancemeter's shape (its index among the scene's shapes).
    pub meter: Option<u32>,
}

pub fn build_sensor(b: &mut Builder, node: &Node) -> Result<Sensor, SceneError> {
    let kind = node.require("type")?;
    if kind == "irradiancemeter" {
        return Err(node.error(
            "an irradiancemeter is the child of a shape (<shape …><sensor type=\"irradiancemeter\">), \
             as in Mitsuba: it measures over that shape",
        ));
    }
    if !["perspective", "thinlens", "orthographic", "fisheye"].contains(&kind) {
        return Err(node.error(format!(
            "sensor type '{kind}' is not supported (perspective, thinlens, orthographic, fisheye)"
        )));
    }
    let p = Props::new(node);
    let orthographic = kind == "orthographic";
    // scotopia's own sensor (Mitsuba has none): its projection and full
    // field of view across the film's width.
    let fisheye = if kind == "fisheye" {
        let name = p.string("projection")?.unwrap_or("angular");
        let map = FisheyeMap::from_name(name).ok_or_else(|| {
            node.error(format!(
                "unknown fisheye projection '{name}' (angular or equisolid)"
            ))
        })?;
        Some((map, p.float("fov", 180.0)?))
    } else {
        None
    };
    let (fov, axis) = if orthographic || fisheye.is_some() {
        (90.0, FovAxis::X)
    } else {
        field_of_view(&p, node)?
    };
    let near = p.float("near_clip", 1e-2)?;
    let far = p.float("far_clip", 1e4)?;
    let to_world = p.transform("to_world")?;
    let (aperture, focus) = if kind == "thinlens" {
        (
            p.float("aperture_radius", 0.03)?,
            // Mitsuba: the far clip plane when not given (src/render/sensor.cpp).
            p.float("focus_distance", far)?,
        )
    } else {
        (0.0, 1.0)
    };
    let FilmSettings {
        mut width,
        mut height,
        filter,
        mut crop,
        spp,
    } = film_and_sampler(b, node)?;
    b.report_unused(&p);
    // A resolution override scales the film, and any crop with it.
    if let Some(res) = b.resolution {
        let (w, h) = res.size(width, height);
        crop = crop.map(|(o, s): Crop| {
            let sx = |v: u32| (v as u64 * w as u64 / width as u64) as u32;
            let sy = |v: u32| (v as u64 * h as u64 / height as u64) as u32;
            ([sx(o[0]), sy(o[1])], [sx(s[0]).max(1), sy(s[1]).max(1)])
        });
        (width, height) = (w, h);
    }
    // Checked here, so the error names the scene's line.
    Film::check_size(width, height, None).map_err(|e| node.error(e.to_string()))?;
    let camera = if let Some((map, fov)) = fisheye {
        Camera::fisheye(to_world, [width, height], map, fov, near, far)
    } else if orthographic {
        Camera::orthographic(to_world, width, height, near, far)
    } else {
        Camera::new(
            to_world, width, height, fov, axis, near, far, aperture, focus,
        )
    };
    let mut camera = camera.map_err(|e| node.error(e.to_string()))?;
    if let Some((offset, size)) = crop {
        camera = camera
            .with_crop(offset, size)
            .map_err(|e| node.error(e.to_string()))?;
    }
    Ok(Sensor {
        camera,
        filter,
        spp,
        meter: None,
    })
}

/// Mitsuba's `irradiancemeter`, a child of the shape numbered `shape`: it
/// measures the irradiance averaged over the shape's surface, on the side
/// its normals point to, as one pixel (Mitsuba refuses other film sizes;
/// scotopia warns and renders one pixel). It has no placement of its own.
pub fn build_meter(b: &mut Builder, node: &Node, shape: u32) -> Result<Sensor, SceneError> {
    let p = Props::new(node);
    if p.get("to_world").is_some() {
        return Err(node.error(
            "an irradiancemeter has no to_world: it takes its shape's placement (as in Mitsuba)",
        ));
    }
    let film = film_and_sampler(b, node)?;
    if (film.width, film.height) != (1, 1) || film.crop.is_some() {
        b.warn(
            node,
            format!(
                "the irradiancemeter measures one value: its {}×{} film is rendered as 1×1",
                film.width, film.height
            ),
        );
    }
    b.report_unused(&p);
    let camera = Camera::orthographic(Transform::IDENTITY, 1, 1, 1e-2, 1e4)
        .map_err(|e| node.error(e.to_string()))?;
    Ok(Sensor {
        camera,
        filter: film.filter,
        spp: film.spp,
        meter: Some(shape),
    })
}

/// A sensor's film and sampler settings, with Mitsuba's defaults.
struct FilmSettings {
    width: u32,
    height: u32,
    filter: Filter,
    crop: Option<Crop>,
    spp: u32,
}

fn film_and_sampler(b: &mut Builder, node: &Node) -> Result<FilmSettings, SceneError> {
    let (mut width, mut height, mut filter) = (768, 576, Filter::Gaussian { stddev: 0.5 });
    let mut crop = None;
    let mut spp = 4;
    for child in &node.children {
        match child.tag.as_str() {
            "film" => {
                let fp = Props::new(child);
                match child.attr("type") {
                    Some("hdrfilm") | None => {}
                    Some(other) => b.warn(
                        child,
                        format!("film '{other}' is read as hdrfilm: scotopia's film is X, Y, Z, V′ (render --spectral writes a spectral image)"),
                    ),
                }
                width = positive(child, fp.integer("width", 768)?)?;
                height = positive(child, fp.integer("height", 576)?)?;
                crop = film_crop(&fp, child, width, height)?;
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
    Ok(FilmSettings {
        width,
        height,
        filter,
        crop,
        spp,
    })
}

/// `fov` along `fov_axis`, or Mitsuba's `focal_length` ("50mm" by default)
/// of a 36 × 24 mm film, which sets the field along the diagonal.
pub(super) fn field_of_view(p: &Props, node: &Node) -> Result<(f32, FovAxis), SceneError> {
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

/// A crop window: top-left pixel and size.
type Crop = ([u32; 2], [u32; 2]);

/// Mitsuba's film crop window: `crop_offset_x/y` (0), `crop_width/height`
/// (the rest of the film); `None` when it is the whole film.
fn film_crop(fp: &Props, film: &Node, width: u32, height: u32) -> Result<Option<Crop>, SceneError> {
    let ox = fp.integer("crop_offset_x", 0)?;
    let oy = fp.integer("crop_offset_y", 0)?;
    let cw = fp.integer("crop_width", width as i64 - ox)?;
    let ch = fp.integer("crop_height", height as i64 - oy)?;
    let fits = |o: i64, s: i64, full: u32| o >= 0 && s > 0 && o + s <= full as i64;
    if !(fits(ox, cw, width) && fits(oy, ch, height)) {
        return Err(film.error(format!(
            "crop window {cw}×{ch} at ({ox}, {oy}) does not fit the {width}×{height} film"
        )));
    }
    let whole = ox == 0 && oy == 0 && cw == width as i64 && ch == height as i64;
    Ok((!whole).then_some(([ox as u32, oy as u32], [cw as u32, ch as u32])))
}

/// A film size that overrides the scene's (`scotopia render --res`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Resolution {
    pub width: u32,
    /// `None`: keep the film's aspect ratio.
    pub height: Option<u32>,
}

impl Resolution {
    /// `W` or `WxH`.
    pub fn parse(text: &str) -> Result<Self, String> {
        let bad = || format!("resolution '{text}': give W or WxH, e.g. 640 or 640x480");
        let num = |s: &str| {
            s.trim()
                .parse::<u32>()
                .ok()
                .filter(|&v| (1..=65536).contains(&v))
                .ok_or_else(bad)
        };
        match text.split_once(['x', 'X']) {
            Some((w, h)) => Ok(Self {
                width: num(w)?,
                height: Some(num(h)?),
            }),
            None => Ok(Self {
                width: num(text)?,
                height: None,
            }),
        }
    }

    /// The film size for a scene film of `width`×`height`.
    pub fn size(self, width: u32, height: u32) -> (u32, u32) {
        let h = self.height.unwrap_or_else(|| {
            ((self.width as f64 * height as f64 / width as f64).round() as u32).max(1)
        });
        (self.width, h)
    }
}

impl std::str::FromStr for Resolution {
    type Err = String;

    fn from_str(text: &str) -> Result<Self, String> {
        Self::parse(text)
    }
}

/// `W` or `WxH`, as `parse` reads it.
impl std::fmt::Display for Resolution {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.height {
            Some(h) => write!(f, "{}x{h}", self.width),
            None => write!(f, "{}", self.width),
        }
    }
}

#[cfg(test)]
mod resolution_tests {
    use super::Resolution;

    #[test]
    fn a_resolution_prints_to_the_text_it_reads() {
        for text in ["640", "640x480", "1x65536"] {
            let r: Resolution = text.parse().unwrap();
            assert_eq!(r.to_string(), text);
        }
        assert_eq!("20X10".parse::<Resolution>().unwrap().to_string(), "20x10");
        for bad in ["0", "x", "640x", "65537", "-3", "wide"] {
            let e = bad.parse::<Resolution>().unwrap_err();
            assert!(e.contains("give W or WxH"), "{bad}: {e}");
        }
    }
}
