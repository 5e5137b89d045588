//! `scotopia measure` for Python: illuminance at points of a scene.

use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::atomic::AtomicBool;

use numpy::{AllowTypeChange, IntoPyArray, PyArrayLike2};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use scotopia_render::integrator::{measure_setup, Receiver, ReceiverShape, RenderOptions, Setup};
use scotopia_render::math::Vec3;
use scotopia_scene::{load_scene_with, LoadOptions};
use scotopia_vision::mode::Mesopic;

/// Measures illuminance at points of a Mitsuba 3 XML scene (the `scotopia
/// measure` verb) with the path tracer's own transport. `points`: an
/// N × 6 array of x, y, z, nx, ny, nz (the normal is the side each
/// receiver faces). Returns a dict of length-N float64 arrays: `E_lx`
/// (photopic illuminance, lx), `E_lx_se` (its standard error), `Es_lx`
/// (scotopic, K′m = 1700 lm/W), `Es_lx_se`, `SP` (their ratio), and CIE
/// 191:2010 figures of a Lambertian surface of `reflectance` there:
/// `L_cdm2` (its luminance ρE/π), `m` (the adaptation coefficient at it)
/// and `Lmes_cdm2` (the mesopic luminance); then the α-opic equivalent
/// daylight (D65) illuminances of CIE S 026, lx: `scEDI_lx`, `mcEDI_lx`,
/// `lcEDI_lx`, `rhEDI_lx`, `mEDI_lx` (and each with `_se`, its standard
/// error). `spp`: samples per point
/// (default: the scene's samples per pixel). `receiver`: "plane" (the
/// illuminance of the plane of each normal), "cylindrical" (E_z, EN
/// 12464-1: the mean over a small cylinder along `up`; the normals are not
/// used) or "semicylindrical" (E_sc, EN 13201-2: a half-cylinder along
/// `up` facing each normal's direction across it); for the cylinders
/// `L_cdm2`, `m` and `Lmes_cdm2` are NaN. `observer`: an eye (x, y, z)
/// whose view of each point is measured too (the points should lie on a
/// surface: the road's, a `roadsurface` BSDF giving the CIE r-tables):
/// `Lobs_cdm2`, `Lobs_cdm2_se`, `Lobs_SP` (its scotopic over photopic
/// luminance) and `Lobs_mes_cdm2` (CIE 191's mesopic luminance).
/// `direct`: light straight from the emitters alone, as EN 13201-3's
/// method counts it. The scene needs no sensor.
/// The GIL is released while measuring; Ctrl-C stops it and raises
/// KeyboardInterrupt.
#[pyfunction]
#[pyo3(signature = (path, points, spp = None, seed = 0, wavelengths = "swc", cluster = 4, params = None, reflectance = 1.0, receiver = "plane", up = (0.0, 1.0, 0.0), observer = None, direct = false))]
#[allow(clippy::too_many_arguments)]
fn measure<'py>(
    py: Python<'py>,
    path: PathBuf,
    points: PyArrayLike2<'py, f64, AllowTypeChange>,
    spp: Option<u32>,
    seed: u32,
    wavelengths: &str,
    cluster: usize,
    params: Option<HashMap<String, String>>,
    reflectance: f64,
    receiver: &str,
    up: (f32, f32, f32),
    observer: Option<(f32, f32, f32)>,
    direct: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let err = |e: String| PyValueError::new_err(e);
    let reflectance = scotopia_vision::mode::reflectance(reflectance)
        .map_err(|e| err(format!("reflectance {e}")))?;
    let shape =
        ReceiverShape::from_name(receiver, Vec3::new(up.0, up.1, up.2)).ok_or_else(|| {
            err(format!(
                "receiver '{receiver}': use plane, cylindrical or semicylindrical"
            ))
        })?;
    let strategy = crate::render::wavelength_strategy(wavelengths)?;
    let cluster = crate::render::cluster_size(cluster)?;
    let a = points.as_array();
    if a.ncols() != 6 || a.nrows() == 0 {
        return Err(err(format!(
            "points: expected an N × 6 array (x, y, z, nx, ny, nz), got shape {:?}",
            a.shape()
        )));
    }
    let receivers: Vec<Receiver> = a
        .rows()
        .into_iter()
        .map(|r| {
            let v: Vec<f32> = r.iter().map(|&x| x as f32).collect();
            Receiver {
                p: Vec3::new(v[0], v[1], v[2]),
                n: Vec3::new(v[3], v[4], v[5]),
            }
        })
        .collect();
    let scene = sensorless_scene(&path, params)?;
    let options = RenderOptions {
        spp,
        seed,
        strategy,
        cluster,
        ..RenderOptions::default()
    };
    // Ctrl-C stops the measurement (nothing is returned, as the CLI
    // writes nothing) and raises KeyboardInterrupt.
    let cancel = AtomicBool::new(false);
    let (measured, interrupted) = crate::interrupt::interruptible(py, &cancel, || {
        let setup = Setup {
            shape,
            observer: observer.map(|(x, y, z)| Vec3::new(x, y, z)),
            direct,
            ..Setup::default()
        };
        measure_setup(&scene, &receivers, setup, &options, &cancel, &|_, _| {})
    });
    if let Some(e) = interrupted {
        return Err(e);
    }
    let measured = measured.map_err(|e| err(e.to_string()))?;
    let d = PyDict::new(py);
    let column = |f: fn(&scotopia_render::integrator::Measured) -> f64| {
        measured
            .iter()
            .map(f)
            .collect::<Vec<f64>>()
            .into_pyarray(py)
    };
    d.set_item("E_lx", column(|m| m.e))?;
    d.set_item("E_lx_se", column(|m| m.e_se))?;
    d.set_item("Es_lx", column(|m| m.es))?;
    d.set_item("Es_lx_se", column(|m| m.es_se))?;
    d.set_item("SP", column(|m| m.sp()))?;
    let mesopic: Vec<Mesopic> = measured
        .iter()
        .map(|m| scotopia_cli::measure::surface_mesopic(m, reflectance, shape))
        .collect();
    let figure =
        |f: fn(&Mesopic) -> f64| mesopic.iter().map(f).collect::<Vec<f64>>().into_pyarray(py);
    d.set_item("L_cdm2", figure(|m| m.luminance))?;
    d.set_item("m", figure(|m| m.m))?;
    d.set_item("Lmes_cdm2", figure(|m| m.mesopic))?;
    for (k, name) in ["scEDI_lx", "mcEDI_lx", "lcEDI_lx", "rhEDI_lx", "mEDI_lx"]
        .into_iter()
        .enumerate()
    {
        let of = |se: bool| {
            measured
                .iter()
                .map(|m| if se { m.edi_se[k] } else { m.edi[k] })
                .collect::<Vec<f64>>()
                .into_pyarray(py)
        };
        d.set_item(name, of(false))?;
        d.set_item(format!("{name}_se"), of(true))?;
    }
    if observer.is_some() {
        let seen: Vec<[f64; 4]> = measured
            .iter()
            .map(scotopia_cli::measure::observed)
            .collect();
        for (k, name) in ["Lobs_cdm2", "Lobs_cdm2_se", "Lobs_SP", "Lobs_mes_cdm2"]
            .into_iter()
            .enumerate()
        {
            d.set_item(
                name,
                seen.iter()
                    .map(|s| s[k])
                    .collect::<Vec<f64>>()
                    .into_pyarray(py),
            )?;
        }
    }
    Ok(d)
}

/// A scene for measuring, which needs no sensor, with `params` set.
pub(crate) fn sensorless_scene(
    path: &std::path::Path,
    params: Option<HashMap<String, String>>,
) -> PyResult<scotopia_render::scene::Scene> {
    let load = LoadOptions {
        sensor_optional: true,
        ..LoadOptions::default()
    };
    load_scene_with(path, &params.unwrap_or_default(), &load)
        .map_err(|e| PyValueError::new_err(e.to_string()))
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(measure, m)?)?;
    Ok(())
}
