//! A density's inverse CDF tabulated at N + 1 equally spaced u and
//! interpolated linearly between them: a wavelength costs one multiply,
//! one index and one lerp, with no search, square root or division.
//!
//! The table is a density of its own, and the estimator divides by that
//! one, not by the density it was made from: a linear piece of the inverse
//! CDF between λ[j] and λ[j+1] spreads the mass 1/N evenly over the cell,
//! so p(λ) = (1/N) / (λ[j+1] − λ[j]) there. Sampling returns that value
//! with the wavelength, which makes sampler and pdf consistent by
//! construction: any increasing table is unbiased, and how well λ[j]
//! follows the source density only sets the variance. The cells are
//! equal-mass, so they crowd where the mass is: a 0.2 nm emission line
//! holding a tenth of the power gets N/10 cells inside it and keeps its
//! triangle shape; only the two cells that straddle a line's edges mix
//! it with its surroundings (at most 2/N of the mass per line).

use super::SpectralPdf;

/// Cells of the table: the sodium lines of scenes/night-street.xml hold
/// about half its mass in 0.4 nm; with 2048 cells the table's density
/// stays within a few per cent of the exact mixture there (see the
/// `resolution_of_the_table` test) at 24 KB, inside a core's L1 cache.
pub const CELLS: usize = 2048;

/// One equal-mass cell: it starts at `start` nm, spans `width` nm, and
/// its density is (1/N)/width per nm.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Cell {
    start: f32,
    width: f32,
    density: f32,
}

#[derive(Debug, Clone, PartialEq)]
pub struct InverseCdf {
    cells: Box<[Cell]>,
    /// The upper end of the last cell.
    end: f32,
}

impl InverseCdf {
    /// The table of `p` with `n` cells (n ≥ 1): its edges are p's exact
    /// quantiles j/n. Each cell keeps its start rounded to f32 but its
    /// width and density from the f64 quantiles: rounded to f32 steps of
    /// λ, the widths of the cells inside a sodium line (a few steps each)
    /// would scatter the density by ±20 % from cell to cell.
    pub fn new(p: &SpectralPdf, n: usize) -> Self {
        let n = n.max(1);
        let (lo, hi) = p.support();
        let mut edges: Vec<f64> = (0..=n).map(|j| p.quantile(j as f64 / n as f64)).collect();
        edges[0] = lo as f64;
        edges[n] = hi as f64;
        let cells = edges
            .windows(2)
            .map(|e| {
                // A zero width (a density with gaps, which the mixture's
                // defensive share never has) becomes a tiny one.
                let width = (e[1] - e[0]).max(1e-9);
                Cell {
                    start: e[0] as f32,
                    width: width as f32,
                    density: (1.0 / (n as f64 * width)) as f32,
                }
            })
            .collect();
        Self { cells, end: hi }
    }

    /// A wavelength for u ∈ [0, 1) and the table's density there (per nm).
    #[inline]
    pub fn sample(&self, u: f32) -> (f32, f32) {
        let n = self.cells.len();
        let x = u.clamp(0.0, 1.0) * n as f32;
        let j = (x as usize).min(n - 1);
        let c = self.cells[j];
        let f = (x - j as f32).min(1.0);
        (c.start + f * c.width, c.density)
    }

    /// K wavelengths stratified over the table, member k at u_k = (k + u)/K,
    /// and their densities. With n a multiple of K, u_k·n = k·n/K + u·n/K:
    /// every member shares one cell offset and one fraction, so a cluster
    /// costs one float-to-index conversion, not K (each is a dozen
    /// instructions, more than the rest of a member).
    #[inline]
    pub fn sample_strata<const K: usize>(&self, u: f32) -> ([f32; K], [f32; K]) {
        let n = self.cells.len();
        let per = n / K;
        if per == 0 || per * K != n {
            let members: [(f32, f32); K] =
                std::array::from_fn(|k| self.sample((k as f32 + u) / K as f32));
            return (members.map(|m| m.0), members.map(|m| m.1));
        }
        let x = u.clamp(0.0, 1.0) * per as f32;
        // `as u32`: the saturating conversion to u64 takes twice as many
        // instructions.
        let i = (x as u32 as usize).min(per - 1);
        let f = (x - i as f32).min(1.0);
        let cells: [Cell; K] = std::array::from_fn(|k| self.cells[(k * per + i).min(n - 1)]);
        (
            std::array::from_fn(|k| cells[k].start + f * cells[k].width),
            std::array::from_fn(|k| cells[k].density),
        )
    }

    /// The table's density at `lambda` (per nm): the cell that holds it,
    /// by bisection. Sampling returns this value without a search, and
    /// that is the one to divide by: a cell keeps its exact width while
    /// its start is rounded to f32, so the last f32 step of a cell can
    /// hold the next one's start, where this lookup finds the neighbour.
    pub fn pdf(&self, lambda: f32) -> f32 {
        if !(lambda >= self.cells[0].start && lambda <= self.end) {
            return 0.0;
        }
        let j = self.cells.partition_point(|c| c.start <= lambda);
        self.cells[j.max(1) - 1].density
    }

    /// The table's probability mass in [a, b].
    pub fn mass_between(&self, a: f32, b: f32) -> f64 {
        self.cells
            .iter()
            .map(|c| {
                // In f64: rounded to f32, a cell a few f32 steps wide
                // would lose or gain a fraction of its mass.
                let (start, end) = (c.start as f64, c.start as f64 + c.width as f64);
                let hi = (b as f64).min(end);
                let lo = (a as f64).max(start);
                (hi - lo).max(0.0) * c.density as f64
            })
            .sum()
    }
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use scotopia_color::{cie, io, Spectrum};

    use super::*;
    use crate::test_rng::Rng;

    fn lamp(name: &str) -> Spectrum {
        let p = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../scenes/lamps")
            .join(name);
        Spectrum::from(io::read_spectrum_file(&p).unwrap())
    }

    /// The night street's mixture, roughly: two sodium lamps, an LED, a
    /// dim sky, and the defensive visible share.
    fn street() -> SpectralPdf {
        let (na, led) = (
            SpectralPdf::new(&lamp("low-pressure-sodium.csv")).unwrap(),
            SpectralPdf::new(&lamp("led-4000k.csv")).unwrap(),
        );
        let sky = SpectralPdf::new(&cie::illuminant("d65").unwrap()).unwrap();
        let lights = SpectralPdf::mixture(&[(0.6, &na), (0.35, &led), (0.05, &sky)]).unwrap();
        SpectralPdf::mixture(&[(0.9, &lights), (0.1, &SpectralPdf::visible())]).unwrap()
    }

    /// χ² divergence ∫ p²/q − 1 of the table q from the density p it was
    /// made of: the relative variance it adds to an integrand ∝ p.
    /// Simpson's rule on every piece between p's nodes and q's edges,
    /// exact for p² there.
    fn divergence(p: &SpectralPdf, q: &InverseCdf) -> f64 {
        let mut x: Vec<f32> = p.nodes().to_vec();
        x.extend(q.cells.iter().map(|c| c.start));
        x.push(q.end);
        x.sort_by(f32::total_cmp);
        x.dedup();
        x.windows(2)
            .map(|w| {
                let (a, b) = (w[0] as f64, w[1] as f64);
                let m = 0.5 * (a + b);
                let ql = q.pdf(m as f32) as f64;
                // p is linear on [a, b]: evaluate it at the ends from inside.
                let pa = p.pdf(w[0]) as f64;
                let pb = p.pdf(w[1]) as f64;
                let pm = 0.5 * (pa + pb);
                (b - a) / 6.0 * (pa * pa + 4.0 * pm * pm + pb * pb) / ql
            })
            .sum::<f64>()
            - 1.0
    }

    /// The χ² divergence of the table from the street's mixture falls with
    /// N (printed: 256 → 0.22, 1024 → 0.034, 2048 → 0.016, 4096 → 0.005);
    /// the table's size is chosen where it adds under 2 % to the variance
    /// of what the lamps light and still fits the L1 cache.
    #[test]
    fn resolution_of_the_table() {
        let p = street();
        for n in [256, 1024, CELLS, 4096] {
            let d = divergence(&p, &InverseCdf::new(&p, n));
            println!("N = {n}: χ² divergence {d:.2e}");
            if n == CELLS {
                assert!(d < 0.02, "{d}");
            }
        }
    }

    /// Samples follow the table's own density: a χ² test over 10 nm bins
    /// and 0.05 nm bins across the sodium lines, with expected counts from
    /// integrating `pdf`, at 5 standard deviations of the statistic.
    #[test]
    fn samples_follow_the_tables_density() {
        let q = InverseCdf::new(&street(), CELLS);
        let mut edges: Vec<f32> = (0..=47).map(|i| 360.0 + 10.0 * i as f32).collect();
        edges.extend((0..=30).map(|i| 588.8 + 0.05 * i as f32));
        edges.sort_by(f32::total_cmp);
        edges.dedup_by(|a, b| (*a - *b).abs() < 1e-3);
        let bins = edges.len() - 1;
        let n = 1_000_000;
        let mut count = vec![0u32; bins];
        let mut rng = Rng(5);
        for _ in 0..n {
            let (l, _) = q.sample(rng.next());
            let b = edges.partition_point(|&e| e <= l).clamp(1, bins) - 1;
            count[b] += 1;
        }
        let mut chi2 = 0.0;
        for (b, &c) in count.iter().enumerate() {
            // ∫ pdf over the bin, at 2 000 points (the cells are finer
            // than that only where the line's mass is, counted exactly by
            // `mass_between`).
            let expected = q.mass_between(edges[b], edges[b + 1]) * n as f64;
            assert!(expected > 5.0, "bin {b} too small for χ²");
            chi2 += (c as f64 - expected).powi(2) / expected;
        }
        let dof = (bins - 1) as f64;
        assert!(
            chi2 < dof + 5.0 * (2.0 * dof).sqrt(),
            "χ² {chi2} over {dof} dof"
        );
        // The masses the test expects are the pdf's integral.
        let m = 2_000_000;
        let riemann: f64 = (0..m)
            .map(|i| q.pdf(360.0 + 470.0 * (i as f32 + 0.5) / m as f32) as f64 * 470.0 / m as f64)
            .sum();
        assert!((riemann - 1.0).abs() < 1e-3, "∫ pdf = {riemann}");
        assert!((q.mass_between(300.0, 900.0) - 1.0).abs() < 1e-5);
    }

    /// The density returned with a sample is `pdf` at that wavelength.
    #[test]
    fn sampled_and_evaluated_densities_agree() {
        let q = InverseCdf::new(&street(), CELLS);
        let mut rng = Rng(11);
        for i in 0..200_000 {
            // Cell centres, and random points.
            let u = if i < CELLS {
                (i as f32 + 0.5) / CELLS as f32
            } else {
                rng.next()
            };
            let (l, p) = q.sample(u);
            assert!((360.0..=830.0).contains(&l), "{l}");
            // Rounded to f32, the last sliver of a cell can land on the
            // next cell's start (or one f32 step above it): there the
            // lookup finds the neighbour. Nowhere else.
            if q.pdf(l) != p {
                let j = q.cells.partition_point(|c| c.start <= l).max(1) - 1;
                let step = q.cells[j].start * f32::EPSILON;
                assert!(
                    l - q.cells[j].start <= step && q.cells[j - 1].density == p,
                    "u {u}: λ {l}, sampled {p} vs pdf {}",
                    q.pdf(l)
                );
            }
        }
        assert_eq!(q.sample(0.0).0, 360.0);
        assert!(q.sample(0.999_999_94).0 <= 830.0);
        assert_eq!(q.pdf(359.0), 0.0);
        assert_eq!(q.pdf(f32::NAN), 0.0);
    }

    /// A cluster's members are the table's samples at (k + u)/K.
    #[test]
    fn strata_are_single_samples() {
        fn check<const K: usize>(q: &InverseCdf, u: f32) {
            let (l, p) = q.sample_strata::<K>(u);
            for k in 0..K {
                let (lk, pk) = q.sample((k as f32 + u) / K as f32);
                assert!((l[k] - lk).abs() < 1e-3, "K {K} u {u}: {} vs {lk}", l[k]);
                // Away from a cell's ends both find the same cell.
                let f = (u * (CELLS / K) as f32).fract();
                assert!(p[k] == pk || !(0.01..0.99).contains(&f), "K {K} u {u}");
            }
        }
        let q = InverseCdf::new(&street(), CELLS);
        let mut rng = Rng(2);
        for _ in 0..20_000 {
            let u = rng.next();
            check::<1>(&q, u);
            check::<2>(&q, u);
            check::<4>(&q, u);
            check::<8>(&q, u);
            check::<16>(&q, u);
        }
        // A table whose size K does not divide still stratifies.
        let odd = InverseCdf::new(&street(), 1001);
        let (l, _) = odd.sample_strata::<4>(0.5);
        assert_eq!(l[1], odd.sample(0.375).0);
    }

    /// A 0.2 nm sodium line keeps its mass inside it: the table puts the
    /// exact density's mass there, up to the two cells that straddle its
    /// ends, and so do the samples.
    #[test]
    fn lines_keep_their_mass() {
        let p = SpectralPdf::new(&lamp("low-pressure-sodium.csv")).unwrap();
        let q = InverseCdf::new(&p, CELLS);
        for (a, b) in [(588.895, 589.095), (589.492, 589.692)] {
            let exact = p.mass_below(b) - p.mass_below(a);
            let table = q.mass_between(a, b);
            assert!(
                (table - exact).abs() < 2.0 / CELLS as f64,
                "{a}–{b}: {table} vs {exact}"
            );
            // Cells wholly inside the line.
            let inside = q
                .cells
                .iter()
                .filter(|c| c.start >= a && c.start + c.width <= b)
                .count();
            assert!(inside as f64 >= exact * CELLS as f64 - 2.0, "{inside}");
            let n = 100_000;
            let hits = (0..n)
                .filter(|&i| (a..b).contains(&q.sample((i as f32 + 0.5) / n as f32).0))
                .count();
            assert!(
                (hits as f64 / n as f64 - table).abs() < 2.0 / n as f64 + 1e-6,
                "{hits}"
            );
        }
    }
}
