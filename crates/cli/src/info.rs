//! `scotopia info`: what a scene file holds.

use std::fmt::Write;
use std::path::PathBuf;

use anyhow::{Context, Result};

use scotopia_scene::mitsuba::Parameters;
use scotopia_scene::{load_scene_with, LoadOptions, Resolution, SceneInfo};

#[derive(clap::Args)]
pub struct Args {
    /// The scene (Mitsuba 3 XML).
    scene: PathBuf,
    /// Set a scene parameter, overriding its <default> (repeatable).
    #[arg(short = 'D', value_name = "NAME=VALUE")]
    define: Vec<String>,
    /// Override the film size: W (keeping the film's aspect) or WxH. The
    /// field of view along the film's fov_axis stays, as in Mitsuba.
    #[arg(long, value_name = "W|WxH")]
    res: Option<Resolution>,
    /// Print JSON instead of text.
    #[arg(long)]
    json: bool,
}

/// Parses `-D name=value` pairs.
pub fn parameters(define: &[String]) -> Result<Parameters> {
    define
        .iter()
        .map(|d| {
            let (k, v) = d
                .split_once('=')
                .with_context(|| format!("-D {d}: expected NAME=VALUE"))?;
            Ok((k.to_string(), v.to_string()))
        })
        .collect()
}

/// `--res` as load options.
pub fn load_options(resolution: Option<Resolution>) -> LoadOptions {
    LoadOptions {
        resolution,
        ..LoadOptions::default()
    }
}

pub fn run(args: Args) -> Result<()> {
    let options = load_options(args.res);
    let scene = load_scene_with(&args.scene, &parameters(&args.define)?, &options)?;
    let i = SceneInfo::of(&scene);
    let text = if args.json {
        // Through a `Value`, which widens f32 to f64 as the fields are.
        format!("{}\n", serde_json::to_value(&i)?)
    } else {
        let mut o = String::new();
        writeln!(o, "{}", args.scene.display())?;
        writeln!(o, "  shapes      {} ({} triangles)", i.shapes, i.triangles)?;
        if i.instances > 0 {
            writeln!(o, "  instances   {}", i.instances)?;
        }
        writeln!(o, "  materials   {}", i.materials)?;
        writeln!(o, "  emitters    {}", i.emitters)?;
        let (camera, film) = (&i.camera, &i.film);
        match camera.meter_shape {
            Some(shape) => writeln!(
                o,
                "  sensor      irradiancemeter on shape {shape}: its average illuminance, lx"
            )?,
            None => writeln!(
                o,
                "  camera      {}, fov {:.2}° × {:.2}°",
                if camera.thin_lens {
                    "thin lens"
                } else {
                    &camera.projection
                },
                camera.fov_degrees[0],
                camera.fov_degrees[1]
            )?,
        }
        writeln!(
            o,
            "  film        {}×{}, {} filter, {} spp",
            film.width, film.height, film.filter, i.samples_per_pixel
        )?;
        writeln!(
            o,
            "  max depth   {}",
            if i.max_depth < 0 {
                "unlimited".to_string()
            } else {
                i.max_depth.to_string()
            }
        )?;
        for (k, l) in i.lights.iter().enumerate() {
            writeln!(
                o,
                "  light {k}     {}: {:.4e} W, {:.4e} lm",
                l.kind, l.watts, l.lumens
            )?;
        }
        for (k, m) in i.media.iter().enumerate() {
            let albedo = m.albedo.map_or("a grid".to_string(), |a| format!("{a:.3}"));
            if m.grids.is_empty() && m.kind == "homogeneous" {
                writeln!(
                    o,
                    "  medium {k}    {}: at 550 nm σt {:.4e} per unit, albedo {albedo}, g {:.2}; {:.3} mean free paths across the scene",
                    m.kind, m.sigma_t, m.g, m.optical_thickness
                )?;
            } else {
                let grids: Vec<String> = m
                    .grids
                    .iter()
                    .map(|g| {
                        format!(
                            "{} {}×{}×{} cells of {} channel{}",
                            g.parameter,
                            g.cells[0],
                            g.cells[1],
                            g.cells[2],
                            g.channels,
                            if g.channels == 1 { "" } else { "s" }
                        )
                    })
                    .collect();
                writeln!(
                    o,
                    "  medium {k}    {}: σt at most {:.4e} per unit, albedo {albedo} (550 nm), g {:.2}; at most {:.3} mean free paths across it; grids: {}",
                    m.kind,
                    m.sigma_t,
                    m.g,
                    m.optical_thickness,
                    if grids.is_empty() { "none".to_string() } else { grids.join(", ") }
                )?;
            }
        }
        for w in &i.warnings {
            writeln!(o, "  warning     {w}")?;
        }
        o
    };
    crate::print(&text)
}
