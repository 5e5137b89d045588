//! The reference's two bisections, replayed: each step's outcome is
//! decided by comparing its chroma with roots found by Newton's and
//! Halley's methods, and only the steps that settle the answer are
//! evaluated. Both replays assume what the bisections themselves do —
//! that along the line the clip distance grows with chroma, and the
//! colour leaves the gamut once — and check it where it matters.

use super::line::{Frame, HueLine};
use super::{clip, in_gamut, EPSILON, JND};

/// What CSS Color 4's search does at a chroma whose clip lies ΔEOK `e`
/// away: raise the lower end, stop there, or lower the upper end.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Step {
    Up,
    Stop,
    Down,
}

/// The reference's test, as it writes it (NaN goes down).
fn step(e: f64) -> Step {
    if e < JND {
        if JND - e < EPSILON {
            Step::Stop
        } else {
            Step::Up
        }
    } else {
        Step::Down
    }
}

/// The search's path from [0, `c`] if the clip distance crosses JND − ε
/// at `r1` and JND at `r2`: the bracket (min, max) and the chroma between
/// them where it stops, or `None` if it would run out first.
fn predict(c: f64, r1: f64, r2: f64) -> Option<(f64, f64, f64)> {
    let (mut min, mut max) = (0.0, c);
    while max - min > EPSILON {
        let chroma = 0.5 * (min + max);
        if chroma <= r1 {
            min = chroma;
        } else if chroma >= r2 {
            max = chroma;
        } else {
            return Some((min, chroma, max));
        }
    }
    None
}

/// How far (ΔEOK) from JND − ε or JND a step's predicted distance must
/// lie for its outcome to be taken from the prediction when a channel
/// starts clipping near the crossings: where one more channel starts
/// clipping, the distance may turn back by a few 1e-5 (seen on yellows).
const KINK_MARGIN: f64 = 2e-3;

/// Whether the search, taking the path [`predict`] gives for `r1` and
/// `r2` to `(min, chroma, max)`, would take it: the distance at `chroma`
/// must stop the search, at `min` raise it and at `max` lower it, and so,
/// the distance growing with chroma, at every step before — unless a
/// channel starts clipping among the steps near a crossing (the distance
/// may turn back there, for a while): then each of those is checked too.
/// Returns the clipped colour's Oklab if so, and otherwise which of `min`
/// and `max` went as predicted.
fn check(
    line: &HueLine,
    c: f64,
    (r1, r2): (f64, f64),
    (min, chroma, max): (f64, f64, f64),
) -> Result<[f64; 3], (bool, bool)> {
    let (lab, e) = line.clip_at(chroma);
    // (Evaluated even where what is known would answer: beyond a kink the
    // distance may turn back. Chroma 0 is grey; `c`, the colour itself,
    // is never a step.)
    let below = min == 0.0 || step(line.clip_at(min).1) == Step::Up;
    let above = max == c || step(line.clip_at(max).1) == Step::Down;
    if !(below && above && step(e) == Step::Stop) {
        return Err((below, above));
    }
    // The other steps near a crossing: if a channel starts clipping
    // among them (the clipped channels differ between the nearest steps
    // at either end), each is checked.
    let slope = EPSILON / (r2 - r1);
    let mut near = [(0.0, false); 64];
    let mut n = 0;
    let (mut a, mut b) = (0.0, c);
    while b - a > EPSILON && n < near.len() {
        let mid = 0.5 * (a + b);
        if mid == chroma {
            break;
        }
        let up = mid <= r1;
        let gap = if up { r1 - mid } else { mid - r2 };
        if slope * gap < KINK_MARGIN && mid != min && mid != max {
            near[n] = (mid, up);
            n += 1;
        }
        if up {
            a = mid;
        } else {
            b = mid;
        }
    }
    let near = &near[..n];
    let lowest = near.iter().fold(min, |m, &(x, _)| m.min(x));
    let highest = near.iter().fold(max, |m, &(x, _)| m.max(x));
    if line.clipped_channels(lowest) != line.clipped_channels(highest) {
        for &(mid, up) in near {
            if step(line.clip_at(mid).1) != if up { Step::Up } else { Step::Down } {
                return Err((false, false));
            }
        }
    }
    Ok(lab)
}

/// CSS Color 4's binary search with local MINDE on `line`, for a colour
/// of chroma `c` whose clip lies `e0` ≥ JND away: the Oklab of the
/// clipped colour it returns.
pub(super) fn css_color_4(line: &HueLine, c: f64, e0: f64) -> Option<[f64; 3]> {
    let low = JND - EPSILON;
    // A first guess: the distance grows from 0 at the gamut's boundary,
    // with a slope known there, to e0 at the colour: where a parabola
    // through both crosses JND − ε and JND.
    let edge = line.boundary_estimate(c, 1e-4);
    let slope = line.exit_slope(edge);
    let u = c - edge;
    let k = (e0 - slope * u) / (u * u);
    let cross = |t: f64| {
        let disc = slope * slope + 4.0 * k * t;
        if disc > 0.0 && slope > 0.0 {
            edge + 2.0 * t / (slope + disc.sqrt())
        } else {
            edge + u * t / e0
        }
    };
    let (mut r1, mut r2) = (cross(low), cross(JND));
    // Known: the search goes up at chroma up to `lo` (grey is in gamut)
    // and down from `hi` (the colour itself) on.
    let (mut lo, mut hi, mut hi_e) = (0.0f64, c, e0);
    for _ in 0..3 {
        let Some(path) = predict(c, r1, r2) else {
            break;
        };
        let (min, chroma, max) = path;
        match check(line, c, (r1, r2), path) {
            Ok(lab) => return Some(lab),
            Err((false, false)) if min > lo && max < hi => {}
            Err((below, above)) => {
                if below {
                    lo = lo.max(min);
                }
                if above && max < hi {
                    (hi, hi_e) = (max, JND);
                }
            }
        }
        // Newton's estimates from the middle (more steps while they
        // move far).
        let mut x = chroma;
        for _ in 0..8 {
            let at = line.clip_with_slope(x);
            match step(at.e) {
                Step::Up => lo = lo.max(x),
                Step::Down => (hi, hi_e) = (x, at.e),
                Step::Stop => {}
            }
            (r1, r2) = if at.e > 1e-9 && at.slope > 0.0 {
                (x - (at.e - low) / at.slope, x - (at.e - JND) / at.slope)
            } else {
                // In gamut (no slope): a line from the boundary to the
                // nearest point known beyond JND.
                let through = |e: f64| edge + (hi - edge) * e / hi_e;
                (through(low), through(JND))
            };
            (r1, r2) = (r1.clamp(lo, hi), r2.clamp(lo, hi));
            if (r2 - x).abs() <= 1e-3 {
                break;
            }
            x = 0.5 * (r1 + r2);
        }
    }
    bisect(line, c)
}

/// The search itself, every step evaluated, where the replay could not
/// settle (the distance turning near a crossing, or a search that runs
/// out): the reference's loop on `line`. `None` if it never clips.
fn bisect(line: &HueLine, c: f64) -> Option<[f64; 3]> {
    let (mut min, mut max, mut min_in_gamut) = (0.0, c, true);
    let mut last = None;
    while max - min > EPSILON {
        let chroma = 0.5 * (min + max);
        if min_in_gamut && in_gamut(line.rgb(chroma)) {
            min = chroma;
            continue;
        }
        let (lab, e) = line.clip_at(chroma);
        last = Some(lab);
        match step(e) {
            Step::Stop => return last,
            Step::Up => (min, min_in_gamut) = (chroma, false),
            Step::Down => max = chroma,
        }
    }
    last
}

/// scotopia's hue restoration: the clipped colour with Oklab `lab` put
/// back on the hue (cos, sin) = `hue` at its own lightness and chroma,
/// its chroma lowered by bisection to ε until in gamut. The bisection is
/// the reference's, every step evaluated (the line may leave the gamut
/// and come back, near the blue corner), but without branches: each step
/// a cubic per channel. `None` where the colour lies on the gamut's
/// surface to rounding, in or out by chance: the reference's rounding
/// decides.
pub(super) fn restore_hue(frame: &Frame, lab: [f64; 3], hue: (f64, f64)) -> Option<[f64; 3]> {
    let c = super::line::chroma(lab);
    let line = HueLine::new(frame, lab[0], hue);
    let full = line.rgb(c);
    // How far inside the RGB cube (negative: outside).
    let margin = full
        .iter()
        .fold(f64::INFINITY, |m, &x| m.min(x).min(1.0 - x));
    if margin > SURFACE {
        return Some(full);
    }
    if margin >= -SURFACE {
        return None;
    }
    let (mut lo, mut hi) = (0.0, c);
    while hi - lo > EPSILON {
        let mid = 0.5 * (lo + hi);
        let inside = in_gamut(line.rgb(mid));
        lo = if inside { mid } else { lo };
        hi = if inside { hi } else { mid };
    }
    Some(clip(line.rgb(lo)))
}

/// How close to the gamut's surface two computations of a colour may
/// disagree on which side it lies (a thousand times their rounding).
pub(super) const SURFACE: f64 = 1e-12;
