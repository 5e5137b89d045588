//! scotopia's own optimiser for the Jakob & Hanika 2019 coefficient tables:
//! Gauss–Newton on the CIELAB residual between a target RGB and the colour of
//! the sigmoid-polynomial reflectance under the space's white illuminant
//! (Jakob & Hanika 2019, §4), with step halving when a step overshoots.

use rayon::prelude::*;

use super::table::{xy_nodes, z_nodes, SigmoidTable};
use crate::space::{xyz_to_lab, Mat3, RgbSpace};
use crate::spectrum::normalised_lambda;
use crate::upsample::weights::ReflectanceWeights;

/// CIELAB linear-segment threshold (6/29)³ and slope (29/3)³, CIE 015:2018 eq. 8.3.
const EPSILON: f64 = 216.0 / 24389.0;
const KAPPA: f64 = 24389.0 / 27.0;
/// Bound on |cᵢ|. Colours no smooth reflectance reaches (the spectral-locus
/// primaries of Rec.2020, ACEScg's beyond it) drive the fit towards box
/// spectra with unbounded coefficients; at 10⁴ the sigmoid's edge is already
/// narrower than 0.1 nm, so nothing is lost by stopping there.
const COEFF_MAX: f64 = 300.0;

/// Fits sigmoid-polynomial coefficients to RGB reflectances of one space.
pub struct Fitter {
    /// Normalised wavelength, its square, and the XYZ weights, per sample.
    samples: Vec<(f64, f64, [f64; 3])>,
    space: RgbSpace,
    white: [f64; 3],
}

/// A fit: the coefficients and the final CIELAB residual norm.
#[derive(Debug, Clone, Copy)]
pub struct Fit {
    pub coeffs: [f64; 3],
    pub residual: f64,
}

impl Fitter {
    pub fn new(space: RgbSpace) -> Self {
        let w = ReflectanceWeights::of(space);
        let samples = w
            .lambda
            .iter()
            .zip(&w.w)
            .map(|(&l, &w)| {
                let t = normalised_lambda(l) as f64;
                (t, t * t, w)
            })
            .collect();
        Self {
            samples,
            space,
            white: space.def().white_xyz(),
        }
    }

    /// XYZ of the coefficients' reflectance, and its Jacobian ∂XYZ/∂c.
    fn xyz_and_jacobian(&self, c: &[f64; 3]) -> ([f64; 3], [[f64; 3]; 3]) {
        let mut xyz = [0.0; 3];
        let mut jac = [[0.0; 3]; 3];
        for &(t, t2, w) in &self.samples {
            let x = c[0] * t2 + c[1] * t + c[2];
            let r = 1.0 / (1.0 + x * x).sqrt();
            let s = 0.5 + 0.5 * x * r;
            // dS/dx = ½ (1 + x²)^(−3/2)
            let ds = 0.5 * r * r * r;
            let basis = [t2 * ds, t * ds, ds];
            for k in 0..3 {
                xyz[k] += w[k] * s;
                for (j, b) in basis.iter().enumerate() {
                    jac[k][j] += w[k] * b;
                }
            }
        }
        (xyz, jac)
    }

    /// CIELAB of `xyz` and ∂Lab/∂XYZ.
    fn lab_and_jacobian(&self, xyz: [f64; 3]) -> ([f64; 3], [[f64; 3]; 3]) {
        let f = |v: f64| {
            if v > EPSILON {
                v.cbrt()
            } else {
                (KAPPA * v + 16.0) / 116.0
            }
        };
        let df = |v: f64| {
            if v > EPSILON {
                1.0 / (3.0 * v.cbrt() * v.cbrt())
            } else {
                KAPPA / 116.0
            }
        };
        let n = [0, 1, 2].map(|k| xyz[k] / self.white[k]);
        let d = [0, 1, 2].map(|k| df(n[k]) / self.white[k]);
        let lab = xyz_to_lab(xyz, self.white);
        debug_assert!((lab[0] - (116.0 * f(n[1]) - 16.0)).abs() < 1e-9);
        let jac = [
            [0.0, 116.0 * d[1], 0.0],
            [500.0 * d[0], -500.0 * d[1], 0.0],
            [0.0, 200.0 * d[1], -200.0 * d[2]],
        ];
        (lab, jac)
    }

    fn residual(&self, c: &[f64; 3], target: &[f64; 3]) -> ([f64; 3], [[f64; 3]; 3]) {
        let (xyz, jx) = self.xyz_and_jacobian(c);
        let (lab, jl) = self.lab_and_jacobian(xyz);
        let r = [0, 1, 2].map(|k| lab[k] - target[k]);
        let j = std::array::from_fn(|a| {
            std::array::from_fn(|b| (0..3).map(|k| jl[a][k] * jx[k][b]).sum())
        });
        (r, j)
    }

    /// Gauss–Newton from `start` towards the reflectance of colour `rgb`.
    pub fn fit(&self, rgb: [f64; 3], start: [f64; 3]) -> Fit {
        let target = xyz_to_lab(self.space.def().rgb_to_xyz(rgb), self.white);
        let norm = |r: &[f64; 3]| (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]).sqrt();
        let mut c = start;
        let (mut r, mut j) = self.residual(&c, &target);
        let mut err = norm(&r);
        for _ in 0..200 {
            if err < 1e-8 {
                break;
            }
            let Some(step) = solve3(j, r) else { break };
            // Halve the step until it reduces the residual.
            let mut scale = 1.0;
            let mut improved = false;
            for _ in 0..30 {
                let trial = [0, 1, 2].map(|k| c[k] - scale * step[k]);
                if trial.iter().all(|v| v.abs() <= COEFF_MAX) {
                    let (r2, j2) = self.residual(&trial, &target);
                    let e2 = norm(&r2);
                    if e2 < err {
                        (c, r, j, err) = (trial, r2, j2, e2);
                        improved = true;
                        break;
                    }
                }
                scale *= 0.5;
            }
            if !improved {
                break;
            }
        }
        Fit {
            coeffs: c,
            residual: err,
        }
    }

    /// Fits the whole table: for each of the three "largest component" blocks
    /// and each (x, y) column, start at a mid brightness from a flat grey and
    /// walk up and down in z, each fit warm-started from its neighbour
    /// (Jakob & Hanika 2019, §4.2). Columns run in parallel.
    pub fn build_table(&self, res: usize) -> (SigmoidTable, f64) {
        let z_nodes: Vec<f32> = z_nodes(res).iter().map(|&z| z as f32).collect();
        let xy = xy_nodes(res);
        let start_k = res / 5;
        let columns: Vec<(usize, usize, usize)> = (0..3)
            .flat_map(|l| (0..res).flat_map(move |j| (0..res).map(move |i| (l, j, i))))
            .collect();
        let fitted: Vec<(Vec<[f32; 3]>, f64)> = columns
            .par_iter()
            .map(|&(l, j, i)| {
                let (x, y) = (xy[i], xy[j]);
                let mut out = vec![[0.0f32; 3]; res];
                let mut worst: f64 = 0.0;
                let mut fit_at = |k: usize, start: [f64; 3]| {
                    let z = z_nodes[k] as f64;
                    let mut rgb = [0.0; 3];
                    rgb[l] = z;
                    rgb[(l + 1) % 3] = x * z;
                    rgb[(l + 2) % 3] = y * z;
                    let mut f = self.fit(rgb, start);
                    // A warm start from a neighbour at the edge of the
                    // reachable set can stall; a cold start may not.
                    if f.residual > 1e-3 {
                        let cold = self.fit(rgb, [0.0; 3]);
                        if cold.residual < f.residual {
                            f = cold;
                        }
                    }
                    out[k] = f.coeffs.map(|v| v as f32);
                    // Below 1e-4 of white the target is too dark to matter.
                    if z > 1e-4 {
                        worst = worst.max(f.residual);
                    }
                    f.coeffs
                };
                let mid = fit_at(start_k, [0.0; 3]);
                let mut c = mid;
                for k in start_k + 1..res {
                    c = fit_at(k, c);
                }
                c = mid;
                for k in (1..start_k).rev() {
                    c = fit_at(k, c);
                }
                // z = 0 is black, which no sigmoid reaches: take the limit from above.
                out[0] = out[1];
                (out, worst)
            })
            .collect();
        let mut table = SigmoidTable::empty(res, z_nodes);
        let mut worst: f64 = 0.0;
        for (&(l, j, i), (column, w)) in columns.iter().zip(&fitted) {
            worst = worst.max(*w);
            for (k, c) in column.iter().enumerate() {
                table.set(l, k, j, i, *c);
            }
        }
        (table, worst)
    }
}

/// Solves J·x = r for 3×3 J; `None` when singular.
fn solve3(j: [[f64; 3]; 3], r: [f64; 3]) -> Option<[f64; 3]> {
    Mat3(j).inverse().map(|m| m.apply(r))
}
