//! Many pixels at once: the reference's algorithm itself — every step of
//! CSS Color 4's search and of the hue restoration evaluated, no
//! prediction — on out-of-gamut pixels side by side, each pixel a lane of
//! plain loops without branches (a step's outcome a select), compiled
//! for the CPU's widest SIMD by [`crate::wide_math::dispatch`].
//!
//! The work goes through four queues of [`LANES`] lanes (structure of
//! arrays), each run when full and at the end: the first clip (Oklab of
//! the colour and of its clip), the search (those the first clip leaves
//! more than JND away), the hue restoration's first test, and its
//! bisection (those whose restored colour lies outside). So a lane
//! rarely computes for nothing; within the search and the bisection a
//! lane that has finished computes along and keeps its values. A colour
//! on the gamut's surface to rounding, or with no hue, goes to
//! [`super::map_to_gamut`].

use super::line::{apply, chroma, distance, Frame, M1, M2};
use super::search::SURFACE;
use super::{clip, in_gamut, map_to_gamut, EPSILON, JND};
use crate::wide_math::{cbrt, dispatch};
use rayon::prelude::*;
use scotopia_color::space::RgbColorSpace;

/// Lanes per queue.
const LANES: usize = 64;
/// Colours the search takes at a time: it keeps [`LANES`] of them going,
/// a lane taking the next as soon as its own is found.
const SEARCHES: usize = 4 * LANES;
/// Pixels per parallel task.
const CHUNK: usize = 8192;

/// One f64 per lane.
type Lanes = [f64; LANES];

/// [`super::map_to_gamut`] of every pixel's X, Y, Z (its first three
/// values; the rest, such as V′, are ignored), as f32 linear RGB in
/// [0, 1], in parallel. The same results but for rounding (the tests hold
/// both to the reference).
pub fn map_pixels_to_gamut<const N: usize>(
    pixels: &[[f32; N]],
    space: &RgbColorSpace,
) -> Vec<[f32; 3]> {
    let mut out: Vec<[f32; 3]> = crate::resample::zeroed(pixels.len());
    Frame::with(space, |frame| {
        out.par_chunks_mut(CHUNK)
            .zip(pixels.par_chunks(CHUNK))
            .for_each(|(out, pixels)| {
                let mut run = Run {
                    frame,
                    space,
                    pixels,
                    out,
                };
                dispatch(
                    #[inline(always)]
                    || run.map(),
                )
            });
    });
    out
}

/// One task: its pixels, where they go, and the space.
struct Run<'a, const N: usize> {
    frame: &'a Frame,
    space: &'a RgbColorSpace,
    pixels: &'a [[f32; N]],
    out: &'a mut [[f32; 3]],
}

/// Colours waiting for a step: where each pixel goes, and `F` values
/// each (`CAP` of them at most).
struct Queue<const F: usize, const CAP: usize = LANES> {
    len: usize,
    index: [usize; CAP],
    v: [[f64; CAP]; F],
}

impl<const F: usize, const CAP: usize> Queue<F, CAP> {
    fn new() -> Self {
        Self {
            len: 0,
            index: [0; CAP],
            v: [[0.0; CAP]; F],
        }
    }

    /// Adds a lane; whether the queue is now full.
    #[inline(always)]
    fn push(&mut self, index: usize, values: [f64; F]) -> bool {
        self.stage(index, values);
        self.len += 1;
        self.len == CAP
    }

    /// Writes a lane's values into the next free lane, without taking it.
    #[inline(always)]
    fn stage(&mut self, index: usize, values: [f64; F]) {
        let k = self.len;
        self.index[k] = index;
        for (v, x) in self.v.iter_mut().zip(values) {
            v[k] = x;
        }
    }

    /// Fills the unused places with the first one's values, so that
    /// every lane computes on a real colour.
    #[inline(always)]
    fn pad(&mut self) {
        for v in &mut self.v {
            let first = v[0];
            v[self.len..].fill(first);
        }
    }
}

/// The first clip's queue: just where the pixels are.
type Front = Queue<0>;
/// The search's: lightness, chroma, the hue's cos and sin, and the first
/// clip's Oklab.
type Search = Queue<7, SEARCHES>;
/// The hue restoration's: Oklab, and the hue's cos and sin.
type Restore = Queue<5>;
/// Its bisection's: lightness, chroma, the hue's cos and sin.
type Bisect = Queue<4>;

/// Lines of constant lightness and hue, one per lane, as in
/// [`super::line::HueLine`]: lms′ = base + C·dir.
struct Lines {
    base: [Lanes; 3],
    dir: [Lanes; 3],
}

impl Lines {
    #[inline(always)]
    fn new(frame: &Frame, l: &Lanes, cos: &Lanes, sin: &Lanes) -> Self {
        let mut base = [[0.0; LANES]; 3];
        let mut dir = [[0.0; LANES]; 3];
        for k in 0..LANES {
            let b = apply(&frame.lms_from_lab, [l[k], 0.0, 0.0]);
            let d = apply(&frame.lms_from_lab, [0.0, cos[k], sin[k]]);
            for j in 0..3 {
                base[j][k] = b[j];
                dir[j][k] = d[j];
            }
        }
        Lines { base, dir }
    }

    /// Lane `k`'s linear RGB at chroma `c`.
    #[inline(always)]
    fn rgb(&self, frame: &Frame, k: usize, c: f64) -> [f64; 3] {
        rgb_at(frame, get(&self.base, k), get(&self.dir, k), c)
    }
}

/// Oklab from linear values that `to_lms` takes to LMS.
#[inline(always)]
fn oklab(to_lms: &[[f64; 3]; 3], v: [f64; 3]) -> [f64; 3] {
    let lms = apply(to_lms, v);
    apply(&M2.0, [cbrt(lms[0]), cbrt(lms[1]), cbrt(lms[2])])
}

/// Lane `k` of three arrays.
#[inline(always)]
fn get<const CAP: usize>(v: &[[f64; CAP]], k: usize) -> [f64; 3] {
    [v[0][k], v[1][k], v[2][k]]
}

/// Linear RGB at chroma `c` on the line lms′ = base + C·dir.
#[inline(always)]
fn rgb_at(frame: &Frame, base: [f64; 3], dir: [f64; 3], c: f64) -> [f64; 3] {
    let t = |j: usize| {
        let t = base[j] + c * dir[j];
        t * t * t
    };
    apply(&frame.rgb_from_lms, [t(0), t(1), t(2)])
}

impl<const N: usize> Run<'_, N> {
    /// The task's pixels: those in gamut written at once, the others
    /// through the queues.
    #[inline(always)]
    fn map(&mut self) {
        let m = &self.space.rgb_from_xyz.0;
        let mut front = Front::new();
        let mut search = Search::new();
        let mut restore = Restore::new();
        let mut bisect = Bisect::new();
        for (i, p) in self.pixels.iter().enumerate() {
            let xyz = [p[0], p[1], p[2]].map(f64::from);
            // `space.xyz_to_rgb`: the same products and sums.
            let rgb = apply(m, xyz);
            // Without a branch on the outcome (half the pixels by day):
            // written out, and queued in the next free lane, which only
            // an out-of-gamut pixel takes.
            self.out[i] = rgb.map(|v| v as f32);
            front.stage(i, []);
            front.len += usize::from(!in_gamut(rgb));
            if front.len == LANES {
                self.front(&mut front, &mut search, &mut restore, &mut bisect);
            }
        }
        // What is left in each queue, in order.
        if front.len > 0 {
            self.front(&mut front, &mut search, &mut restore, &mut bisect);
        }
        if search.len > 0 {
            self.search(&mut search, &mut restore, &mut bisect);
        }
        if restore.len > 0 {
            self.restore(&mut restore, &mut bisect);
        }
        if bisect.len > 0 {
            self.bisect(&mut bisect);
        }
    }

    /// Writes pixel `i`'s result.
    #[inline(always)]
    fn put(&mut self, i: usize, rgb: [f64; 3]) {
        self.out[i] = rgb.map(|v| v as f32);
    }

    /// Pixel `i` by the single-pixel path.
    fn alone(&mut self, i: usize) {
        let p = self.pixels[i];
        let rgb = map_to_gamut([p[0], p[1], p[2]].map(f64::from), self.space);
        self.put(i, rgb);
    }

    /// The first clip (CSS step 3): the colour's and its clip's Oklab;
    /// white, black, to the search or to the hue restoration.
    #[inline(always)]
    fn front(
        &mut self,
        front: &mut Front,
        search: &mut Search,
        restore: &mut Restore,
        bisect: &mut Bisect,
    ) {
        // The pixels' X, Y, Z (unused lanes repeat the first).
        let mut xyz = [[0.0; LANES]; 3];
        let first = front.index[0];
        for (k, &i) in front.index.iter().enumerate() {
            let p = self.pixels[if k < front.len { i } else { first }];
            for (j, v) in xyz.iter_mut().enumerate() {
                v[k] = f64::from(p[j]);
            }
        }
        let m = &self.space.rgb_from_xyz.0;
        let mut lab = [[0.0; LANES]; 3];
        let mut origin = [[0.0; LANES]; 3];
        for k in 0..LANES {
            let xyz = get(&xyz, k);
            let o = oklab(&M1.0, xyz);
            let c = oklab(&self.frame.lms_from_rgb, clip(apply(m, xyz)));
            for j in 0..3 {
                origin[j][k] = o[j];
                lab[j][k] = c[j];
            }
        }
        for k in 0..front.len {
            let i = front.index[k];
            let (o, c) = (get(&origin, k), get(&lab, k));
            let (l, chroma) = (o[0], chroma(o));
            if l >= 1.0 {
                self.put(i, [1.0; 3]);
            } else if l.is_nan() || l <= 0.0 {
                self.put(i, [0.0; 3]);
            } else if !(chroma > 0.0 && chroma.is_finite()) {
                self.alone(i);
            } else {
                let (cos, sin) = (o[1] / chroma, o[2] / chroma);
                if distance(c, o) < JND {
                    if restore.push(i, [c[0], c[1], c[2], cos, sin]) {
                        self.restore(restore, bisect);
                    }
                } else if search.push(i, [l, chroma, cos, sin, c[0], c[1], c[2]]) {
                    self.search(search, restore, bisect);
                }
            }
        }
        front.len = 0;
    }

    /// CSS Color 4's binary search with local MINDE: at each step every
    /// lane evaluates its chroma, and those still searching take the
    /// outcome; a lane whose search has ended takes the next colour. The
    /// clipped colour each search returns goes on to the hue restoration.
    #[inline(always)]
    fn search(&mut self, search: &mut Search, restore: &mut Restore, bisect: &mut Bisect) {
        search.pad();
        let frame = self.frame;
        let [l, c, cos, sin, lab @ ..] = &search.v;
        // Each colour's line: lms′ = base + C·dir.
        let mut base = [[0.0; SEARCHES]; 3];
        let mut dir = [[0.0; SEARCHES]; 3];
        for k in 0..SEARCHES {
            let b = apply(&frame.lms_from_lab, [l[k], 0.0, 0.0]);
            let d = apply(&frame.lms_from_lab, [0.0, cos[k], sin[k]]);
            for j in 0..3 {
                base[j][k] = b[j];
                dir[j][k] = d[j];
            }
        }
        // The first steps, while the chroma tried is in gamut, need no
        // cube root: taken for every colour on their own, until each
        // meets one that is not.
        let mut start = [0.0; SEARCHES];
        loop {
            let mut busy = false;
            for k in 0..SEARCHES {
                let chroma = 0.5 * (start[k] + c[k]);
                let rgb = rgb_at(frame, get(&base, k), get(&dir, k), chroma);
                let step = c[k] - start[k] > EPSILON && in_gamut(rgb);
                start[k] = if step { chroma } else { start[k] };
                busy |= step;
            }
            if !busy {
                break;
            }
        }
        // The rest, in lanes: which colour each holds (`NONE`: none), and
        // its search's state.
        const NONE: usize = usize::MAX;
        let mut held = [NONE; LANES];
        let mut live = [false; LANES];
        let mut min = [0.0; LANES];
        let mut max = [0.0; LANES];
        let mut min_in_gamut = [true; LANES];
        let mut done = [false; LANES];
        let mut found = [[0.0; LANES]; 3];
        let (mut line_base, mut line_dir) = ([[0.0; LANES]; 3], [[0.0; LANES]; 3]);
        let (mut line_l, mut line_cos, mut line_sin) = ([0.0; LANES], [0.0; LANES], [0.0; LANES]);
        let mut ended = [false; LANES];
        let mut next = 0;
        loop {
            // Free lanes take the next colours.
            for k in 0..LANES {
                if held[k] == NONE && next < search.len {
                    let n = next;
                    next += 1;
                    held[k] = n;
                    live[k] = true;
                    (min[k], max[k]) = (start[n], c[n]);
                    (min_in_gamut[k], done[k]) = (true, false);
                    (line_l[k], line_cos[k], line_sin[k]) = (l[n], cos[n], sin[n]);
                    for j in 0..3 {
                        found[j][k] = lab[j][n];
                        line_base[j][k] = base[j][n];
                        line_dir[j][k] = dir[j][n];
                    }
                }
            }
            if !live.iter().any(|&l| l) {
                break;
            }
            for k in 0..LANES {
                let active = live[k] && !done[k] && max[k] - min[k] > EPSILON;
                let chroma = 0.5 * (min[k] + max[k]);
                let rgb = rgb_at(frame, get(&line_base, k), get(&line_dir, k), chroma);
                let skip = min_in_gamut[k] && in_gamut(rgb);
                let clipped = oklab(&frame.lms_from_rgb, clip(rgb));
                let at = [line_l[k], chroma * line_cos[k], chroma * line_sin[k]];
                let e = distance(clipped, at);
                let evaluated = active && !skip;
                let below = e < JND;
                let stop = below && JND - e < EPSILON;
                let up = below && !stop;
                min[k] = if active && (skip || up) {
                    chroma
                } else {
                    min[k]
                };
                max[k] = if evaluated && !below { chroma } else { max[k] };
                min_in_gamut[k] = min_in_gamut[k] && !(evaluated && up);
                for j in 0..3 {
                    found[j][k] = if evaluated { clipped[j] } else { found[j][k] };
                }
                done[k] = done[k] || (evaluated && stop);
                ended[k] = live[k] && (done[k] || max[k] - min[k] <= EPSILON);
            }
            // Ended searches go on to the hue restoration.
            for k in 0..LANES {
                if ended[k] {
                    let n = held[k];
                    let [a, b, c] = get(&found, k);
                    held[k] = NONE;
                    live[k] = false;
                    if restore.push(search.index[n], [a, b, c, cos[n], sin[n]]) {
                        self.restore(restore, bisect);
                    }
                }
            }
        }
        search.len = 0;
    }

    /// scotopia's hue restoration, first test: the clipped colour put
    /// back on the hue at its own lightness and chroma, kept if in gamut,
    /// else to the bisection.
    #[inline(always)]
    fn restore(&mut self, restore: &mut Restore, bisect: &mut Bisect) {
        restore.pad();
        let frame = self.frame;
        let [lab @ .., cos, sin] = &restore.v;
        let lines = Lines::new(frame, &lab[0], cos, sin);
        let mut full = [[0.0; LANES]; 3];
        let mut margin = [0.0; LANES];
        let mut c = [0.0; LANES];
        for k in 0..LANES {
            c[k] = chroma(get(lab, k));
            let rgb = lines.rgb(frame, k, c[k]);
            // How far inside the RGB cube (negative: outside).
            margin[k] = rgb
                .iter()
                .fold(f64::INFINITY, |m, &x| m.min(x).min(1.0 - x));
            for j in 0..3 {
                full[j][k] = rgb[j];
            }
        }
        for k in 0..restore.len {
            let i = restore.index[k];
            if margin[k] > SURFACE {
                self.put(i, get(&full, k));
            } else if margin[k] >= -SURFACE {
                self.alone(i);
            } else if bisect.push(i, [lab[0][k], c[k], cos[k], sin[k]]) {
                self.bisect(bisect);
            }
        }
        restore.len = 0;
    }

    /// The hue restoration's bisection: chroma lowered to ε until in
    /// gamut, every step evaluated.
    #[inline(always)]
    fn bisect(&mut self, bisect: &mut Bisect) {
        bisect.pad();
        let frame = self.frame;
        let [l, c, cos, sin] = &bisect.v;
        let lines = Lines::new(frame, l, cos, sin);
        let mut lo = [0.0; LANES];
        let mut hi = *c;
        loop {
            let mut busy = false;
            for k in 0..LANES {
                let active = hi[k] - lo[k] > EPSILON;
                let mid = 0.5 * (lo[k] + hi[k]);
                let inside = in_gamut(lines.rgb(frame, k, mid));
                lo[k] = if active && inside { mid } else { lo[k] };
                hi[k] = if active && !inside { mid } else { hi[k] };
                busy |= active;
            }
            if !busy {
                break;
            }
        }
        for (k, &lo) in lo.iter().enumerate().take(bisect.len) {
            let rgb = clip(lines.rgb(frame, k, lo));
            self.put(bisect.index[k], rgb);
        }
        bisect.len = 0;
    }
}
