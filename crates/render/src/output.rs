//! Writing a render: the X, Y, Z, V′ OpenEXR with what a reader needs to
//! know about how it was made.

use std::path::Path;

use scotopia_image::{write_exr, ImageError, Meta};

use crate::camera::{FisheyeMap, Projection};
use crate::integrator::{Quantity, RenderOptions, Rendered, RunFacts};
use crate::scene::Scene;

/// Header attributes of a render: fields of view in degrees, samples per
/// pixel actually completed, the wavelength strategy and K, the seed, the
/// render time, the scene file, and the units.
pub fn render_metadata(
    scene: &Scene,
    options: &RenderOptions,
    rendered: &RunFacts,
    scene_file: &str,
) -> Vec<(&'static str, Meta)> {
    let (fov_x, fov_y) = scene.camera.fov_degrees();
    let mut meta = vec![
        ("fovHorizontalDegrees", Meta::F32(fov_x)),
        ("fovVerticalDegrees", Meta::F32(fov_y)),
        ("samplesPerPixel", Meta::I32(rendered.spp as i32)),
        ("wavelengthStrategy", Meta::Text(options.strategy.name().into())),
        (
            "integrator",
            Meta::Text(rendered.integrator.name().into()),
        ),
        ("clusterSize", Meta::I32(options.cluster.get() as i32)),
        ("guiding", Meta::Text(options.guiding.name().into())),
        ("seed", Meta::I32(options.seed as i32)),
        ("renderSeconds", Meta::F32(rendered.elapsed.as_secs_f32())),
        ("raysTraced", Meta::Text(rendered.rays.to_string())),
        ("sceneFile", Meta::Text(scene_file.into())),
        ("quantity", Meta::Text(rendered.quantity.name().into())),
        (
            "units",
            Meta::Text(match rendered.quantity {
                Quantity::Radiance => "X, Y, Z in cd/m2 (CIE 1931, Km = 683 lm/W); V in scotopic cd/m2 (CIE 1951, K'm = 1700 lm/W)".into(),
                Quantity::Illuminance => "illuminance at the surface each pixel sees: X, Y, Z with Y in lx (CIE 1931, Km = 683 lm/W); V in scotopic lx (CIE 1951, K'm = 1700 lm/W)".into(),
                Quantity::MelanopicEdi => "illuminance at the surface each pixel sees: X, Y, Z with Y in lx (CIE 1931, Km = 683 lm/W); mEDI the melanopic equivalent daylight (D65) illuminance in lx (CIE S 026:2018)".into(),
            }),
        ),
        ("interrupted", Meta::I32(rendered.cancelled as i32)),
        ("renderer", Meta::Text(format!("scotopia {}", env!("CARGO_PKG_VERSION")))),
    ];
    // What `scotopia glare` reads a fisheye picture's geometry from.
    if let Projection::Fisheye(map) = scene.camera.projection {
        meta.push(("projection", Meta::Text(map.name().into())));
    }
    meta
}

/// The Radiance view options of `scene`'s camera, for a Radiance picture
/// of the render (`scotopia_image::radiance`): `-vtv -vh H -vv V` for a
/// perspective camera that is not cropped, `-vta` for an angular fisheye
/// (Radiance has no equisolid view). (Radiance's default view direction
/// and up stand for the camera's: a picture's angles are measured from
/// its own centre and up.)
pub fn radiance_view(scene: &Scene) -> Option<String> {
    let c = &scene.camera;
    let whole = c.crop_offset() == [0, 0] && c.full_size() == [c.width, c.height];
    let (h, v) = c.fov_degrees();
    let kind = match c.projection {
        Projection::Perspective => "v",
        Projection::Fisheye(FisheyeMap::Angular) => "a",
        _ => return None,
    };
    (whole && h > 0.0).then(|| format!("-vt{kind} -vh {h} -vv {v}"))
}

/// Writes channels X, Y, Z, V (V′) of `rendered` to `path`, atomically.
pub fn write_xyzv_exr(
    path: &Path,
    rendered: &Rendered,
    metadata: &[(&str, Meta)],
) -> Result<(), ImageError> {
    let film = &rendered.film;
    let (w, h) = (film.width as usize, film.height as usize);
    write_xyzv_pixels(path, w, h, &film.xyzv(), metadata)
}

/// Writes X, Y, Z, V′ pixels (row-major, `w` × `h`) as channels X, Y, Z,
/// V of an OpenEXR, atomically; when the metadata's quantity is
/// `melanopic-edi` the fourth channel is `mEDI`, so that nothing reads
/// it as V′.
pub fn write_xyzv_pixels(
    path: &Path,
    w: usize,
    h: usize,
    px: &[[f32; 4]],
    metadata: &[(&str, Meta)],
) -> Result<(), ImageError> {
    let channel = |c: usize| px.iter().map(|p| p[c]).collect::<Vec<f32>>();
    write_exr(
        path,
        w,
        h,
        vec![
            ("X".into(), channel(0)),
            ("Y".into(), channel(1)),
            ("Z".into(), channel(2)),
            (fourth_channel(metadata).into(), channel(3)),
        ],
        metadata,
    )
}

/// The name of an image's fourth channel: `V`, or `mEDI` for the
/// quantity `melanopic-edi`.
fn fourth_channel(metadata: &[(&str, Meta)]) -> &'static str {
    let melanopic = metadata.iter().any(|(k, v)| {
        *k == "quantity" && matches!(v, Meta::Text(t) if t == Quantity::MelanopicEdi.name())
    });
    if melanopic {
        "mEDI"
    } else {
        "V"
    }
}

/// The Fichet, Pacanowski & Wilkie 2021 channel name of an emissive band
/// centred at `lambda` nm: `S0.550,000000nm` (a comma as decimal mark).
pub fn spectral_channel_name(lambda: f32) -> String {
    format!("S0.{}nm", format!("{lambda:.6}").replace('.', ","))
}

/// Writes the film's spectral bands as a spectral OpenEXR (Fichet et al.
/// 2021, JCGT 10(3)): one `S0.<λ>nm` channel per band centre, the band's
/// mean spectral radiance, with the layout's `emissiveUnits` attribute.
pub fn write_spectral_exr(
    path: &Path,
    rendered: &Rendered,
    metadata: &[(&str, Meta)],
) -> Result<(), ImageError> {
    let film = &rendered.film;
    let Some(bands) = film.bands else {
        return Err(ImageError::Invalid(format!(
            "{}: the render has no spectral bands",
            path.display()
        )));
    };
    let channels = (0..bands.0)
        .map(|i| (spectral_channel_name(bands.centre(i)), film.band_means(i)))
        .collect();
    let mut meta: Vec<(&str, Meta)> = metadata.to_vec();
    meta.push(("emissiveUnits", Meta::Text("W.m^-2.sr^-1".into())));
    meta.push(("spectralBandWidthNm", Meta::F32(bands.width())));
    write_exr(
        path,
        film.width as usize,
        film.height as usize,
        channels,
        &meta,
    )
}
