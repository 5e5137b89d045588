//! `scotopia measure`: illuminance at points of a scene, as a lighting
//! designer's calculation grid.

use std::fmt::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::Ordering;

use anyhow::{bail, Context, Result};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

use scotopia_render::integrator::{
    measure_setup, ClusterSize, Measured, Receiver, ReceiverShape, RenderError, RenderOptions,
    Setup,
};
use scotopia_render::math::Vec3;
use scotopia_render::wavelength::WavelengthStrategy;
use scotopia_scene::{load_scene_tracked, LoadOptions};
use scotopia_vision::mode::Mesopic;

use crate::info::{load_options, parameters};
use crate::render::{cancel_on_interrupt, simd_level};

#[derive(clap::Args)]
pub struct Args {
    /// The scene (Mitsuba 3 XML). Its sensor is not used and may be absent.
    scene: PathBuf,
    /// The points: CSV rows `x,y,z,nx,ny,nz` (scene units; the normal is
    /// the side the receiver faces, any length but zero). The header line
    /// x,y,z,nx,ny,nz, blank lines and lines starting with # are skipped;
    /// any other row that is not six numbers is an error naming its line.
    /// At most 64 MiB.
    #[arg(long, value_name = "POINTS.csv")]
    points: PathBuf,
    /// The output: the points with photopic and scotopic illuminance, their
    /// standard errors and the S/P ratio, then CIE 191 mesopic figures of
    /// the surface there (see --reflectance), then the five α-opic
    /// equivalent daylight illuminances of CIE S 026 (S-, M-, L-cone,
    /// rhodopic, melanopic: lx of D65 that would stimulate the receptor as
    /// much), as CSV with the header
    /// x,y,z,nx,ny,nz,E_lx,E_lx_se,Es_lx,Es_lx_se,SP,L_cdm2,m,Lmes_cdm2,
    /// scEDI_lx,mcEDI_lx,lcEDI_lx,rhEDI_lx,mEDI_lx.
    #[arg(short, long, value_name = "OUT.csv")]
    output: PathBuf,
    /// Reflectance of the (Lambertian) surface at the points, for the
    /// mesopic columns: its luminance L = ρE/π (cd/m²), CIE 191's
    /// adaptation coefficient m at L and the mesopic luminance L_mes. The
    /// default 1 (the white receiver) errs towards photopic; an asphalt
    /// road is about 0.1.
    #[arg(long, default_value_t = 1.0, value_name = "ρ", value_parser = reflectance)]
    reflectance: f64,
    /// What each point measures: the illuminance of the plane of its
    /// normal, the cylindrical illuminance E_z (EN 12464-1: the mean over
    /// a small cylinder along --up; the normal is not used) or the
    /// semi-cylindrical E_sc (EN 13201-2: a half-cylinder along --up facing
    /// the normal's direction across it). For the cylinders the columns
    /// L_cdm2, m and Lmes_cdm2, figures of a surface, are nan.
    #[arg(
        long,
        default_value = "plane",
        value_name = "plane|cylindrical|semicylindrical"
    )]
    receiver: String,
    /// The cylinders' axis, X,Y,Z (Mitsuba's scenes are y-up).
    #[arg(long, default_value = "0,1,0", value_name = "X,Y,Z", value_parser = crate::numbers::direction)]
    up: [f32; 3],
    /// An eye at X,Y,Z: also the luminance it sees at each point (which
    /// should lie on a surface: the road's, for EN 13201-3's luminance
    /// method; a <bsdf type="roadsurface"> gives the CIE r-tables), in the
    /// columns Lobs_cdm2, Lobs_cdm2_se, Lobs_SP (its scotopic over its
    /// photopic luminance) and Lobs_mes_cdm2 (CIE 191's mesopic luminance).
    #[arg(long, value_name = "X,Y,Z", value_parser = crate::numbers::point)]
    observer: Option<[f32; 3]>,
    /// Count light straight from the emitters alone, as the standards'
    /// methods do (illuminance, and the luminance the observer sees);
    /// without it the full transport: façades, interreflection, sky.
    #[arg(long)]
    direct: bool,
    /// Samples per point (default: the scene's samples per pixel).
    #[arg(long)]
    spp: Option<u32>,
    /// Set a scene parameter, overriding its <default> (repeatable).
    #[arg(short = 'D', value_name = "NAME=VALUE")]
    define: Vec<String>,
    /// Worker threads (default: all cores; at most 4096).
    #[arg(long, value_parser = crate::numbers::threads)]
    threads: Option<usize>,
    /// Seed of the sample sequence: the same seed gives the same figures.
    #[arg(long, default_value_t = 0)]
    seed: u32,
    /// How paths choose wavelengths: swc, hero or single.
    #[arg(long, default_value = "swc", value_name = "swc|hero|single")]
    wavelengths: WavelengthStrategy,
    /// Wavelengths per path: 1, 2, 4, 8 or 16.
    #[arg(long, default_value = "4", value_name = "K")]
    cluster: ClusterSize,
}

/// The largest points file read: a calculation grid of a million points
/// is ~40 MiB of text, so 64 MiB (the limit of the other data files)
/// suffices and stops `/dev/zero` or a runaway file at once.
pub const POINTS_FILE_LIMIT: u64 = 64 * scotopia_color::io::MIB;

/// The header a points file may start with (any case, fields quoted or not).
const POINT_COLUMNS: [&str; 6] = ["x", "y", "z", "nx", "ny", "nz"];

/// The receivers of a points file, each with its line; errors name the
/// file and line.
pub fn read_points(path: &Path) -> Result<Vec<(Receiver, usize)>> {
    let name = path.display().to_string();
    let bytes = scotopia_color::io::read_limited(path, POINTS_FILE_LIMIT)
        .with_context(|| format!("{name}: cannot read the points"))?;
    let text = String::from_utf8(bytes).map_err(|e| {
        anyhow::anyhow!(
            "{name}: not UTF-8 text (invalid byte at offset {})",
            e.utf8_error().valid_up_to()
        )
    })?;
    parse_points(&text, &name)
}

/// The receivers of a points file's text; `name` names it in errors.
/// Rows `x,y,z,nx,ny,nz`; blank lines and `#` lines skipped; lines end in
/// LF, CRLF or CR; a UTF-8 byte-order mark is skipped. A header is known
/// by its words (x,y,z,nx,ny,nz, before the first point), so any other
/// row that is not six numbers — a typo in the first row too — is an
/// error naming its line, never a point silently lost. Numbers must be
/// finite in f32, where the renderer works; a normal need not be of unit
/// length (the measurement normalises it) but must not be zero.
pub fn parse_points(text: &str, name: &str) -> Result<Vec<(Receiver, usize)>> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut out = Vec::new();
    for (i, line) in scotopia_color::io::lines(text).enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let at = || format!("{name}:{}", i + 1);
        let fields: Vec<&str> = line.split(',').map(str::trim).collect();
        if out.is_empty() && is_header(&fields) {
            continue;
        }
        let numbers: Option<Vec<f64>> = fields.iter().map(|f| f.parse::<f64>().ok()).collect();
        let Some(v) = numbers else {
            bail!(
                "{}: expected six numbers x,y,z,nx,ny,nz (or, before the first point, the header \
                 x,y,z,nx,ny,nz), found {line:?}",
                at()
            );
        };
        if v.len() != 6 {
            bail!(
                "{}: expected six numbers x,y,z,nx,ny,nz, found {}",
                at(),
                v.len()
            );
        }
        if v.iter().any(|x| !(*x as f32).is_finite()) {
            bail!(
                "{}: every number must be finite (within ±3.4e38, single precision)",
                at()
            );
        }
        let n = Vec3::new(v[3] as f32, v[4] as f32, v[5] as f32);
        if n.abs().max_component() == 0.0 {
            bail!(
                "{}: the normal ({}, {}, {}) is zero",
                at(),
                v[3],
                v[4],
                v[5]
            );
        }
        let p = Vec3::new(v[0] as f32, v[1] as f32, v[2] as f32);
        out.push((Receiver { p, n }, i + 1));
    }
    if out.is_empty() {
        bail!("{name}: no points");
    }
    Ok(out)
}

/// The fields are the header's words.
fn is_header(fields: &[&str]) -> bool {
    fields.len() == POINT_COLUMNS.len()
        && fields.iter().zip(POINT_COLUMNS).all(|(f, want)| {
            f.trim_matches(|c| c == '"' || c == '\'')
                .trim()
                .eq_ignore_ascii_case(want)
        })
}

/// The output's columns.
pub const HEADER: &str = "x,y,z,nx,ny,nz,E_lx,E_lx_se,Es_lx,Es_lx_se,SP,L_cdm2,m,Lmes_cdm2,\
scEDI_lx,mcEDI_lx,lcEDI_lx,rhEDI_lx,mEDI_lx\n";

/// The columns `--observer` adds.
pub const OBSERVER_COLUMNS: &str = ",Lobs_cdm2,Lobs_cdm2_se,Lobs_SP,Lobs_mes_cdm2\n";

/// What the observer saw at a point: its luminance, standard error, S/P
/// and CIE 191 mesopic luminance.
pub fn observed(m: &Measured) -> [f64; 4] {
    let sp = if m.lobs > 0.0 {
        m.lobs_scotopic / m.lobs
    } else {
        f64::NAN
    };
    let mes = scotopia_vision::mode::mesopic_luminance(m.lobs, sp);
    [m.lobs, m.lobs_se, sp, mes]
}

/// The receivers `--receiver` names, along `up`.
pub fn receiver_shape(name: &str, [x, y, z]: [f32; 3]) -> Result<ReceiverShape> {
    ReceiverShape::from_name(name, Vec3::new(x, y, z))
        .with_context(|| format!("--receiver {name}: use plane, cylindrical or semicylindrical"))
}

/// CIE 191's figures of a surface of `reflectance` receiving what `m`
/// measured; NaN for a cylinder, whose mean illuminance lights no surface.
pub fn surface_mesopic(m: &Measured, reflectance: f64, shape: ReceiverShape) -> Mesopic {
    let mut mes = Mesopic::of_surface(m.e, m.sp(), reflectance);
    if shape != ReceiverShape::Plane {
        (mes.luminance, mes.m, mes.mesopic) = (f64::NAN, f64::NAN, f64::NAN);
    }
    mes
}

fn reflectance(text: &str) -> Result<f64, String> {
    let rho = text
        .trim()
        .parse::<f64>()
        .map_err(|_| format!("'{text}': give a reflectance from 0 to 1"))?;
    scotopia_vision::mode::reflectance(rho)
}

pub fn run(args: Args) -> Result<()> {
    simd_level()?;
    if args.spp == Some(0) {
        bail!("--spp must be positive");
    }
    let output: &[(&str, &Path)] = &[("-o", &args.output)];
    let inputs = [
        ("the scene", &*args.scene),
        ("the --points file", &*args.points),
    ];
    scotopia_image::check_outputs(&inputs, output).map_err(anyhow::Error::msg)?;
    let (receivers, lines): (Vec<Receiver>, Vec<usize>) =
        read_points(&args.points)?.into_iter().unzip();
    let load = LoadOptions {
        sensor_optional: true,
        ..load_options(None)
    };
    let (scene, files) = load_scene_tracked(&args.scene, &parameters(&args.define)?, &load)?;
    let read = crate::render::named_inputs("the scene", &files);
    scotopia_image::check_outputs(&read, output).map_err(anyhow::Error::msg)?;
    for w in &scene.warnings {
        eprintln!("scotopia: warning: {w}");
    }
    let options = RenderOptions {
        spp: args.spp,
        seed: args.seed,
        strategy: args.wavelengths,
        cluster: args.cluster,
        ..RenderOptions::default()
    };
    let cancel = cancel_on_interrupt()?;
    let bar = ProgressBar::new(receivers.len() as u64);
    bar.set_style(
        ProgressStyle::with_template("{bar:40} {pos}/{len} points  {elapsed} elapsed, {eta} left")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    if !std::io::IsTerminal::is_terminal(&std::io::stderr()) {
        bar.set_draw_target(ProgressDrawTarget::hidden());
    }
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(args.threads.unwrap_or(0))
        .build()
        .context("cannot start the worker threads")?;
    let progress = |done: usize, _| bar.set_position(done as u64);
    let shape = receiver_shape(&args.receiver, args.up)?;
    let setup = Setup {
        shape,
        observer: args.observer.map(|[x, y, z]| Vec3::new(x, y, z)),
        direct: args.direct,
        ..Setup::default()
    };
    let measured = pool
        .install(|| measure_setup(&scene, &receivers, setup, &options, &cancel, &progress))
        .map_err(|e| match e {
            RenderError::Facing(i) => anyhow::anyhow!(
                "{}:{}: a semi-cylinder faces across its axis (--up), and this normal lies along it",
                args.points.display(),
                lines.get(i).copied().unwrap_or(0)
            ),
            e => e.into(),
        })?;
    bar.finish_and_clear();
    if cancel.load(Ordering::Relaxed) {
        bail!("interrupted: nothing written");
    }
    let mut csv = String::from(HEADER);
    if args.observer.is_some() {
        csv.pop();
        csv.push_str(OBSERVER_COLUMNS);
    }
    for (r, m) in receivers.iter().zip(&measured) {
        let mes = surface_mesopic(m, args.reflectance, shape);
        let _ = writeln!(
            csv,
            "{},{},{},{},{},{},{:.6e},{:.3e},{:.6e},{:.3e},{:.4},{:.6e},{:.4},{:.6e},\
             {:.6e},{:.6e},{:.6e},{:.6e},{:.6e}",
            r.p.x,
            r.p.y,
            r.p.z,
            r.n.x,
            r.n.y,
            r.n.z,
            m.e,
            m.e_se,
            m.es,
            m.es_se,
            m.sp(),
            mes.luminance,
            mes.m,
            mes.mesopic,
            m.edi[0],
            m.edi[1],
            m.edi[2],
            m.edi[3],
            m.edi[4]
        );
        if args.observer.is_some() {
            let [l, se, sp, mes] = observed(m);
            csv.pop();
            let _ = writeln!(csv, ",{l:.6e},{se:.3e},{sp:.4},{mes:.6e}");
        }
    }
    scotopia_image::write_atomic(&args.output, csv.as_bytes())
        .with_context(|| format!("{}: cannot write", args.output.display()))?;
    let spp = measured.first().map_or(0, |m| m.samples);
    eprintln!(
        "scotopia: {} points, {spp} samples each → {}",
        receivers.len(),
        args.output.display()
    );
    Ok(())
}
