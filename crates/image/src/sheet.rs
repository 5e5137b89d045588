//! A labelled side-by-side sheet of images (`scotopia display --compare`):
//! each panel scaled to a common height by box filtering, a caption bar
//! above it in an 8×8 bitmap font (font8x8).

use font8x8::{UnicodeFonts, BASIC_FONTS};

/// One panel: a caption and an 8-bit RGB image.
pub struct Panel<'a> {
    pub label: &'a str,
    pub width: usize,
    pub height: usize,
    pub rgb: &'a [u8],
}

const CAPTION: usize = 28;
const GAP: usize = 6;
const BACKGROUND: [u8; 3] = [24, 24, 24];
const INK: [u8; 3] = [235, 235, 235];

/// Lays `panels` out in a row, each scaled to `height` rows (never up),
/// returning (width, height, RGB bytes).
pub fn sheet(panels: &[Panel], height: usize) -> (usize, usize, Vec<u8>) {
    let scaled: Vec<(usize, usize, Vec<u8>)> = panels.iter().map(|p| shrink(p, height)).collect();
    let h = scaled.iter().map(|s| s.1).max().unwrap_or(0) + CAPTION;
    let w = scaled.iter().map(|s| s.0 + GAP).sum::<usize>() + GAP;
    let mut px = BACKGROUND.repeat(w * h);
    let mut x0 = GAP;
    for (panel, (pw, ph, rgb)) in panels.iter().zip(&scaled) {
        text(&mut px, w, x0, 6, panel.label, *pw);
        for y in 0..*ph {
            let src = &rgb[y * pw * 3..(y + 1) * pw * 3];
            let at = ((y + CAPTION) * w + x0) * 3;
            px[at..at + pw * 3].copy_from_slice(src);
        }
        x0 += pw + GAP;
    }
    (w, h, px)
}

/// Box-filters a panel down to at most `height` rows, keeping its aspect.
fn shrink(p: &Panel, height: usize) -> (usize, usize, Vec<u8>) {
    if p.height <= height || height == 0 {
        return (p.width, p.height, p.rgb.to_vec());
    }
    let f = p.height as f64 / height as f64;
    let w = ((p.width as f64 / f).round() as usize).max(1);
    let mut out = Vec::with_capacity(w * height * 3);
    for y in 0..height {
        let (y0, y1) = (
            (y as f64 * f) as usize,
            (((y + 1) as f64 * f) as usize).min(p.height),
        );
        for x in 0..w {
            let (x0, x1) = (
                (x as f64 * f) as usize,
                (((x + 1) as f64 * f) as usize).min(p.width),
            );
            let mut sum = [0u32; 3];
            let mut n = 0;
            for sy in y0..y1.max(y0 + 1) {
                for sx in x0..x1.max(x0 + 1) {
                    let i = (sy * p.width + sx) * 3;
                    for (s, v) in sum.iter_mut().zip(&p.rgb[i..i + 3]) {
                        *s += *v as u32;
                    }
                    n += 1;
                }
            }
            out.extend(sum.map(|s| (s / n.max(1)) as u8));
        }
    }
    (w, height, out)
}

/// Draws `label` at scale 2 from (x, y), clipped to `max_width` pixels.
fn text(px: &mut [u8], w: usize, x: usize, y: usize, label: &str, max_width: usize) {
    for (n, ch) in label.chars().enumerate() {
        let Some(rows) = BASIC_FONTS.get(ch) else {
            continue;
        };
        for (r, bits) in rows.iter().enumerate() {
            for b in 0..8 {
                let gx = n * 16 + b * 2;
                if bits & (1 << b) == 0 || gx + 2 > max_width {
                    continue;
                }
                for dy in 0..2 {
                    for dx in 0..2 {
                        let i = ((y + r * 2 + dy) * w + x + gx + dx) * 3;
                        px[i..i + 3].copy_from_slice(&INK);
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn panels_are_laid_out_with_captions_and_scaled() {
        let white = vec![255u8; 40 * 20 * 3];
        let black = vec![0u8; 40 * 20 * 3];
        let panels = [
            Panel {
                label: "A",
                width: 40,
                height: 20,
                rgb: &white,
            },
            Panel {
                label: "glare",
                width: 40,
                height: 20,
                rgb: &black,
            },
        ];
        let (w, h, px) = sheet(&panels, 10);
        assert_eq!((w, h), (GAP + 20 + GAP + 20 + GAP, 10 + CAPTION));
        // The first panel is white, the second black, below the captions.
        let at = |x: usize, y: usize| &px[(y * w + x) * 3..(y * w + x) * 3 + 3];
        assert_eq!(at(GAP + 5, CAPTION + 5), &[255, 255, 255]);
        assert_eq!(at(2 * GAP + 25, CAPTION + 5), &[0, 0, 0]);
        // Some caption ink was drawn.
        assert!((0..CAPTION).any(|y| (0..w).any(|x| at(x, y) == INK)));
    }
}
