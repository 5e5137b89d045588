//! A measured reradiation (Donaldson) matrix: the bispectral radiance
//! factor D(λi, λo) on a grid of excitation wavelengths (columns) and
//! emission wavelengths (rows), as bispectrometers report it (Donaldson
//! 1954; CIE 182:2007). Each cell is dimensionless: the radiance at λo,
//! relative to a perfect white diffuser, from light in the excitation
//! band around λi. Under an illuminant S the total radiance factor is
//! β(λo) = Σ_i D(λi, λo)·S(λi)/S(λo).
//!
//! Cells with λi = λo hold the elastic reflectance (the caller decides
//! whether to use them); the others are fluorescence. As a continuous
//! function, per nm of excitation wavelength,
//!
//!   F(λi → λo) = D(column of λi, λo)/Δλ_column,
//!
//! piecewise constant over each column's band (midway to its neighbours)
//! and linear in λo between rows, zero outside the rows. Sampling draws a
//! row by its interpolation weight times its mass, then a band by mass,
//! then λi uniformly in the band, which makes p(λi) exactly F/∫F: every
//! sample weighs ∫F dλi.

use scotopia_color::{Spectrum, Tabulated, LAMBDA_MAX, LAMBDA_MIN};

use crate::sampling::spectral_pdf::SpectralPdf;

#[derive(Debug, Clone, PartialEq)]
pub struct Donaldson {
    /// Emission wavelengths, nm, increasing.
    rows: Vec<f32>,
    /// Band edges of the excitation columns, nm, clipped to λmin..λmax.
    edges: Vec<f32>,
    /// Row-major (rows × columns): F per nm of λi, zero on the diagonal.
    density: Vec<f32>,
    /// Per row, the running mass over the columns (columns + 1 entries).
    cdf: Vec<f32>,
    /// ∫F over λo as rows' masses, for sampling λo ∝ emission.
    emission: SpectralPdf,
    /// The diagonal cells, where every row has one.
    diagonal: Option<Spectrum>,
    /// ∫ F(λi → λo) dλo per column.
    column_out: Vec<f32>,
}

impl Donaldson {
    /// `values` row-major: `emission.len()` rows of `excitation.len()`
    /// cells. Wavelengths must increase. Negative cells (measurement
    /// noise) count as zero; the second value says how many there were.
    pub fn new(
        excitation: &[f32],
        emission: &[f32],
        values: &[f32],
    ) -> Result<(Self, usize), String> {
        let (nc, nr) = (excitation.len(), emission.len());
        if nc < 2 || nr < 2 {
            return Err(format!(
                "the matrix needs at least two excitation and two emission wavelengths, \
                 got {nc} and {nr}"
            ));
        }
        if values.len() != nc * nr {
            return Err(format!(
                "{nr} rows of {nc} cells need {} values, got {}",
                nc * nr,
                values.len()
            ));
        }
        for axis in [excitation, emission] {
            if axis.windows(2).any(|w| w[1] <= w[0]) || axis.iter().any(|l| !l.is_finite()) {
                return Err("wavelengths must be finite and increase".into());
            }
        }
        // Column bands reach halfway to the neighbours.
        let mut edges = Vec::with_capacity(nc + 1);
        edges.push(excitation[0] - 0.5 * (excitation[1] - excitation[0]));
        for w in excitation.windows(2) {
            edges.push(0.5 * (w[0] + w[1]));
        }
        edges.push(excitation[nc - 1] + 0.5 * (excitation[nc - 1] - excitation[nc - 2]));
        let width: Vec<f32> = edges.windows(2).map(|w| w[1] - w[0]).collect();
        let clipped: Vec<f32> = edges
            .iter()
            .map(|e| e.clamp(LAMBDA_MIN, LAMBDA_MAX))
            .collect();
        let diagonal_of = |r: usize| {
            excitation
                .iter()
                .position(|&l| (l - emission[r]).abs() < 1e-3)
        };
        let mut negative = 0;
        let mut density = vec![0.0f32; nr * nc];
        let mut cdf = vec![0.0f32; nr * (nc + 1)];
        for r in 0..nr {
            let diag = diagonal_of(r);
            for c in 0..nc {
                let v = values[r * nc + c];
                if v < 0.0 {
                    negative += 1;
                }
                let f = if Some(c) == diag {
                    0.0
                } else {
                    v.max(0.0) / width[c]
                };
                density[r * nc + c] = f;
                let mass = f * (clipped[c + 1] - clipped[c]);
                cdf[r * (nc + 1) + c + 1] = cdf[r * (nc + 1) + c] + mass;
            }
        }
        let row_mass: Vec<f32> = (0..nr).map(|r| cdf[r * (nc + 1) + nc]).collect();
        let emission_pdf = Tabulated::new(emission.to_vec(), row_mass)
            .ok()
            .and_then(|t| SpectralPdf::new(&Spectrum::tabulated(t)))
            .ok_or("no fluorescent (off-diagonal) cell is positive within 360–830 nm")?;
        let diagonal = (0..nr)
            .map(|r| diagonal_of(r).map(|c| values[r * nc + c].max(0.0)))
            .collect::<Option<Vec<f32>>>()
            .and_then(|d| Tabulated::new(emission.to_vec(), d).ok())
            .map(Spectrum::tabulated);
        // ∫ over λo of the rows' linear interpolation: trapezoid weights.
        let row_weight: Vec<f32> = (0..nr)
            .map(|r| {
                let left = if r > 0 {
                    emission[r] - emission[r - 1]
                } else {
                    0.0
                };
                let right = if r + 1 < nr {
                    emission[r + 1] - emission[r]
                } else {
                    0.0
                };
                0.5 * (left + right)
            })
            .collect();
        let column_out = (0..nc)
            .map(|c| (0..nr).map(|r| density[r * nc + c] * row_weight[r]).sum())
            .collect();
        Ok((
            Self {
                rows: emission.to_vec(),
                edges: clipped,
                density,
                cdf,
                emission: emission_pdf,
                diagonal,
                column_out,
            },
            negative,
        ))
    }

    fn columns(&self) -> usize {
        self.edges.len() - 1
    }

    /// The elastic reflectance from the diagonal cells, if every emission
    /// wavelength has an equal excitation wavelength.
    pub fn diagonal(&self) -> Option<&Spectrum> {
        self.diagonal.as_ref()
    }

    /// The row interval holding λo and the weight of the upper row.
    fn row_at(&self, lambda_o: f32) -> Option<(usize, f32)> {
        let rows = &self.rows;
        if !(rows[0]..=rows[rows.len() - 1]).contains(&lambda_o) {
            return None;
        }
        let r = rows
            .partition_point(|&l| l <= lambda_o)
            .clamp(1, rows.len() - 1)
            - 1;
        Some((r, (lambda_o - rows[r]) / (rows[r + 1] - rows[r])))
    }

    /// The column whose band holds λi.
    fn column_at(&self, lambda_i: f32) -> Option<usize> {
        let e = &self.edges;
        if !(e[0]..e[e.len() - 1]).contains(&lambda_i) {
            return None;
        }
        Some(e.partition_point(|&x| x <= lambda_i) - 1)
    }

    fn row_mass(&self, r: usize) -> f32 {
        self.cdf[r * (self.columns() + 1) + self.columns()]
    }

    /// F(λi → λo), per nm of λi.
    pub fn eval(&self, lambda_i: f32, lambda_o: f32) -> f32 {
        let (Some((r, t)), Some(c)) = (self.row_at(lambda_o), self.column_at(lambda_i)) else {
            return 0.0;
        };
        let nc = self.columns();
        (1.0 - t) * self.density[r * nc + c] + t * self.density[(r + 1) * nc + c]
    }

    /// ∫ F(λi → λo) dλi.
    pub fn albedo(&self, lambda_o: f32) -> f32 {
        self.row_at(lambda_o).map_or(0.0, |(r, t)| {
            (1.0 - t) * self.row_mass(r) + t * self.row_mass(r + 1)
        })
    }

    /// ∫ F(λi → λo) dλo.
    pub fn reemitted(&self, lambda_i: f32) -> f32 {
        self.column_at(lambda_i).map_or(0.0, |c| self.column_out[c])
    }

    /// The emission wavelengths' density (∝ the rows' masses).
    pub fn emission_density(&self) -> &SpectralPdf {
        &self.emission
    }

    /// λi drawn ∝ F(λi → λo), and F/p = ∫F dλi.
    pub fn sample(&self, u: f32, lambda_o: f32) -> Option<(f32, f32)> {
        let (r, t) = self.row_at(lambda_o)?;
        let (w0, w1) = ((1.0 - t) * self.row_mass(r), t * self.row_mass(r + 1));
        let total = w0 + w1;
        if total <= 0.0 {
            return None;
        }
        let target = u.clamp(0.0, 1.0) * total;
        let (row, mass) = if target < w0 || w1 <= 0.0 {
            (r, (target / (1.0 - t)).min(self.row_mass(r)))
        } else {
            (r + 1, ((target - w0) / t).min(self.row_mass(r + 1)))
        };
        let nc = self.columns();
        let cdf = &self.cdf[row * (nc + 1)..(row + 1) * (nc + 1)];
        // The first column whose running mass passes `mass`, skipping empty ones.
        let c = (cdf.partition_point(|&m| m <= mass).clamp(1, nc) - 1..nc)
            .find(|&c| cdf[c + 1] > cdf[c])?;
        let frac = ((mass - cdf[c]) / (cdf[c + 1] - cdf[c])).clamp(0.0, 1.0);
        let lambda_i = self.edges[c] + frac * (self.edges[c + 1] - self.edges[c]);
        Some((lambda_i, total))
    }
}

impl Donaldson {
    /// λo drawn ∝ F(λi → λo) (linear between rows within λi's column),
    /// and F/p = ∫F dλo (light paths run this way).
    pub fn sample_emission(&self, u: f32, lambda_i: f32) -> Option<(f32, f32)> {
        let c = self.column_at(lambda_i)?;
        let nc = self.columns();
        let cell = |r: usize| self.density[r * nc + c];
        let segment = |r: usize| 0.5 * (cell(r) + cell(r + 1)) * (self.rows[r + 1] - self.rows[r]);
        let total: f32 = (0..self.rows.len() - 1).map(segment).sum();
        if total <= 0.0 {
            return None;
        }
        // The segment by mass, then λo within it by the trapezoid's CDF.
        let mut target = u.clamp(0.0, 1.0) * total;
        let mut r = 0;
        while r + 2 < self.rows.len() && (target >= segment(r) || segment(r) <= 0.0) {
            target -= segment(r);
            r += 1;
        }
        let m = segment(r);
        if m <= 0.0 {
            return None;
        }
        let (a, b) = (cell(r), cell(r + 1));
        let x = (target / m).clamp(0.0, 1.0);
        // Density ∝ a + (b − a)·t on t ∈ [0, 1]: solve its CDF = x.
        let t = if (b - a).abs() < 1e-6 * (a + b) {
            x
        } else {
            ((a * a + x * (b * b - a * a)).max(0.0).sqrt() - a) / (b - a)
        };
        let lambda_o = self.rows[r] + t.clamp(0.0, 1.0) * (self.rows[r + 1] - self.rows[r]);
        Some((lambda_o, total))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// 400–700 nm every 10 nm; reflectance 0.5 on the diagonal; light
    /// absorbed at 400–440 re-emitted at 460–520 nm with a row profile.
    fn matrix() -> (Vec<f32>, Vec<f32>) {
        let grid: Vec<f32> = (0..31).map(|i| 400.0 + 10.0 * i as f32).collect();
        let mut v = vec![0.0; 31 * 31];
        for (r, &lo) in grid.iter().enumerate() {
            for (c, &li) in grid.iter().enumerate() {
                v[r * 31 + c] = if r == c {
                    0.5
                } else if li <= 440.0 && (460.0..=520.0).contains(&lo) {
                    0.01 * (1.0 + (lo - 460.0) / 60.0) * (450.0 - li) / 50.0
                } else {
                    0.0
                };
            }
        }
        (grid, v)
    }

    #[test]
    fn sampling_matches_the_density_and_weighs_its_integral() {
        let (grid, v) = matrix();
        let (d, negative) = Donaldson::new(&grid, &grid, &v).unwrap();
        assert_eq!(negative, 0);
        assert_eq!(d.diagonal().unwrap().eval(555.0), 0.5);
        // ∫F dλi at a row is the row's off-diagonal cells' sum.
        let row_sum: f32 = (0..5).map(|c| v[8 * 31 + c]).sum();
        assert!((d.albedo(480.0) - row_sum).abs() < 1e-6);
        // Between rows the estimator E[F/p·g] equals ∫F·g for a test g.
        let g = |l: f32| 1.0 + (l - 395.0) / 30.0;
        let lambda_o = 487.0;
        let n = 100_000;
        let mut est = 0.0f64;
        for i in 0..n {
            let (li, w) = d.sample((i as f32 + 0.5) / n as f32, lambda_o).unwrap();
            est += (w * g(li)) as f64;
        }
        let want: f64 = (0..40_000)
            .map(|i| {
                let l = 395.0 + (i as f32 + 0.5) * 0.01;
                (d.eval(l, lambda_o) * g(l)) as f64 * 0.01
            })
            .sum();
        assert!(
            (est / n as f64 / want - 1.0).abs() < 1e-3,
            "{est} vs {want}"
        );
        // Nothing beyond the rows or for λo without fluorescence.
        assert!(d.sample(0.5, 710.0).is_none() && d.sample(0.5, 600.0).is_none());
    }

    #[test]
    fn a_column_reemits_its_cells_and_noise_is_counted() {
        let (grid, mut v) = matrix();
        // Column 420 nm: interior rows weigh 10 nm, the matrix is per band.
        let want: f32 = (6..=12).map(|r| v[r * 31 + 2]).sum();
        let (d, _) = Donaldson::new(&grid, &grid, &v).unwrap();
        assert!((d.reemitted(421.0) - want).abs() < 1e-6);
        assert_eq!(d.reemitted(600.0), 0.0);
        v[100] = -1e-4;
        assert_eq!(Donaldson::new(&grid, &grid, &v).unwrap().1, 1);
        let msg = Donaldson::new(&grid, &grid, &vec![0.1; 31 * 31][..31 * 30]).unwrap_err();
        assert!(msg.contains("need 961 values"), "{msg}");
        let diag_only: Vec<f32> = (0..961)
            .map(|i| if i % 32 == 0 { 0.5 } else { 0.0 })
            .collect();
        assert!(Donaldson::new(&grid, &grid, &diag_only).is_err());
    }
}
