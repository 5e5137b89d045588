//! `scotopia road`: EN 13201-3's luminance method on a straight road of a
//! scene: the grid and observers of `scotopia_render::integrator::Road`,
//! the luminance each observer sees at every point (by `measure`'s
//! observer, through the full spectral transport or `--direct`), and per
//! observer L_av, U_o, U_l along its lane's centre line and the threshold
//! increment TI from each luminaire's illuminance at its eye.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};

use anyhow::{bail, Context, Result};
use scotopia_render::integrator::{
    lights_at_eye, measure_setup, GridPoint, Receiver, RenderOptions, Road, Setup,
};
use scotopia_render::math::Vec3;
use scotopia_render::scene::Scene;
use scotopia_scene::{load_scene_tracked, LoadOptions};
use scotopia_vision::ratings::{road_veiling, threshold_increment, TI_AGE};

use crate::info::{load_options, parameters};
use crate::render::{cancel_on_interrupt, simd_level};

#[derive(clap::Args)]
pub struct Args {
    /// The scene (Mitsuba 3 XML) with the road and its luminaires; a
    /// <bsdf type="roadsurface"> on the road gives the CIE r-tables. Its
    /// sensor is not used and may be absent.
    scene: PathBuf,
    /// The field's start: the point of the road's first edge where the
    /// field between two luminaires of a row begins, X,Y,Z.
    #[arg(long, value_name = "X,Y,Z", value_parser = crate::numbers::point)]
    start: [f32; 3],
    /// The direction of travel, X,Y,Z: the observers look along it.
    #[arg(long, value_name = "X,Y,Z", value_parser = crate::numbers::direction)]
    along: [f32; 3],
    /// Across the road, from the first lane to the last, X,Y,Z.
    #[arg(long, value_name = "X,Y,Z", value_parser = crate::numbers::direction)]
    across: [f32; 3],
    /// Up (Mitsuba's scenes are y-up).
    #[arg(long, default_value = "0,1,0", value_name = "X,Y,Z", value_parser = crate::numbers::direction)]
    up: [f32; 3],
    /// The luminaires' spacing along a row, m: the field's length.
    #[arg(long, value_name = "S")]
    spacing: f32,
    /// Lanes.
    #[arg(long, default_value_t = 2)]
    lanes: u32,
    /// A lane's width, m.
    #[arg(long, default_value_t = 3.5, value_name = "W")]
    lane_width: f32,
    /// The observer's age for TI, years (EN 13201-3's k = 9.86·(1 + (A/66.4)⁴)
    /// is about 10 at its default 23).
    #[arg(long, default_value_t = TI_AGE, value_parser = crate::numbers::age)]
    age: f64,
    /// Count light straight from the luminaires alone, as the standard's
    /// method does; without it the full transport (façades,
    /// interreflection, sky).
    #[arg(long)]
    direct: bool,
    /// Write the grid, one row per point and observer: lane, row, x, y, z,
    /// observer, L_cdm2, L_cdm2_se, SP, Lmes_cdm2 (CSV).
    #[arg(short, long, value_name = "OUT.csv")]
    output: Option<PathBuf>,
    /// Write the grid's points as a `measure` points file (x,y,z,nx,ny,nz).
    #[arg(long, value_name = "POINTS.csv")]
    grid: Option<PathBuf>,
    /// Print one JSON object instead of the table.
    #[arg(long)]
    json: bool,
    /// Samples per point (default: the scene's samples per pixel).
    #[arg(long)]
    spp: Option<u32>,
    /// Set a scene parameter, overriding its <default> (repeatable).
    #[arg(short = 'D', value_name = "NAME=VALUE")]
    define: Vec<String>,
    /// Seed of the sample sequence.
    #[arg(long, default_value_t = 0)]
    seed: u32,
}

/// What one observer (of its lane) finds.
#[derive(Debug, Clone, PartialEq)]
pub struct Observed {
    pub lane: u32,
    pub eye: [f32; 3],
    /// The grid's average luminance (cd/m²), overall uniformity
    /// L_min/L_av, and longitudinal uniformity L_min/L_max along this
    /// lane's centre line.
    pub l_av: f64,
    pub u_o: f64,
    pub u_l: f64,
    /// The veiling luminance (cd/m²) of the luminaires between 1.5° and
    /// 60° of the line of sight and below the vehicle roof's 20° cut-off,
    /// and the threshold increment TI (%), `None` for a dark road.
    pub l_v: f64,
    pub ti: Option<f64>,
    /// Per grid point: luminance, its standard error, S/P and CIE 191
    /// mesopic luminance.
    pub points: Vec<[f64; 4]>,
}

/// The luminance method's result: the grid and each lane's observer.
#[derive(Debug, Clone, PartialEq)]
pub struct RoadReport {
    pub grid: Vec<GridPoint>,
    pub observers: Vec<Observed>,
}

/// The vehicle roof's cut-off above the horizontal (EN 13201-3): lamps
/// seen higher are screened from the driver.
pub const ROOF_CUT_OFF_DEG: f64 = 20.0;

/// EN 13201-3's luminance method on `road` of `scene`.
pub fn evaluate(
    scene: &Scene,
    road: Road,
    options: &RenderOptions,
    (age, direct): (f64, bool),
    cancel: &AtomicBool,
) -> Result<RoadReport> {
    let road = road.checked()?;
    let grid = road.grid();
    let receivers: Vec<Receiver> = grid
        .iter()
        .map(|g| Receiver { p: g.p, n: road.up })
        .collect();
    let los = road.line_of_sight();
    let mut observers = Vec::new();
    for lane in 0..road.lanes {
        let eye = road.observer(lane);
        let setup = Setup {
            observer: Some(eye),
            direct,
            seen_only: true,
            ..Setup::default()
        };
        let m = measure_setup(scene, &receivers, setup, options, cancel, &|_, _| {})?;
        if cancel.load(Ordering::Relaxed) {
            bail!("interrupted");
        }
        let points: Vec<[f64; 4]> = m.iter().map(crate::measure::observed).collect();
        let l: Vec<f64> = points.iter().map(|p| p[0]).collect();
        let l_av = l.iter().sum::<f64>() / l.len() as f64;
        let min = l.iter().copied().fold(f64::INFINITY, f64::min);
        let centre: Vec<f64> = grid
            .iter()
            .zip(&l)
            .filter(|(g, _)| g.lane == lane && g.centre)
            .map(|(_, &v)| v)
            .collect();
        let (cmin, cmax) = centre
            .iter()
            .fold((f64::INFINITY, 0.0f64), |(a, b), &v| (a.min(v), b.max(v)));
        // TI: each luminaire below the roof's cut-off, E_k at θ_k.
        let lamps: Vec<(f64, f64)> = lights_at_eye(scene, eye, los, options)?
            .into_iter()
            .filter(|a| {
                let elevation = f64::from(a.direction.dot(road.up)).asin().to_degrees();
                elevation <= ROOF_CUT_OFF_DEG
            })
            .map(|a| {
                let theta = f64::from(a.direction.dot(los))
                    .clamp(-1.0, 1.0)
                    .acos()
                    .to_degrees();
                (a.e, theta)
            })
            .collect();
        let l_v = road_veiling(&lamps, age);
        observers.push(Observed {
            lane,
            eye: eye.to_array(),
            l_av,
            u_o: if l_av > 0.0 { min / l_av } else { f64::NAN },
            u_l: if cmax > 0.0 { cmin / cmax } else { f64::NAN },
            l_v,
            ti: threshold_increment(l_v, l_av),
            points,
        });
    }
    Ok(RoadReport { grid, observers })
}

pub fn run(args: Args) -> Result<()> {
    simd_level()?;
    if args.spp == Some(0) {
        bail!("--spp must be positive");
    }
    let outputs: Vec<(&str, &Path)> = [("-o", &args.output), ("--grid", &args.grid)]
        .into_iter()
        .filter_map(|(flag, p)| p.as_deref().map(|p| (flag, p)))
        .collect();
    scotopia_image::check_outputs(&[("the scene", &*args.scene)], &outputs)
        .map_err(anyhow::Error::msg)?;
    let load = LoadOptions {
        sensor_optional: true,
        ..load_options(None)
    };
    let (scene, _) = load_scene_tracked(&args.scene, &parameters(&args.define)?, &load)?;
    for w in &scene.warnings {
        eprintln!("scotopia: warning: {w}");
    }
    let v = |[x, y, z]: [f32; 3]| Vec3::new(x, y, z);
    let road = Road {
        start: v(args.start),
        along: v(args.along),
        across: v(args.across),
        up: v(args.up),
        spacing: args.spacing,
        lanes: args.lanes,
        lane_width: args.lane_width,
    };
    let options = RenderOptions {
        spp: args.spp,
        seed: args.seed,
        ..RenderOptions::default()
    };
    let cancel = cancel_on_interrupt()?;
    let report = evaluate(&scene, road, &options, (args.age, args.direct), &cancel)?;
    if let Some(path) = &args.grid {
        let up = v(args.up).normalize();
        let mut csv = String::from("x,y,z,nx,ny,nz\n");
        for g in &report.grid {
            let _ = writeln!(
                csv,
                "{},{},{},{},{},{}",
                g.p.x, g.p.y, g.p.z, up.x, up.y, up.z
            );
        }
        scotopia_image::write_atomic(path, csv.as_bytes())
            .with_context(|| format!("{}: cannot write", path.display()))?;
    }
    if let Some(path) = &args.output {
        let mut csv = String::from("lane,row,x,y,z,observer,L_cdm2,L_cdm2_se,SP,Lmes_cdm2\n");
        for o in &report.observers {
            for (g, [l, se, sp, mes]) in report.grid.iter().zip(&o.points) {
                let _ = writeln!(
                    csv,
                    "{},{},{},{},{},{},{l:.6e},{se:.3e},{sp:.4},{mes:.6e}",
                    g.lane, g.row, g.p.x, g.p.y, g.p.z, o.lane
                );
            }
        }
        scotopia_image::write_atomic(path, csv.as_bytes())
            .with_context(|| format!("{}: cannot write", path.display()))?;
    }
    if args.json {
        let json = serde_json::json!({
            "direct": args.direct,
            "age": args.age,
            "points": report.grid.len(),
            "observers": report.observers.iter().map(|o| serde_json::json!({
                "lane": o.lane,
                "eye": o.eye,
                "L_av_cdm2": o.l_av,
                "U_o": o.u_o,
                "U_l": o.u_l,
                "Lv_cdm2": o.l_v,
                "TI_percent": o.ti,
            })).collect::<Vec<_>>(),
        });
        crate::print(&format!("{json}\n"))
    } else {
        let mut text = format!(
            "EN 13201-3 luminance method: {} points, {} ({}), observers 60 m before the field, 1.5 m up\n\
             lane  L_av cd/m²   U_o    U_l    L_v cd/m²  TI %\n",
            report.grid.len(),
            if args.direct { "direct light" } else { "full transport" },
            scene_name(&args.scene)
        );
        for o in &report.observers {
            let ti = o.ti.map_or("—".to_string(), |t| format!("{t:.1}"));
            let _ = writeln!(
                text,
                "{:>4}  {:>10.3}  {:>5.2}  {:>5.2}  {:>9.4}  {ti:>5}",
                o.lane + 1,
                o.l_av,
                o.u_o,
                o.u_l,
                o.l_v
            );
        }
        crate::print(&text)
    }
}

fn scene_name(path: &Path) -> String {
    path.file_name().map_or_else(
        || path.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    )
}
