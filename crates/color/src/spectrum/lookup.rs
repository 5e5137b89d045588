//! How a tabulated spectrum finds the segment that holds a wavelength,
//! chosen once when the table is made: renderers evaluate it at every
//! vertex of every path.
//!
//! - A table on a uniform grid is read by index arithmetic.
//! - An irregular table is resampled once onto a uniform grid when the
//!   grid's piecewise-linear function differs from the table's by at most
//!   [`RESAMPLE_TOLERANCE`] of the table's largest magnitude everywhere
//!   (measured reflectances at 10 or 50 nm steps that skip a few, spectra
//!   smooth between their samples), and is then read the same way.
//! - Otherwise (a 0.2 nm emission line off any coarse grid) the table is
//!   kept, and a guide table, one entry per grid cell of about 1 nm, gives
//!   the few segments to search instead of all of them.

/// How far a resampled table may stray from the original, relative to the
/// largest |value|: below what f32 photometry resolves in practice.
pub const RESAMPLE_TOLERANCE: f32 = 1e-4;

/// Grid steps tried for resampling, coarsest first (nm); each is adjusted
/// so that a whole number of steps spans the table.
const STEPS: [f32; 12] = [
    50.0, 25.0, 20.0, 10.0, 5.0, 2.5, 2.0, 1.0, 0.5, 0.25, 0.2, 0.1,
];

/// The most grid points a resampled table may have (0.1 nm over 360–830
/// nm needs 4,701).
const MAX_GRID: usize = 8192;

#[derive(Debug, Clone, PartialEq)]
pub(super) enum Lookup {
    /// One sample: the value at that wavelength.
    Single,
    /// Values at `start + i / inv_step`. In f64: the position of 830 nm
    /// on a grid of 4,700 cells would be off by 6·10⁻⁴ of a cell in f32,
    /// a visible error on a steep segment.
    Grid {
        start: f64,
        inv_step: f64,
        values: Vec<f32>,
    },
    /// `guide[g]`: the segment holding `start + g / inv_step`;
    /// `slope[i]`: segment i's slope, so a value costs no division.
    Guided {
        start: f32,
        inv_step: f32,
        guide: Vec<u32>,
        slope: Vec<f32>,
    },
}

/// Index of the segment [x[i], x[i + 1]] that holds `v` (x increasing, at
/// least two entries), searching only segments lo..=hi.
#[inline]
fn segment(x: &[f32], v: f32, lo: usize, hi: usize) -> usize {
    let hi = hi.min(x.len() - 2);
    let lo = lo.min(hi);
    lo + x[lo + 1..=hi].partition_point(|&c| c <= v)
}

/// Piecewise-linear value through (lambda, value) at `l` inside the
/// table's span, by bisection: the reference the lookups are tested
/// against.
#[cfg(test)]
pub(super) fn searched(lambda: &[f32], value: &[f32], l: f32) -> f32 {
    let n = lambda.len();
    if n == 1 {
        return value[0];
    }
    let i = segment(lambda, l, 0, n - 2);
    let (l0, l1) = (lambda[i], lambda[i + 1]);
    let t = ((l - l0) / (l1 - l0)).clamp(0.0, 1.0);
    value[i] + t * (value[i + 1] - value[i])
}

/// Linear between grid values at `start + i / inv_step`.
#[inline(always)]
fn on_grid(start: f64, inv_step: f64, values: &[f32], l: f32) -> f32 {
    let x = (l as f64 - start) * inv_step;
    // `as u32`: the saturating conversion to u64 takes twice as many
    // instructions.
    let i = (x as u32 as usize).min(values.len() - 2);
    let t = (x - i as f64).min(1.0) as f32;
    values[i] + t * (values[i + 1] - values[i])
}

/// Linear between the table's samples, the segment found from the guide
/// and a short scan (a guide cell holds one or two samples but inside a
/// line).
#[inline(always)]
fn guided(
    start: f32,
    inv_step: f32,
    guide: &[u32],
    slope: &[f32],
    lambda: &[f32],
    value: &[f32],
    l: f32,
) -> f32 {
    let g = (((l - start) * inv_step) as u32 as usize).min(guide.len() - 2);
    let last = (guide[g + 1] as usize).min(slope.len() - 1);
    let mut i = (guide[g] as usize).min(last);
    while i < last && lambda[i + 1] <= l {
        i += 1;
    }
    value[i] + (l - lambda[i]) * slope[i]
}

impl Lookup {
    /// The lookup for a table with strictly increasing `lambda`.
    pub(super) fn new(lambda: &[f32], value: &[f32]) -> Self {
        let n = lambda.len();
        if n < 2 {
            return Lookup::Single;
        }
        let (start, span) = (lambda[0], lambda[n - 1] - lambda[0]);
        // Already uniform: the table is its own grid.
        let step = span / (n - 1) as f32;
        let uniform = lambda
            .iter()
            .enumerate()
            .all(|(i, &l)| (l - (start + step * i as f32)).abs() <= 1e-4 * step);
        if uniform {
            return Lookup::Grid {
                start: start as f64,
                inv_step: (n - 1) as f64 / span as f64,
                values: value.to_vec(),
            };
        }
        // The coarsest grid within the tolerance.
        let largest = value.iter().fold(0.0f32, |m, v| m.max(v.abs()));
        let tolerance = RESAMPLE_TOLERANCE * largest;
        for h in STEPS {
            let cells = (span / h).round().max(1.0) as usize;
            if cells + 1 > MAX_GRID {
                break;
            }
            let grid = Lookup::resampled(lambda, value, cells);
            // Both functions are linear between the union of their nodes;
            // on the grid's nodes they agree (the grid holds the table's
            // values there), so the largest difference is at one of the
            // table's own nodes.
            let worst = lambda
                .iter()
                .zip(value)
                .map(|(&l, &v)| (grid.eval(lambda, value, l) - v).abs())
                .fold(0.0f32, f32::max);
            if worst <= tolerance {
                return grid;
            }
        }
        // Kept: a guide per ~1 nm (or per segment, if finer).
        let cells = (span.ceil() as usize).max(n - 1).min(1 << 16);
        Lookup::guided(lambda, value, cells)
    }

    /// The table kept, with a guide of `cells` equal cells over its span.
    pub(super) fn guided(lambda: &[f32], value: &[f32], cells: usize) -> Self {
        let n = lambda.len();
        let start = lambda[0];
        let inv_step = cells as f32 / (lambda[n - 1] - start);
        let guide = (0..=cells)
            .map(|g| segment(lambda, start + g as f32 / inv_step, 0, n - 2) as u32)
            .collect();
        let slope = (0..n - 1)
            .map(|i| (value[i + 1] - value[i]) / (lambda[i + 1] - lambda[i]))
            .collect();
        Lookup::Guided {
            start,
            inv_step,
            guide,
            slope,
        }
    }

    /// The table resampled onto `cells` equal steps over its span.
    fn resampled(lambda: &[f32], value: &[f32], cells: usize) -> Self {
        let n = lambda.len();
        let start = lambda[0] as f64;
        let step = (lambda[n - 1] as f64 - start) / cells as f64;
        // The table's function at each node's exact position: rounded to
        // f32 first, a node 3·10⁻⁵ nm off on a steep segment (400 per nm)
        // would carry an error of 10⁻².
        let values = (0..=cells)
            .map(|i| {
                let x = start + step * i as f64;
                let j = lambda.partition_point(|&l| (l as f64) <= x).clamp(1, n - 1) - 1;
                let (l0, l1) = (lambda[j] as f64, lambda[j + 1] as f64);
                let t = ((x - l0) / (l1 - l0)).clamp(0.0, 1.0);
                (value[j] as f64 + t * (value[j + 1] as f64 - value[j] as f64)) as f32
            })
            .collect();
        Lookup::Grid {
            start,
            inv_step: 1.0 / step,
            values,
        }
    }

    /// Value at `l`, inside the table's span [lambda[0], lambda[n − 1]].
    #[inline]
    pub(super) fn eval(&self, lambda: &[f32], value: &[f32], l: f32) -> f32 {
        match self {
            Lookup::Single => value[0],
            Lookup::Grid {
                start,
                inv_step,
                values,
            } => on_grid(*start, *inv_step, values, l),
            Lookup::Guided {
                start,
                inv_step,
                guide,
                slope,
            } => guided(*start, *inv_step, guide, slope, lambda, value, l),
        }
    }

    /// Values at K wavelengths, zero outside the table's span: one match
    /// for the cluster, not one per wavelength.
    #[inline]
    pub(super) fn eval_cluster<const K: usize>(
        &self,
        lambda: &[f32],
        value: &[f32],
        l: &[f32; K],
    ) -> [f32; K] {
        let (lo, hi) = (lambda[0], lambda[lambda.len() - 1]);
        let inside = |x: f32| x >= lo && x <= hi;
        // Each value is computed whatever the wavelength (the index is
        // clamped, so it is always a valid read) and zeroed outside the
        // span: a select, not a branch per member.
        match self {
            Lookup::Single => std::array::from_fn(|k| if inside(l[k]) { value[0] } else { 0.0 }),
            Lookup::Grid {
                start,
                inv_step,
                values,
            } => std::array::from_fn(|k| {
                let v = on_grid(*start, *inv_step, values, l[k]);
                if inside(l[k]) {
                    v
                } else {
                    0.0
                }
            }),
            Lookup::Guided {
                start,
                inv_step,
                guide,
                slope,
            } => std::array::from_fn(|k| {
                if inside(l[k]) {
                    guided(*start, *inv_step, guide, slope, lambda, value, l[k])
                } else {
                    0.0
                }
            }),
        }
    }

    /// The lookup of the table with every value multiplied by `s`.
    pub(super) fn scaled(&self, s: f32) -> Self {
        match self {
            Lookup::Grid {
                start,
                inv_step,
                values,
            } => Lookup::Grid {
                start: *start,
                inv_step: *inv_step,
                values: values.iter().map(|v| v * s).collect(),
            },
            Lookup::Guided {
                start,
                inv_step,
                guide,
                slope,
            } => Lookup::Guided {
                start: *start,
                inv_step: *inv_step,
                guide: guide.clone(),
                slope: slope.iter().map(|v| v * s).collect(),
            },
            Lookup::Single => Lookup::Single,
        }
    }

    /// Whether the table is read from a uniform grid (its own or resampled).
    pub(super) fn is_grid(&self) -> bool {
        matches!(self, Lookup::Grid { .. })
    }
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::*;
    use crate::photometry::spectrum_to_xyzv;
    use crate::spectrum::{Spectrum, Tabulated};
    use crate::{cie, io};

    fn repo(path: &str) -> std::path::PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../..")
            .join(path)
    }

    /// The test's tables: lamps, illuminants, the Cornell box's walls,
    /// aluminium's n and k, and irregular tables smooth and spiky.
    fn tables() -> Vec<(String, Tabulated)> {
        let mut out = Vec::new();
        for lamp in ["low-pressure-sodium", "led-4000k", "uv-blacklight"] {
            let t = io::read_spectrum_file(repo(&format!("scenes/lamps/{lamp}.csv"))).unwrap();
            out.push((lamp.to_string(), t));
        }
        for name in cie::ILLUMINANT_NAMES {
            if let Spectrum::Tabulated(t) = cie::illuminant(name).unwrap() {
                out.push((name.to_string(), (*t).clone()));
            }
        }
        let walls: [&[(f32, f32)]; 2] = [
            &[
                (400.0, 0.05),
                (550.0, 0.06),
                (600.0, 0.45),
                (650.0, 0.62),
                (700.0, 0.64),
            ],
            &[
                (400.0, 0.06),
                (480.0, 0.15),
                (530.0, 0.45),
                (580.0, 0.30),
                (650.0, 0.08),
                (700.0, 0.07),
            ],
        ];
        for w in walls {
            let (l, v) = w.iter().copied().unzip();
            out.push(("wall".into(), Tabulated::new(l, v).unwrap()));
        }
        let al = std::fs::read_to_string(repo("data/conductors/al.csv")).unwrap();
        let rows: Vec<Vec<f32>> = al
            .lines()
            .filter(|r| r.starts_with(|c: char| c.is_ascii_digit()))
            .map(|r| r.split(',').map(|x| x.trim().parse().unwrap()).collect())
            .collect();
        for c in [1, 2] {
            let t = Tabulated::new(
                rows.iter().map(|r| r[0]).collect(),
                rows.iter().map(|r| r[c]).collect(),
            );
            out.push((format!("Al column {c}"), t.unwrap()));
        }
        // Irregular: a smooth curve at jittered wavelengths, and lines 0.2
        // nm wide at decimal positions on a flat floor.
        let mut state = 1u64;
        let mut next = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 40) as f32 / (1u64 << 24) as f32
        };
        let mut l = 360.0f32;
        let (mut ls, mut vs) = (Vec::new(), Vec::new());
        while l < 830.0 {
            ls.push(l);
            vs.push((l * 0.03).sin() + 1.5);
            l += 0.3 + 4.0 * next();
        }
        out.push(("jittered".into(), Tabulated::new(ls, vs).unwrap()));
        let mut ls = vec![380.0];
        let mut vs = vec![0.01];
        for c in [435.833, 546.074, 577.119, 579.065] {
            ls.extend([c - 0.1, c, c + 0.1]);
            vs.extend([0.01, 5.0, 0.01]);
        }
        ls.push(780.0);
        vs.push(0.01);
        out.push(("mercury lines".into(), Tabulated::new(ls, vs).unwrap()));
        // A ramp of 400 per nm between nodes on a 0.1 nm grid: resampled,
        // where a node's position rounded to f32 would cost 10⁻².
        let steep = Tabulated::new(
            vec![500.0, 501.0, 589.0, 589.2, 600.0, 600.5],
            vec![0.0, 0.2, 0.2, 80.0, 1.0, 0.0],
        );
        out.push(("steep".into(), steep.unwrap()));
        out
    }

    /// Wherever it resamples, the lookup stays within the tolerance of the
    /// table's own piecewise-linear function: at every sample, between
    /// samples, and on a 0.01 nm grid past both ends.
    #[test]
    fn lookups_stay_within_the_bound() {
        for (name, t) in tables() {
            let (l, v) = (t.wavelengths(), t.values());
            let largest = v.iter().fold(0.0f32, |m, x| m.max(x.abs()));
            // Allowance for f32 rounding of the interpolation itself.
            let bound = RESAMPLE_TOLERANCE * largest + 4.0 * f32::EPSILON * largest;
            let mut at: Vec<f32> = l.to_vec();
            at.extend(l.windows(2).map(|w| 0.5 * (w[0] + w[1])));
            at.extend((0..=50_000).map(|i| 340.0 + 0.01 * i as f32));
            for &x in &at {
                let want = if x >= l[0] && x <= l[l.len() - 1] {
                    searched(l, v, x)
                } else {
                    0.0
                };
                let got = t.eval(x);
                assert!(
                    (got - want).abs() <= bound,
                    "{name} at {x}: {got} vs {want}"
                );
                let cluster = t.eval_cluster(&[x, x, 0.0, 900.0]);
                assert_eq!(cluster, [got, got, 0.0, 0.0], "{name} at {x}");
            }
        }
    }

    /// Which tables are read from a grid: everything here but the line
    /// spectra (sodium, the black light's mercury lines at 404.656 and
    /// 435.833 nm, the made-up mercury lines).
    #[test]
    fn tables_on_grids_and_lines_kept() {
        for (name, t) in tables() {
            let lines = ["lines", "sodium", "blacklight"]
                .iter()
                .any(|l| name.contains(l));
            assert_eq!(t.is_gridded(), !lines, "{name}");
        }
        // The walls' breakpoints lie on 50 and 10 nm grids: exact.
        let t = Tabulated::new(
            vec![400.0, 550.0, 600.0, 700.0],
            vec![0.05, 0.06, 0.45, 0.64],
        )
        .unwrap();
        let Lookup::Grid { values, .. } = &t.lookup_for_tests() else {
            panic!("grid")
        };
        assert_eq!(values.len(), 7);
    }

    /// Photometry of every lamp and illuminant: X, Y, Z and V′ within
    /// 10⁻⁴ of the table's own function.
    #[test]
    fn photometry_is_unchanged() {
        for (name, t) in tables() {
            if name == "wall" || name.starts_with("Al") {
                continue;
            }
            let reference = Spectrum::tabulated(t.searched_for_tests());
            let (a, b) = (
                spectrum_to_xyzv(&Spectrum::tabulated(t)),
                spectrum_to_xyzv(&reference),
            );
            for (x, y) in [(a.x, b.x), (a.y, b.y), (a.z, b.z), (a.v, b.v)] {
                assert!((x - y).abs() <= 1e-4 * y.abs(), "{name}: {x} vs {y}");
            }
        }
    }
}
