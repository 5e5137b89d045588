//! The local adaptation each pixel's gains see: an edge-aware pooling of
//! log luminance over a field given in degrees of visual angle, so that
//!
//! - a uniform field adapts uniformly (every pixel gets exactly its value);
//! - beside an edge each side adapts to itself (the pooling weighs pixels
//!   of other luminances down: a bilateral filter, Tomasi & Manduchi 1998,
//!   in log luminance as Durand & Dorsey 2002 use it for tone mapping);
//! - a highlight smaller than the pooling field is not adapted to (the
//!   finding of Vangorp, Myszkowski, Graf & Mantiuk 2015, "A model of
//!   local adaptation": the eye cannot adapt to small highlights): the
//!   range weight has a floor, so a pixel whose own luminance covers little
//!   of its pooling field takes its surround's level;
//! - the result does not depend on pixels per degree (the field is in
//!   degrees).
//!
//! Computed on a bilateral grid (Chen, Paris & Durand 2007): each pixel's
//! log luminance and weight are splatted into cells of the pooling width
//! in space (the nearest cell) and of the range width in log luminance
//! (linearly), the grid is blurred, and each pixel reads it back
//! trilinearly at its own position and luminance. The grid is small (a 1920 × 1080 image at 60°
//! and 0.5° cells is 124 × 70 × ~40 cells), so this costs two passes over
//! the pixels.

use rayon::prelude::*;

use crate::wide_math;

/// How the eye pools light for its adaptation state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pooling {
    /// The width of the pooling field: the grid's cell, degrees. The
    /// grid's blur and trilinear reads make the spatial kernel a smooth
    /// bump with a standard deviation of about 1.2 cells.
    pub degrees: f64,
    /// How far down in luminance a pixel pools with darker neighbours:
    /// the range kernel's standard deviation below the pixel, decades.
    pub darker: f64,
    /// How far up it pools with brighter ones, decades. Smaller than
    /// `darker`: a pixel beside a brighter region hardly adapts to it, so
    /// the foot of a bright gradient (a lamp's veil, a halo's rim) is not
    /// darkened below what lies beyond it.
    pub brighter: f64,
    /// The range weight's floor towards darker pixels, as a share of the
    /// weight of equal luminance: a highlight covering less than about
    /// this share of its pooling field adapts to its darker surround.
    pub floor: f64,
    /// How local the adaptation is: each pixel adapts to its pooled
    /// surround to this power and to the whole image's adaptation to the
    /// rest (in log luminance; Reinhard & Devlin 2005's "light
    /// adaptation" mix of local and global). 1: fully local, every large
    /// region shown near mid-grey whatever its luminance; 0: global.
    pub local: f64,
    /// The same for the rods' adaptation (tried 0 to 1 on the night
    /// street: every value leaves dusk brighter on average than day, see
    /// docs/vision.md; ½ like the cones').
    pub rods_local: f64,
}

impl Default for Pooling {
    fn default() -> Self {
        Self {
            degrees: 0.5,
            darker: 0.5,
            brighter: 0.15,
            floor: 0.1,
            local: 0.5,
            rods_local: 0.5,
        }
    }
}

/// The grid's range cell, decades: finer than the narrower kernel.
const RANGE_CELL: f64 = 0.125;

/// Luminance below this (cd/m²) pools as this: the log of black is
/// finite, and 10⁻⁶ cd/m² is below absolute threshold.
const FLOOR_LUMINANCE: f32 = 1e-6;

/// Per pixel, the adaptation luminance of the cones (cd/m²) and of the
/// rods (scotopic cd/m²).
pub struct AdaptationMap {
    pub cones: Vec<f32>,
    pub rods: Vec<f32>,
}

/// The grid: per cell the weighted sums of log₂ luminance (cones), log₂
/// rod signal, and the weight.
struct Grid {
    nx: usize,
    nz: usize,
    cells: Vec<[f32; 3]>,
}

/// Cells of padding on each side: the blur's reach.
const PAD: usize = 2;

impl Grid {
    fn new(nx: usize, ny: usize, nz: usize) -> Self {
        Self {
            nx,
            nz,
            cells: vec![[0.0; 3]; nx * ny * nz],
        }
    }

    /// Cells are stored column by column: a column is every luminance
    /// cell of one (x, y), so the range pooling reads contiguous memory.
    #[inline(always)]
    fn index(&self, x: usize, y: usize, z: usize) -> usize {
        (y * self.nx + x) * self.nz + z
    }

    /// The grid read at continuous position (x, y, z), trilinearly.
    #[inline(always)]
    fn read(&self, x: f32, y: f32, z: f32) -> [f32; 3] {
        let (ix, iy, iz) = (x as usize, y as usize, z as usize);
        let (fx, fy, fz) = (x - ix as f32, y - iy as f32, z - iz as f32);
        let mut out = [0.0f32; 3];
        for (dy, wy) in [(0, 1.0 - fy), (1, fy)] {
            for (dx, wx) in [(0, 1.0 - fx), (1, fx)] {
                let at = self.index(ix + dx, iy + dy, iz);
                let w = wy * wx;
                let pair = &self.cells[at..at + 2];
                for c in 0..3 {
                    out[c] += w * ((1.0 - fz) * pair[0][c] + fz * pair[1][c]);
                }
            }
        }
        out
    }

    /// Blurs in space with the binomial kernel [1 4 6 4 1]/16 along x,
    /// then along y (cells beyond the grid are empty). A column of cells
    /// is contiguous, so each tap adds whole columns: wide loops.
    fn blur_space(&mut self) {
        let (nx, nz) = (self.nx, self.nz);
        let row = nx * nz;
        self.cells
            .par_chunks_mut(row)
            .for_each_init(Vec::new, |copy, cells| {
                copy.clear();
                copy.extend_from_slice(cells);
                let (src, out) = (copy.as_flattened(), cells.as_flattened_mut());
                for x in 0..nx {
                    let unit = 3 * nz;
                    blur_taps(&mut out[x * unit..(x + 1) * unit], |d| {
                        let t = x as isize + d;
                        (t >= 0 && t < nx as isize).then(|| &src[t as usize * unit..][..unit])
                    });
                }
            });
        let copy = self.cells.clone();
        let ny = self.cells.len() / row.max(1);
        self.cells
            .par_chunks_mut(row)
            .enumerate()
            .for_each(|(y, cells)| {
                let unit = 3 * row;
                let src = copy.as_flattened();
                blur_taps(cells.as_flattened_mut(), |d| {
                    let t = y as isize + d;
                    (t >= 0 && t < ny as isize).then(|| &src[t as usize * unit..][..unit])
                });
            });
    }

    /// Pools along luminance: cell z gathers cell z + d with weight
    /// `kernel(d)` (d > 0: brighter), plus `floor` × every darker cell of
    /// its column. Only cells that hold weight are computed: a pixel's
    /// read touches only the cells its own splat (blurred in space)
    /// reached, and a column of a typical image is mostly empty.
    fn pool_range(&mut self, kernel: &[f32], floor: f32) {
        let nz = self.nz;
        let reach = (kernel.len() / 2) as isize;
        let src = std::mem::take(&mut self.cells);
        let mut out = vec![[0.0f32; 3]; src.len()];
        out.par_chunks_mut(nz)
            .zip(src.par_chunks(nz))
            .for_each(|(o, column)| {
                let mut darker = [0.0f32; 3];
                for z in 0..nz {
                    if column[z][2] > 0.0 {
                        let mut sum = darker.map(|v| floor * v);
                        for d in -reach..=reach {
                            let t = z as isize + d;
                            if t < 0 || t >= nz as isize {
                                continue;
                            }
                            let w = kernel[(d + reach) as usize];
                            for c in 0..3 {
                                sum[c] += w * column[t as usize][c];
                            }
                        }
                        o[z] = sum;
                    }
                    for c in 0..3 {
                        darker[c] += column[z][c];
                    }
                }
            });
        self.cells = out;
    }
}

/// `out` = Σ over d in −2..=2 of the binomial tap (1, 4, 6, 4, 1)/16 times
/// `source(d)` (absent beyond the grid: nothing added), as one wide loop
/// per tap.
fn blur_taps<'a>(out: &mut [f32], source: impl Fn(isize) -> Option<&'a [f32]>) {
    const K: [f32; 5] = [1.0 / 16.0, 4.0 / 16.0, 6.0 / 16.0, 4.0 / 16.0, 1.0 / 16.0];
    out.fill(0.0);
    for (k, &w) in K.iter().enumerate() {
        if let Some(src) = source(k as isize - 2) {
            wide_math::dispatch(
                #[inline(always)]
                || {
                    for (o, s) in out.iter_mut().zip(src) {
                        *o += w * s;
                    }
                },
            );
        }
    }
}

/// The adaptation map of a `width` × `height` image whose pixel `i` has
/// cone luminance `signals(i).0` (cd/m²) and rod signal `signals(i).1`
/// (scotopic cd/m²), at `degrees_per_pixel`; `global` is the whole
/// image's adaptation (cones, rods) that `pooling.local` mixes in.
pub fn adaptation_map(
    width: usize,
    height: usize,
    degrees_per_pixel: f64,
    pooling: &Pooling,
    global: (f32, f32),
    signals: impl Fn(usize) -> (f32, f32) + Sync,
) -> AdaptationMap {
    let n = width * height;
    let log = |v: f32| wide_math::log2_f32(v.max(FLOOR_LUMINANCE));
    // The luminance range, for the grid's depth (comparisons only; the
    // log of the two ends).
    let (lo, hi) = (0..n)
        .into_par_iter()
        .map(|i| signals(i).0.max(FLOOR_LUMINANCE))
        .fold(|| (f32::INFINITY, 0.0f32), |(a, b), v| (a.min(v), b.max(v)))
        .reduce(
            || (f32::INFINITY, 0.0f32),
            |(a, b), (c, d)| (a.min(c), b.max(d)),
        );
    if n == 0 || lo > hi || lo.is_nan() || !hi.is_finite() {
        return AdaptationMap {
            cones: Vec::new(),
            rods: Vec::new(),
        };
    }
    let (lo, hi) = (log(lo), log(hi));
    // Row `y`'s log₂ signals into `lc`, `lr`, computed wide.
    let logs = |y: usize, lc: &mut [f32], lr: &mut [f32]| {
        for (x, (c, r)) in lc.iter_mut().zip(lr.iter_mut()).enumerate() {
            let (a, b) = signals(y * width + x);
            *c = a;
            *r = b;
        }
        wide_math::dispatch(
            #[inline(always)]
            || {
                let lr = &mut lr[..lc.len()];
                for x in 0..lc.len() {
                    lc[x] = log(lc[x]);
                    lr[x] = log(lr[x]);
                }
            },
        );
    };
    // Grid coordinates: pixels per cell (at least one), log₂ per cell.
    let cell = (pooling.degrees / degrees_per_pixel).max(1.0) as f32;
    let depth = (RANGE_CELL * std::f64::consts::LOG2_10) as f32;
    // The range kernel in cells: Gaussian with its own width each way.
    let reach = (3.0 * pooling.darker.max(pooling.brighter) / RANGE_CELL).ceil() as isize;
    let kernel: Vec<f32> = (-reach..=reach)
        .map(|d| {
            let sigma = if d < 0 {
                pooling.darker
            } else {
                pooling.brighter
            };
            let x = d as f64 * RANGE_CELL / sigma;
            (-0.5 * x * x).exp() as f32
        })
        .collect();
    let (nx, ny) = (
        (width as f32 / cell) as usize + 2 * PAD + 2,
        (height as f32 / cell) as usize + 2 * PAD + 2,
    );
    let nz = ((hi - lo) / depth) as usize + 2 * PAD + 2;
    let at = |x: usize, y: usize, l: f32| {
        (
            (x as f32 + 0.5) / cell + PAD as f32,
            (y as f32 + 0.5) / cell + PAD as f32,
            (l - lo) / depth + PAD as f32,
        )
    };
    // Splat: each pixel into the cell column nearest it in space (the
    // blur and the trilinear read make the spatial kernel smooth), and
    // linearly between the two luminance cells around it. Image rows go
    // to their nearest grid row only, so the grid's rows fill in
    // parallel, each from its own image rows, with no grid per thread.
    let nearest = |p: usize| ((p as f32 + 0.5) / cell + PAD as f32 + 0.5) as usize;
    let row_cell: Vec<usize> = (0..height).map(nearest).collect();
    let column: Vec<usize> = (0..width).map(|x| nearest(x) * nz).collect();
    let mut grid = Grid::new(nx, ny, nz);
    grid.cells
        .par_chunks_mut(nx * nz)
        .enumerate()
        .for_each_init(
            || (vec![0.0f32; width], vec![0.0f32; width]),
            |(lc, lr), (gy, cells)| {
                // Image rows are in order, so theirs are a range.
                let rows =
                    row_cell.partition_point(|&c| c < gy)..row_cell.partition_point(|&c| c <= gy);
                for y in rows {
                    logs(y, lc, lr);
                    for x in 0..width {
                        let z = (lc[x] - lo) / depth + PAD as f32;
                        let iz = z as usize;
                        let fz = z - iz as f32;
                        // Logs relative to the darkest: small sums, and a
                        // uniform field's exactly 0.
                        let v = [lc[x] - lo, lr[x] - lo, 1.0];
                        let pair = &mut cells[column[x] + iz..column[x] + iz + 2];
                        for c in 0..3 {
                            pair[0][c] += (1.0 - fz) * v[c];
                            pair[1][c] += fz * v[c];
                        }
                    }
                }
            },
        );
    // Blur in space, then pool in luminance.
    grid.blur_space();
    grid.pool_range(&kernel, pooling.floor as f32);
    // Read back each pixel's means, mixed with the global level.
    let l = pooling.local.clamp(0.0, 1.0) as f32;
    let l_rods = pooling.rods_local.clamp(0.0, 1.0) as f32;
    let (gc, gr) = (
        (1.0 - l) * log(global.0) + l * lo,
        (1.0 - l_rods) * log(global.1) + l_rods * lo,
    );
    let mut cones = vec![0.0f32; n];
    let mut rods = vec![0.0f32; n];
    cones
        .par_chunks_mut(width)
        .zip(rods.par_chunks_mut(width))
        .enumerate()
        .for_each_init(
            || vec![0.0f32; width],
            |lr, (y, (cr, rr))| {
                // The row's logs (cones in `cr`), the grid's means at them,
                // then back from log₂, wide.
                logs(y, cr, lr);
                for x in 0..width {
                    let (gx, gy, gz) = at(x, y, cr[x]);
                    let [sc, sr, w] = grid.read(gx, gy, gz);
                    // A pixel's own splat keeps w > 0.
                    cr[x] = l * sc / w + gc;
                    rr[x] = l_rods * sr / w + gr;
                }
                wide_math::dispatch(
                    #[inline(always)]
                    || {
                        let rr = &mut rr[..cr.len()];
                        for x in 0..cr.len() {
                            cr[x] = wide_math::exp2_f32(cr[x]);
                            rr[x] = wide_math::exp2_f32(rr[x]);
                        }
                    },
                );
            },
        );
    AdaptationMap { cones, rods }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn map(w: usize, h: usize, dpp: f64, y: impl Fn(usize, usize) -> f32 + Sync) -> Vec<f32> {
        let pooling = Pooling {
            local: 1.0,
            ..Pooling::default()
        };
        adaptation_map(w, h, dpp, &pooling, (1.0, 1.0), |i| {
            let v = y(i % w, i / w);
            (v, 2.0 * v)
        })
        .cones
    }

    #[test]
    fn a_uniform_field_adapts_to_itself_exactly() {
        for level in [1e-4f32, 0.01, 3.0, 5e4] {
            let m = map(97, 41, 0.05, |_, _| level);
            for v in m {
                assert!((v / level - 1.0).abs() < 1e-5, "{level}: {v}");
            }
        }
    }

    #[test]
    fn each_side_of_a_strong_edge_adapts_to_itself() {
        // 0.005 | 50 cd/m², 0.05° per pixel (a cell is 10 pixels).
        let (w, h) = (200, 40);
        let m = map(w, h, 0.05, |x, _| if x < w / 2 { 0.005 } else { 50.0 });
        let row = &m[20 * w..21 * w];
        // Beside the edge the dark side stays within a factor of its
        // level (the floor's share of the bright side), far from it exact.
        assert!(row[w / 2 - 1] < 0.005 * 3.0, "{}", row[w / 2 - 1]);
        assert!((row[10] / 0.005 - 1.0).abs() < 1e-3, "{}", row[10]);
        assert!(row[w / 2] > 50.0 / 3.0, "{}", row[w / 2]);
        // Monotone on each side.
        for x in 1..w / 2 {
            assert!(row[x] >= row[x - 1] * (1.0 - 1e-5), "{x}");
        }
        for x in w / 2 + 1..w {
            assert!(row[x] >= row[x - 1] * (1.0 - 1e-5), "{x}");
        }
    }

    #[test]
    fn a_small_highlight_adapts_to_its_surround() {
        // A 2 × 2 pixel lamp (0.1°) four decades above the field.
        let (w, h) = (100, 100);
        let m = map(w, h, 0.05, |x, y| {
            if (49..51).contains(&x) && (49..51).contains(&y) {
                100.0
            } else {
                0.01
            }
        });
        assert!(m[50 * w + 50] < 1.0, "{}", m[50 * w + 50]);
    }

    #[test]
    fn the_map_does_not_depend_on_pixels_per_degree() {
        // The same 10° × 5° scene (a step and a lamp) at 0.05° and 0.025°
        // per pixel: the maps agree at the same angles.
        let scene = |u: f64, v: f64| -> f32 {
            if (4.0..4.5).contains(&u) && (2.0..2.5).contains(&v) {
                300.0
            } else if u < 6.0 {
                0.02
            } else {
                5.0
            }
        };
        let coarse = map(200, 100, 0.05, |x, y| {
            scene((x as f64 + 0.5) * 0.05, (y as f64 + 0.5) * 0.05)
        });
        let fine = map(400, 200, 0.025, |x, y| {
            scene((x as f64 + 0.5) * 0.025, (y as f64 + 0.5) * 0.025)
        });
        let mut worst = 0.0f32;
        for y in 0..100 {
            for x in 0..200 {
                // The fine pixels covering the coarse one, log-averaged.
                let f: f32 = [(0, 0), (1, 0), (0, 1), (1, 1)]
                    .iter()
                    .map(|(dx, dy)| fine[(2 * y + dy) * 400 + 2 * x + dx].ln())
                    .sum::<f32>()
                    / 4.0;
                worst = worst.max((coarse[y * 200 + x].ln() - f).abs());
            }
        }
        // Within 10 % everywhere (the grid's cell is 10 or 20 pixels).
        assert!(worst < 0.1, "worst log difference {worst}");
    }
}
