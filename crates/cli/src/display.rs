//! `scotopia display`: the vision pipeline on an absolute X, Y, Z, V′
//! image — what a person would see of the scene, on a given display.

use std::path::{Path, PathBuf};

use anyhow::{bail, Context, Result};

use scotopia_color::RgbSpace;
use scotopia_image::{read_xyzv, write_png_rgb8, RgbInput, XyzvImage};
use scotopia_vision::acuity::degrees_per_pixel;
use scotopia_vision::mode::Adaptation;
use scotopia_vision::output::{
    compare_sheet, display_gamut, display_peak, write_display, PngOptions,
};
use scotopia_vision::{display_owned, DisplayParams, Displayed, Observer, ToneOperator};

/// The pipeline's switches, shared by `display` and `render --display`.
#[derive(clap::Args, Clone, Debug)]
pub struct VisionArgs {
    /// Horizontal field of view in degrees (default: the image's metadata).
    #[arg(long, value_name = "DEG", value_parser = crate::numbers::fov)]
    fov: Option<f64>,
    /// The display's peak luminance, cd/m² (default 100; 1000 with --hdr).
    #[arg(long, value_name = "CD")]
    display_peak: Option<f64>,
    /// What the eye adapts to: global (the log-average luminance), local
    /// (per pixel, from the light pooled within about half a degree), or a
    /// luminance in cd/m².
    #[arg(long, default_value = "global", value_name = "global|local|CD")]
    adaptation: String,
    /// Glare from light the display cannot show (Spencer et al. 1995).
    #[arg(long, default_value = "on", value_name = "on|off")]
    glare: String,
    /// The night-vision shift and scotopic acuity loss (Jensen et al. 2001).
    #[arg(long, default_value = "on", value_name = "on|off")]
    night_shift: String,
    /// The tone operator: the multiscale model (Pattanaik et al. 1998),
    /// Reinhard et al. 2002, or a plain exposure.
    #[arg(
        long,
        default_value = "multiscale",
        value_name = "multiscale|reinhard|exposure"
    )]
    tonemap: String,
    /// The display's gamut (default srgb; rec2020 with --hdr).
    #[arg(long, value_name = "srgb|p3|rec2020")]
    gamut: Option<String>,
    /// HDR output: Rec. 2100 PQ in a 16-bit PNG with a cICP chunk.
    #[arg(long)]
    hdr: bool,
    /// Bits per PNG sample: 8 (dithered) or 16.
    #[arg(long, default_value_t = 8, value_name = "8|16")]
    bits: u8,
    /// The observer's age in years (1 to 100): it sets the glare veil
    /// (CIE 146:2002's glare spread function) and the density of the
    /// eye's lens, which yellows with age (Pokorny et al. 1987).
    #[arg(
        long,
        default_value_t = Observer::DEFAULT_AGE,
        value_name = "YEARS",
        value_parser = crate::numbers::age,
        allow_negative_numbers = true
    )]
    age: f64,
    /// The observer's eye pigmentation, CIE 146:2002's factor from 0
    /// (very dark eyes) through 0.5 (brown) to 1 (light blue): paler eyes
    /// let more light through the eye wall, so the glare veil grows.
    #[arg(
        long,
        default_value_t = Observer::DEFAULT_PIGMENTATION,
        value_name = "P",
        value_parser = crate::numbers::pigmentation,
        allow_negative_numbers = true
    )]
    pigmentation: f64,
}

pub(crate) fn on_off(name: &str, value: &str) -> Result<bool> {
    match value.to_ascii_lowercase().as_str() {
        "on" | "yes" | "true" | "1" => Ok(true),
        "off" | "no" | "false" | "0" => Ok(false),
        _ => bail!("--{name} {value}: use on or off"),
    }
}

impl VisionArgs {
    /// The settings as (flag, value) pairs, flags without their dashes:
    /// what `view` reports and merges a page's query into. A switch
    /// (`hdr`) is "on" or "off"; flags not given are left out.
    pub fn pairs(&self) -> Vec<(&'static str, String)> {
        let mut p = vec![
            ("adaptation", self.adaptation.clone()),
            ("glare", self.glare.clone()),
            ("night-shift", self.night_shift.clone()),
            ("tonemap", self.tonemap.clone()),
            ("hdr", if self.hdr { "on" } else { "off" }.into()),
            ("bits", self.bits.to_string()),
            ("age", self.age.to_string()),
            ("pigmentation", self.pigmentation.to_string()),
        ];
        if let Some(f) = self.fov {
            p.push(("fov", f.to_string()));
        }
        if let Some(peak) = self.display_peak {
            p.push(("display-peak", peak.to_string()));
        }
        if let Some(g) = &self.gamut {
            p.push(("gamut", g.clone()));
        }
        p
    }

    /// The pipeline's parameters for an image `width` pixels wide whose
    /// file gives `fov` (degrees), with any notes for the user.
    pub fn params(
        &self,
        width: usize,
        fov: Option<f64>,
    ) -> Result<(DisplayParams, PngOptions, Vec<String>)> {
        let mut notes = Vec::new();
        let degrees_per_pixel = match (self.fov, fov) {
            (Some(f), _) => {
                degrees_per_pixel(f, width).map_err(|e| anyhow::anyhow!("--fov {e}"))?
            }
            (None, Some(f)) => degrees_per_pixel(f, width)
                .map_err(|e| anyhow::anyhow!("the image's field of view {e}; give --fov"))?,
            (None, None) => {
                notes.push("no field of view in the image: assuming 45°; give --fov".into());
                degrees_per_pixel(45.0, width)
                    .map_err(|e| anyhow::anyhow!("the assumed field of view {e}; give --fov"))?
            }
        };
        let flag = |e: String| anyhow::anyhow!("--{e}");
        let peak = display_peak(self.display_peak, self.hdr).map_err(flag)?;
        let adaptation = Adaptation::parse(&self.adaptation).with_context(|| {
            format!(
                "--adaptation {}: use global, local or a luminance from {:e} to {:e} cd/m²",
                self.adaptation,
                f32::MIN_POSITIVE,
                scotopia_vision::screen::ABSURD_LUMINANCE
            )
        })?;
        let tonemap = ToneOperator::from_name(&self.tonemap).with_context(|| {
            format!(
                "--tonemap {}: use multiscale, reinhard or exposure",
                self.tonemap
            )
        })?;
        let gamut = display_gamut(self.gamut.as_deref(), self.hdr).map_err(flag)?;
        let png = PngOptions::new(self.bits, self.hdr).map_err(flag)?;
        // Checked by the flags' parsers already; `--age 0: use years …`.
        let observer =
            Observer::new(self.age, self.pigmentation).map_err(|e| flag(e.to_string()))?;
        let params = DisplayParams {
            degrees_per_pixel,
            display_peak: peak,
            adaptation,
            glare: on_off("glare", &self.glare)?,
            night_shift: on_off("night-shift", &self.night_shift)?,
            tonemap,
            gamut,
            observer,
            ..DisplayParams::default()
        };
        Ok((params, png, notes))
    }
}

#[derive(clap::Args)]
pub struct Args {
    /// The input: an OpenEXR with X, Y, Z (cd/m²) and V (scotopic cd/m²;
    /// estimated if missing), or R, G, B with --units.
    pub input: PathBuf,
    /// The output: .png (sRGB, or PQ with --hdr) or .exr (linear, 1 = peak).
    #[arg(short, long, value_name = "OUT.png")]
    pub output: Option<PathBuf>,
    /// Print the adaptation luminance, s, the mesopic m and the mode.
    #[arg(long)]
    info: bool,
    /// Write a labelled side-by-side sheet of the stages.
    #[arg(long, value_name = "OUT.png")]
    compare: Option<PathBuf>,
    /// For an RGB input: cd/m² of luminance per unit.
    #[arg(long, value_name = "CD")]
    units: Option<f64>,
    /// Multiply the input by K: the scene as if every light were K times
    /// brighter (light transport is linear, so this is exact).
    #[arg(long, value_name = "K")]
    scale: Option<f64>,
    /// For an RGB input: its primaries (linear srgb or acescg).
    #[arg(long, default_value = "srgb", value_name = "srgb|acescg")]
    input_space: String,
    /// Instead of what the eye sees, write (-o, PNG) a false-colour map of
    /// luminance (cd/m²), of CIE 191 mesopic luminance (cd/m², each pixel
    /// at the adaptation coefficient of its own luminance and S/P), or of
    /// illuminance (lx: an image made by `render --quantity illuminance`
    /// or `melanopic-edi`), or of melanopic equivalent daylight illuminance
    /// (lx, CIE S 026: `render --quantity melanopic-edi`), with a labelled
    /// scale bar.
    #[arg(long, value_name = "luminance|mesopic|illuminance|melanopic-edi")]
    pub false_colour: Option<String>,
    /// The false-colour range LO:HI (default: 0 to the 99th percentile;
    /// with --log, the three decades below it).
    #[arg(long, value_name = "LO:HI", requires = "false_colour")]
    pub range: Option<String>,
    /// A logarithmic false-colour scale.
    #[arg(long, requires = "false_colour")]
    pub log: bool,
    #[command(flatten)]
    vision: VisionArgs,
}

pub fn run(args: Args) -> Result<()> {
    let mut clock = PhaseClock::from_env();
    if args.output.is_none() && args.compare.is_none() && !args.info {
        bail!("nothing to do: give -o OUT.png, --compare OUT.png or --info");
    }
    let outputs: Vec<(&str, &Path)> = [("-o", &args.output), ("--compare", &args.compare)]
        .into_iter()
        .filter_map(|(flag, p)| Some((flag, p.as_deref()?)))
        .collect();
    scotopia_image::check_outputs(&[("the input", &args.input)], &outputs)
        .map_err(anyhow::Error::msg)?;
    let space = RgbSpace::from_name(&args.input_space)
        .with_context(|| format!("--input-space {}", args.input_space))?;
    let mut image = read_xyzv(
        &args.input,
        RgbInput {
            units: args.units,
            space,
        },
    )?;
    clock.mark("read EXR");
    if let Some(k) = args.scale {
        let k = crate::numbers::light_scale(k).map_err(anyhow::Error::msg)?;
        for p in &mut image.pixels {
            *p = p.map(|v| v * k);
        }
    }
    for note in &image.notes {
        eprintln!("scotopia: note: {}: {note}", args.input.display());
    }
    scotopia_vision::pipeline::check_size(image.width, image.height)
        .with_context(|| args.input.display().to_string())?;
    if let Some(quantity) = &args.false_colour {
        return write_false_colour(&args, quantity, &image);
    }
    // The eye model takes light reaching the eye; an illuminance map is
    // read as levels, not seen.
    if let Some(q) = image.quantity.as_deref().filter(|&q| q != "radiance") {
        bail!(
            "{} holds {q}, not radiance: the eye sees radiance; map it with --false-colour {}",
            args.input.display(),
            if q == "melanopic-edi" {
                "melanopic-edi"
            } else {
                "illuminance"
            }
        );
    }
    let (params, png, notes) = args.vision.params(image.width, image.fov_horizontal)?;
    for note in notes {
        eprintln!("scotopia: note: {note}");
    }
    let shown = match &args.compare {
        Some(sheet_path) => {
            let (shown, (w, h, rgb)) =
                compare_sheet(&image.pixels, image.width, image.height, &params, 360);
            write_png_rgb8(sheet_path, w as u32, h as u32, &rgb)?;
            shown
        }
        // The image is not needed after: the pipeline works in its memory.
        None => display_owned(image.pixels, image.width, image.height, &params),
    };
    clock.mark("pipeline");
    clock.stages(&shown.report.timings);
    say_left_out(&shown);
    if let Some(out) = &args.output {
        write_shown(out, &shown, &params, png)?;
        clock.mark("write PNG");
    }
    if args.info {
        crate::print(&info_text(&shown, &params))?;
    }
    drop(shown);
    clock.mark("free");
    Ok(())
}

/// With `SCOTOPIA_TIMES` set, each phase's wall time on stderr (for
/// `bench/vision.py` and profiling the whole process; off by default).
struct PhaseClock(Option<std::time::Instant>);

impl PhaseClock {
    fn from_env() -> Self {
        Self(std::env::var_os("SCOTOPIA_TIMES").map(|_| std::time::Instant::now()))
    }

    fn mark(&mut self, phase: &str) {
        if let Some(start) = &mut self.0 {
            let now = std::time::Instant::now();
            eprintln!(
                "scotopia: time: {phase:<10} {:6.1} ms",
                (now - *start).as_secs_f64() * 1e3
            );
            *start = now;
        }
    }

    /// The pipeline's own stages, indented under its phase.
    fn stages(&self, timings: &[(&'static str, f64)]) {
        if self.0.is_some() {
            for (name, secs) in timings {
                eprintln!("scotopia: time:   {name:<14} {:6.1} ms", secs * 1e3);
            }
        }
    }
}

/// `--false-colour`: the map instead of what the eye sees.
fn write_false_colour(args: &Args, quantity: &str, image: &XyzvImage) -> Result<()> {
    let Some(out) = &args.output else {
        bail!("--false-colour: give -o OUT.png");
    };
    let name = args.input.display().to_string();
    let map = crate::false_colour::map(quantity, args.range.as_deref(), args.log, image, &name)?;
    write_png_rgb8(out, map.width as u32, map.height as u32, &map.rgb)
        .with_context(|| format!("{}: cannot write", out.display()))?;
    eprintln!(
        "scotopia: false colour of {quantity}, {} → {}",
        map.legend,
        out.display()
    );
    Ok(())
}

/// Says once, on stderr, which pixels the pipeline left out of its
/// statistics (non-finite or absurd values).
pub fn say_left_out(shown: &Displayed) {
    if let Some(note) = shown.report.statistics.left_out.note() {
        eprintln!("scotopia: note: {note}");
    }
    if let Some(note) = shown.report.statistics.negative_note() {
        eprintln!("scotopia: warning: {note}");
    }
}

/// Writes the pipeline's result and says so.
pub fn write_shown(
    out: &Path,
    shown: &Displayed,
    params: &DisplayParams,
    png: PngOptions,
) -> Result<()> {
    write_display(out, shown, params, png)?;
    let total: f64 = shown.report.timings.iter().map(|t| t.1).sum();
    eprintln!(
        "scotopia: displayed ({}, {:.3} s) → {}",
        shown.report.state.mode.name(),
        total,
        out.display()
    );
    Ok(())
}

/// `--info`: the visual state and what each stage did.
fn info_text(shown: &Displayed, p: &DisplayParams) -> String {
    let r = &shown.report;
    let s = &r.statistics;
    let mut t = String::new();
    t += &format!(
        "adaptation    {:.4e} cd/m² ({})\n",
        r.state.luminance,
        adaptation_name(p.adaptation)
    );
    t += &format!(
        "log-average   {:.4e} cd/m²   maximum {:.4e} cd/m²\n",
        s.log_average, s.maximum
    );
    t += &format!("S/P ratio     {:.4}\n", s.sp_ratio);
    if let Some(note) = s.left_out.note() {
        t += &format!("left out      {note}\n");
    }
    t += &format!("s (Jensen)    {:.4}\n", r.state.s);
    t += &format!("m (CIE 191)   {:.4}\n", r.state.m);
    t += &format!(
        "L_mes         {:.4e} cd/m² (CIE 191 mesopic luminance of the adaptation level)\n",
        scotopia_vision::mode::mesopic_luminance(r.state.luminance, s.sp_ratio)
    );
    t += &format!("mode          {}\n", r.state.mode.name());
    t += &format!(
        "observer      {} years, pigmentation {} (CIE 146)\n",
        p.observer.age, p.observer.pigmentation
    );
    t += &format!(
        "glare         {}\n",
        if r.glare_applied {
            format!(
                "veil {:.4e} cd/m² at the adaptation point (the log-average {:.4e} → {:.4e}), \
                 {:.4e} cd/m² at the centre (CIE 146)",
                r.veil_adaptation,
                s.log_average,
                s.log_average + r.veil_adaptation,
                r.veil_centre
            )
        } else {
            "none (the display reproduces every light)".into()
        }
    );
    t += &format!("acuity blur   σ = {:.2} px\n", r.blur_pixels);
    for (stage, secs) in &r.timings {
        t += &format!("  {stage:<14} {:.1} ms\n", secs * 1e3);
    }
    t
}

fn adaptation_name(a: Adaptation) -> String {
    match a {
        Adaptation::Global => "global: the log-average".into(),
        Adaptation::Local => "local per pixel; the log-average shown".into(),
        Adaptation::Fixed(l) => format!("fixed at {l} cd/m²"),
    }
}
