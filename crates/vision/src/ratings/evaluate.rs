//! Glare ratings read from a fisheye luminance picture, as evalglare
//! reads them: the vertical illuminance at the lens, glare sources found
//! as pixels brighter than a multiple of the picture's average luminance
//! (evalglare's default: 5×), merged where they touch and where their
//! centres lie within 0.2 rad (evalglare's search radius), and the
//! ratings of those sources against the rest.

use super::fisheye::Fisheye;
use super::{Source, View};
use crate::Observer;

/// Bright regions whose centres lie within this angle (radians) of each
/// other are one source: evalglare's default search radius (0.2 rad,
/// 11.5°), so that a luminaire's bright parts, or a noisy render's
/// scattered bright pixels, count as the source they are.
pub const MERGE_ANGLE: f64 = 0.2;

/// The angle (radians) between two directions of any length but zero.
fn angle(a: [f64; 3], b: [f64; 3]) -> f64 {
    let dot = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let len = |v: [f64; 3]| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    (dot / (len(a) * len(b))).clamp(-1.0, 1.0).acos()
}

/// The line of sight of a fisheye picture: its centre, its top up.
pub const FISHEYE_VIEW: View = View {
    sight: [0.0, 0.0, 1.0],
    up: [0.0, 1.0, 0.0],
};

/// A glare source found in a picture.
#[derive(Debug, Clone, PartialEq)]
pub struct Found {
    /// Its mean luminance, solid angle and (solid-angle-weighted) centre.
    pub source: Source,
    /// Its Guth position index.
    pub position_index: f64,
    /// Its pixels, row-major indices.
    pub pixels: Vec<usize>,
}

/// What a picture's glare analysis finds.
#[derive(Debug, Clone, PartialEq)]
pub struct Figures {
    /// The vertical illuminance at the lens, E_v = Σ L·ω·cos θ (lx).
    pub ev_lx: f64,
    /// The picture's mean luminance over its solid angle (cd/m²).
    pub average_cdm2: f64,
    /// The threshold sources are found above (cd/m²).
    pub threshold_cdm2: f64,
    /// UGR's background L_b (cd/m²): CIE 117's indirect illuminance at
    /// the eye over π, (E_v − Σ L·ω·cos θ of the sources' pixels)/π.
    pub background_cdm2: f64,
    pub sources: Vec<Found>,
    /// CIE 117's UGR (`None` without a source or a background).
    pub ugr: Option<f64>,
    /// Wienold & Christoffersen's DGP.
    pub dgp: f64,
    /// CIE 146's veiling luminance of the sources for the observer
    /// (cd/m²), summed over their pixels.
    pub veil_cdm2: f64,
}

/// The four neighbours (left, right, up, down) of pixel `i` of a `w` × `h`
/// picture, row-major; `None` beyond its edges.
pub fn neighbours(i: usize, w: usize, h: usize) -> [Option<usize>; 4] {
    let (x, y) = (i % w, i / w);
    [
        (x > 0).then(|| i - 1),
        (x + 1 < w).then(|| i + 1),
        (y > 0).then(|| i - w),
        (y + 1 < h).then(|| i + w),
    ]
}

/// The glare figures of the luminance picture `lum` (cd/m², row-major) of
/// `eye`'s geometry: sources are the pixels above `factor` times the mean
/// luminance, merged with their four neighbours and then with the regions
/// within [`MERGE_ANGLE`]; a `factor` above 100 is a luminance itself
/// (cd/m²), as evalglare's `-b` takes it.
pub fn evaluate(lum: &[f32], eye: &Fisheye, factor: f64, observer: &Observer) -> Figures {
    let (w, h) = (eye.width, eye.height);
    let mut omega = vec![0.0f64; w * h];
    let mut dirs = vec![[0.0f64; 3]; w * h];
    let (mut ev, mut flux, mut total) = (0.0, 0.0, 0.0);
    for y in 0..h {
        for x in 0..w {
            let i = y * w + x;
            let Some(d) = eye.direction(x as f64 + 0.5, y as f64 + 0.5) else {
                continue;
            };
            let o = eye.solid_angle(x, y);
            let l = f64::from(lum[i]).max(0.0);
            let l = if l.is_finite() { l } else { 0.0 };
            (omega[i], dirs[i]) = (o, d);
            ev += l * o * d[2].max(0.0);
            flux += l * o;
            total += o;
        }
    }
    let average = if total > 0.0 { flux / total } else { 0.0 };
    let threshold = if factor > 100.0 {
        factor
    } else {
        factor * average
    };
    let bright = |i: usize| omega[i] > 0.0 && f64::from(lum[i]) > threshold && average > 0.0;
    let mut seen = vec![false; w * h];
    // The bright pixels that touch, as groups, merged where their centres
    // are within MERGE_ANGLE of each other.
    let mut groups: Vec<(Vec<usize>, [f64; 3])> = Vec::new();
    let centre_of = |pixels: &[usize]| {
        [0, 1, 2].map(|c| pixels.iter().map(|&i| dirs[i][c] * omega[i]).sum::<f64>())
    };
    for start in 0..w * h {
        if seen[start] || !bright(start) {
            continue;
        }
        // The source's pixels: those reached through bright neighbours.
        let mut pixels = vec![start];
        seen[start] = true;
        let mut k = 0;
        while k < pixels.len() {
            for j in neighbours(pixels[k], w, h).into_iter().flatten() {
                if !seen[j] && bright(j) {
                    seen[j] = true;
                    pixels.push(j);
                }
            }
            k += 1;
        }
        let centre = centre_of(&pixels);
        let near = groups
            .iter()
            .position(|(_, c)| angle(*c, centre) < MERGE_ANGLE);
        match near {
            Some(g) => {
                // The centre is a sum over the pixels: it adds up.
                let (members, sum) = &mut groups[g];
                members.extend(pixels);
                *sum = [0, 1, 2].map(|c| sum[c] + centre[c]);
            }
            None => groups.push((pixels, centre)),
        }
    }
    let sources: Vec<Found> = groups
        .into_iter()
        .map(|(pixels, centre)| {
            let o: f64 = pixels.iter().map(|&i| omega[i]).sum();
            let lo: f64 = pixels.iter().map(|&i| f64::from(lum[i]) * omega[i]).sum();
            Found {
                position_index: FISHEYE_VIEW.position_index(centre),
                source: Source {
                    luminance: lo / o,
                    solid_angle: o,
                    dir: centre,
                },
                pixels,
            }
        })
        .collect();
    // The sources' pixels one by one: each a small source at its own
    // angle, for the veil (CIE 146's formula is a point source's: a
    // source across the line of sight taken at its centre's angle alone
    // would count it all at 0.1°) and the direct illuminance.
    let lit: Vec<Source> = sources
        .iter()
        .flat_map(|s| s.pixels.iter())
        .map(|&i| Source {
            luminance: f64::from(lum[i]).max(0.0),
            solid_angle: omega[i],
            dir: dirs[i],
        })
        .collect();
    // CIE 117's background: the indirect illuminance over π, E_v less
    // what the sources give straight (evalglare's default too).
    let direct: f64 = lit
        .iter()
        .map(|s| s.luminance * s.solid_angle * s.dir[2].max(0.0))
        .sum();
    let background = ((ev - direct) / std::f64::consts::PI).max(0.0);
    let plain: Vec<Source> = sources.iter().map(|s| s.source).collect();
    Figures {
        ev_lx: ev,
        average_cdm2: average,
        threshold_cdm2: threshold,
        background_cdm2: background,
        ugr: FISHEYE_VIEW.ugr(&plain, background),
        dgp: FISHEYE_VIEW.dgp(&plain, ev),
        veil_cdm2: FISHEYE_VIEW.veiling(&lit, observer),
        sources,
    }
}
