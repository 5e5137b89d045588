//! What each route answers: the page, the status, the picture for a
//! page's settings, a pixel's values, and saving. No GET changes anything:
//! each request carries its settings, laid over the command line's.

use std::path::Path;
use std::sync::Arc;

use anyhow::{bail, Context, Result};
use rayon::prelude::*;
use serde_json::json;

use scotopia_image::{encode_png, write_atomic, PngColour, PngSamples, XyzvImage};
use scotopia_render::output::write_xyzv_pixels;
use scotopia_vision::display_owned;
use scotopia_vision::output::{compare_sheet, display_png, PngOptions};

use super::guard::Session;
use super::http::{Reply, Request};
use super::live::Live;
use super::query::{from_json, merge, merge_pairs, View};
use super::server::Handler;

/// The viewer's site: the film shown and the session guarding it.
pub struct Site {
    pub live: Arc<Live>,
    pub session: Session,
}

impl Handler for Site {
    fn admit(&self, request: &Request) -> Result<(), Reply> {
        self.session.check_host(request)
    }

    fn answer(&self, request: &Request) -> Reply {
        let live = &self.live;
        let query = request.query.as_str();
        match (request.method.as_str(), request.path.as_str()) {
            ("GET", "/") => Reply::html(super::page::html(self.session.token())),
            ("GET", "/status") => Reply::json(status(live)),
            ("GET", "/image.png") => image(live, query),
            ("GET", "/pixel") => pixel(live, query),
            ("POST", "/save") => match self.session.check_change(request) {
                Ok(()) => save(live, request),
                Err(refused) => refused,
            },
            (_, "/save") => Reply::error(405, "use POST /save".into()).with("Allow", "POST".into()),
            (_, "/" | "/status" | "/image.png" | "/pixel") => {
                Reply::error(405, "method not allowed".into()).with("Allow", "GET".into())
            }
            (_, path) => Reply::error(
                404,
                format!("no page {path}: try /, /status, /image.png, /pixel or /save"),
            ),
        }
    }
}

/// A path as the page may see it: its file name, no folders.
pub fn file_name(path: &Path) -> String {
    path.file_name()
        .unwrap_or(path.as_os_str())
        .to_string_lossy()
        .into_owned()
}

/// `GET /status` (file names only: the page needs no folders).
pub fn status(live: &Live) -> serde_json::Value {
    let f = live.frame();
    json!({
        "name": live.name,
        "phase": live.phase().name(),
        "spp": f.spp,
        "target_spp": live.target_spp,
        "seconds": f.seconds,
        "width": f.image.width,
        "height": f.image.height,
        "fov": f.image.fov_horizontal,
        "quantity": f.image.quantity.as_deref().unwrap_or("radiance"),
        "settings": live.start,
        "output": file_name(&live.output),
    })
}

/// `GET /image.png?SETTINGS`: the picture, with what the eye did in its
/// headers (mode, adaptation luminance) and the film's spp.
pub fn image(live: &Live, query: &str) -> Reply {
    let given =
        form_urlencoded::parse(query.as_bytes()).map(|(k, v)| (k.into_owned(), v.into_owned()));
    match picture(live, given) {
        Ok((bytes, headers)) => Reply::png(bytes, headers),
        Err(e) => Reply::error(400, format!("{e:#}")),
    }
}

type Headers = Vec<(&'static str, String)>;

/// The picture for `given` settings over the command line's.
fn picture(
    live: &Live,
    given: impl IntoIterator<Item = (String, String)>,
) -> Result<(Vec<u8>, Headers)> {
    let (_, settings) = merge_pairs(&live.start, given, &[])?;
    let (view, k) = settings.view()?;
    let frame = live.frame();
    // The film at the light level, in one pass (the frame is shared).
    let film = &frame.image;
    let image = XyzvImage {
        width: film.width,
        height: film.height,
        pixels: film.pixels.par_iter().map(|p| p.map(|v| v * k)).collect(),
        fov_horizontal: film.fov_horizontal,
        quantity: film.quantity.clone(),
        projection: film.projection.clone(),
        notes: Vec::new(),
    };
    let (w, h) = (image.width, image.height);
    let mut headers = vec![("X-Scotopia-Spp", frame.spp.to_string())];
    let name = "image.png";
    // Checked in every view, so that a bad setting is never kept.
    let (params, png, _) = settings.vision.params(w, image.fov_horizontal)?;
    let png = PngOptions {
        stored: true,
        ..png
    };
    let bytes = if view == View::FalseColour {
        let map = crate::false_colour::map(
            &settings.false_colour,
            settings.range.as_deref(),
            settings.log,
            &image,
            &live.name,
        )?;
        headers.push(("X-Scotopia-Legend", map.legend));
        let (mw, mh) = (map.width as u32, map.height as u32);
        encode_png(name, mw, mh, PngSamples::Rgb8(&map.rgb), PngColour::SRGB)?
    } else {
        let (shown, bytes) = if view == View::Stages {
            let (shown, (sw, sh, rgb)) = compare_sheet(&image.pixels, w, h, &params, h.min(360));
            let (sw, sh) = (sw as u32, sh as u32);
            let bytes = encode_png(name, sw, sh, PngSamples::Rgb8(&rgb), PngColour::SRGB)?;
            (shown, bytes)
        } else {
            let shown = display_owned(image.pixels, w, h, &params);
            let bytes = display_png(name, &shown, &params, png)?;
            (shown, bytes)
        };
        let state = &shown.report.state;
        headers.push(("X-Scotopia-Mode", state.mode.name().into()));
        headers.push(("X-Scotopia-Adaptation", format!("{:.4e}", state.luminance)));
        bytes
    };
    Ok((bytes, headers))
}

/// `GET /pixel?x=X&y=Y[&scale=K]`: the pixel's X, Y, Z, V′ (times the
/// light level), luminance, chromaticity and S/P ratio.
pub fn pixel(live: &Live, query: &str) -> Reply {
    match pixel_values(live, query) {
        Ok(v) => Reply::json(v),
        Err(e) => Reply::error(400, format!("{e:#}")),
    }
}

fn pixel_values(live: &Live, query: &str) -> Result<serde_json::Value> {
    let (_, settings) = merge(&live.start, query, &["x", "y"])?;
    let (_, k) = settings.view()?;
    let coordinate = |name: &str| -> Result<usize> {
        let text = form_urlencoded::parse(query.as_bytes())
            .find(|(key, _)| key == name)
            .map(|(_, v)| v.into_owned())
            .with_context(|| format!("give {name}, a pixel coordinate"))?;
        text.parse()
            .with_context(|| format!("{name}={text}: not a pixel coordinate"))
    };
    let (x, y) = (coordinate("x")?, coordinate("y")?);
    let frame = live.frame();
    let image = &frame.image;
    if x >= image.width || y >= image.height {
        bail!(
            "pixel ({x}, {y}) is outside the {}×{} image",
            image.width,
            image.height
        );
    }
    let [cx, cy, cz, cv] = image.pixels[y * image.width + x].map(|v| f64::from(v * k));
    let sum = cx + cy + cz;
    let unit = match image.quantity.as_deref() {
        Some("illuminance") => "lx",
        _ => "cd/m²",
    };
    Ok(json!({
        "x": x,
        "y": y,
        "X": cx,
        "Y": cy,
        "Z": cz,
        "V": cv,
        "luminance": cy,
        "unit": unit,
        "chromaticity": (sum > 0.0).then(|| [cx / sum, cy / sum]),
        "sp_ratio": (cy > 0.0).then(|| cv / cy),
        "spp": frame.spp,
    }))
}

/// `POST /save` with the settings as a JSON object: the film as an EXR at
/// the output path and the picture for those settings as a PNG beside it.
pub fn save(live: &Live, request: &Request) -> Reply {
    if !request.query.is_empty() {
        return Reply::error(
            400,
            "POST /save takes its settings as JSON in the body, not in the query".into(),
        );
    }
    let given = match from_json(&request.body) {
        Ok(g) => g,
        Err(e) => return Reply::error(400, format!("{e:#}")),
    };
    // Bad settings are the request's fault; a failed write is not.
    let bytes = match picture(live, given) {
        Ok((bytes, _)) => bytes,
        Err(e) => return Reply::error(400, format!("{e:#}")),
    };
    match save_files(live, &bytes) {
        Ok(v) => Reply::json(v),
        Err(e) => Reply::error(500, format!("{e:#}")),
    }
}

fn save_files(live: &Live, bytes: &[u8]) -> Result<serde_json::Value> {
    let frame = live.frame();
    let image = &frame.image;
    let exr = &live.output;
    write_xyzv_pixels(exr, image.width, image.height, &image.pixels, &frame.meta)?;
    let png = exr.with_extension("png");
    write_atomic(&png, bytes).with_context(|| format!("{}: cannot write", png.display()))?;
    eprintln!(
        "scotopia: saved {} spp → {} and {}",
        frame.spp,
        exr.display(),
        png.display()
    );
    Ok(json!({
        "exr": file_name(exr),
        "png": file_name(&png),
        "spp": frame.spp,
    }))
}
