//! A picture of a spectrum over 360–830 nm: the area under the curve filled
//! with the colour of each wavelength, the curve in the spectrum's own
//! colour, a swatch of that colour, and wavelength and value labels.

use std::path::Path;

use scotopia_color::cie::xyz_bar;
use scotopia_color::space::{srgb_encode, RgbSpace};
use scotopia_color::{Spectrum, LAMBDA_MAX, LAMBDA_MIN};

use crate::png_out::{write_png_rgb8, ImageError};

const W: usize = 800;
const H: usize = 400;
const LEFT: usize = 70;
const RIGHT: usize = 20;
const TOP: usize = 20;
const BOTTOM: usize = 40;

/// 3×5 glyphs, one bit a pixel, rows top to bottom, for the labels.
fn glyph(c: char) -> Option<[u8; 5]> {
    Some(match c {
        '0' => [0b111, 0b101, 0b101, 0b101, 0b111],
        '1' => [0b010, 0b110, 0b010, 0b010, 0b111],
        '2' => [0b111, 0b001, 0b111, 0b100, 0b111],
        '3' => [0b111, 0b001, 0b111, 0b001, 0b111],
        '4' => [0b101, 0b101, 0b111, 0b001, 0b001],
        '5' => [0b111, 0b100, 0b111, 0b001, 0b111],
        '6' => [0b111, 0b100, 0b111, 0b101, 0b111],
        '7' => [0b111, 0b001, 0b001, 0b001, 0b001],
        '8' => [0b111, 0b101, 0b111, 0b101, 0b111],
        '9' => [0b111, 0b101, 0b111, 0b001, 0b111],
        '.' => [0b000, 0b000, 0b000, 0b000, 0b010],
        '-' => [0b000, 0b000, 0b111, 0b000, 0b000],
        '+' => [0b000, 0b010, 0b111, 0b010, 0b000],
        'e' => [0b111, 0b101, 0b111, 0b100, 0b111],
        'n' => [0b000, 0b000, 0b110, 0b101, 0b101],
        'm' => [0b000, 0b000, 0b111, 0b111, 0b101],
        ' ' => [0; 5],
        _ => return None,
    })
}

struct Canvas {
    px: Vec<u8>,
}

impl Canvas {
    fn set(&mut self, x: usize, y: usize, c: [u8; 3]) {
        if x < W && y < H {
            let i = (y * W + x) * 3;
            self.px[i..i + 3].copy_from_slice(&c);
        }
    }

    fn rect(&mut self, x0: usize, y0: usize, x1: usize, y1: usize, c: [u8; 3]) {
        for y in y0..y1 {
            for x in x0..x1 {
                self.set(x, y, c);
            }
        }
    }

    /// Draws `text` at scale 2 with its top-left corner at (x, y).
    fn text(&mut self, x: usize, y: usize, text: &str, c: [u8; 3]) {
        for (n, ch) in text.chars().enumerate() {
            let Some(rows) = glyph(ch) else { continue };
            for (r, bits) in rows.iter().enumerate() {
                for b in 0..3 {
                    if bits & (0b100 >> b) != 0 {
                        let (gx, gy) = (x + n * 8 + b * 2, y + r * 2);
                        self.rect(gx, gy, gx + 2, gy + 2, c);
                    }
                }
            }
        }
    }
}

/// Linear sRGB → 8-bit encoded, normalised so the largest component is 1
/// (negative components, outside the gamut, are clipped to 0).
fn to_display(linear: [f64; 3]) -> [u8; 3] {
    let clipped = linear.map(|v| v.max(0.0));
    let m = clipped.iter().copied().fold(0.0, f64::max);
    if m <= 0.0 {
        return [0, 0, 0];
    }
    clipped.map(|v| (srgb_encode(v / m) * 255.0).round() as u8)
}

/// The colour of monochromatic light at `lambda`, at full brightness.
fn wavelength_colour(lambda: f32) -> [u8; 3] {
    let xyz = xyz_bar(lambda).map(|v| v as f64);
    to_display(RgbSpace::Srgb.def().xyz_to_rgb(xyz))
}

/// The value drawn in each pixel column: the extreme (largest magnitude) of
/// the spectrum over the column's wavelength range, sampled finely and at
/// the spectrum's own breakpoints, so a line narrower than a pixel shows at
/// its full height.
fn column_values(s: &Spectrum, columns: usize) -> Vec<f32> {
    let width = (LAMBDA_MAX - LAMBDA_MIN) / columns as f32;
    let breaks = s.breakpoints();
    (0..columns)
        .map(|x| {
            let (l0, l1) = (
                LAMBDA_MIN + width * x as f32,
                LAMBDA_MIN + width * (x + 1) as f32,
            );
            let inside = breaks.iter().copied().filter(|&l| l >= l0 && l < l1);
            (0..8)
                .map(|k| l0 + width * k as f32 / 8.0)
                .chain(inside)
                .map(|l| s.eval(l))
                .fold(0.0f32, |m, v| if v.abs() > m.abs() { v } else { m })
        })
        .collect()
}

/// Draws `spectrum` over 360–830 nm to `path`. `colour` is the 8-bit sRGB
/// colour to draw the curve and swatch in.
pub fn plot_spectrum(path: &Path, spectrum: &Spectrum, colour: [u8; 3]) -> Result<(), ImageError> {
    let mut c = Canvas {
        px: vec![255; W * H * 3],
    };
    let (pw, ph) = (W - LEFT - RIGHT, H - TOP - BOTTOM);
    let values = column_values(spectrum, pw);
    let vmax = values.iter().copied().fold(0.0f32, f32::max);
    let vmin = values.iter().copied().fold(0.0f32, f32::min);
    let span = if vmax - vmin > 0.0 {
        (vmax - vmin) * 1.05
    } else {
        1.0
    };
    let y_of = |v: f32| {
        TOP + ph
            - (((v - vmin) / span) * ph as f32)
                .round()
                .clamp(0.0, ph as f32) as usize
    };
    let value_at = |x: usize| values[x];

    // Grid every 50 nm, with labels.
    for lambda in (400..=800).step_by(50) {
        let x = LEFT
            + ((lambda as f32 - LAMBDA_MIN) / (LAMBDA_MAX - LAMBDA_MIN) * (pw - 1) as f32) as usize;
        c.rect(x, TOP, x + 1, TOP + ph, [225, 225, 225]);
        c.text(
            x.saturating_sub(12),
            TOP + ph + 8,
            &lambda.to_string(),
            [60, 60, 60],
        );
    }
    c.text(LEFT + pw - 30, TOP + ph + 24, "nm", [60, 60, 60]);

    // Area under the curve in the colour of each wavelength, lightened.
    let zero = y_of(0.0);
    for x in 0..pw {
        let lambda = LAMBDA_MIN + x as f32 / (pw - 1) as f32 * (LAMBDA_MAX - LAMBDA_MIN);
        let wc = wavelength_colour(lambda).map(|v| ((v as u32 + 255) / 2) as u8);
        let y = y_of(value_at(x));
        let (a, b) = if y < zero { (y, zero) } else { (zero, y) };
        c.rect(LEFT + x, a, LEFT + x + 1, b, wc);
    }

    // The curve, three pixels thick, in the spectrum's colour (outlined).
    let mut prev = y_of(value_at(0));
    for x in 0..pw {
        let y = y_of(value_at(x));
        let (a, b) = (prev.min(y), prev.max(y));
        c.rect(
            LEFT + x,
            a.saturating_sub(2),
            LEFT + x + 1,
            b + 3,
            [40, 40, 40],
        );
        prev = y;
    }
    prev = y_of(value_at(0));
    for x in 0..pw {
        let y = y_of(value_at(x));
        let (a, b) = (prev.min(y), prev.max(y));
        c.rect(LEFT + x, a.saturating_sub(1), LEFT + x + 1, b + 2, colour);
        prev = y;
    }

    // Axes, value labels and the swatch.
    c.rect(LEFT, TOP, LEFT + 1, TOP + ph, [0, 0, 0]);
    c.rect(LEFT, TOP + ph, LEFT + pw, TOP + ph + 1, [0, 0, 0]);
    let label = if (0.01..1e5).contains(&vmax.abs()) {
        format!("{:.4}", vmax).chars().take(7).collect::<String>()
    } else {
        format!("{vmax:.2e}")
    };
    let y_max = y_of(vmax);
    c.rect(LEFT - 5, y_max, LEFT, y_max + 1, [0, 0, 0]);
    c.text(4, y_max.saturating_sub(4), &label, [60, 60, 60]);
    c.text(4, zero.saturating_sub(5), "0", [60, 60, 60]);
    c.rect(
        W - RIGHT - 60,
        TOP + 10,
        W - RIGHT - 10,
        TOP + 60,
        [40, 40, 40],
    );
    c.rect(W - RIGHT - 58, TOP + 12, W - RIGHT - 12, TOP + 58, colour);

    write_png_rgb8(path, W as u32, H as u32, &c.px)
}

/// The display colour of a spectrum's linear sRGB, at full brightness.
pub fn display_colour(linear_srgb: [f64; 3]) -> [u8; 3] {
    to_display(linear_srgb)
}
