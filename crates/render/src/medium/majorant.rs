//! A majorant grid: coarse super-voxels over a heterogeneous medium's unit
//! cube, each holding a bound on σ_t (every wavelength) inside it, walked
//! along a ray by a 3D DDA (Amanatides & Woo 1987). Tracking then draws
//! tentative collisions at each super-voxel's own rate, so that empty or
//! thin regions cost few steps (pbrt-v4 §11.4.3 does the same).

use super::volume::{Field, GridVolume};
use super::Grid;
use crate::math::Vec3;

/// Cells of the density grid along each axis of one super-voxel.
const CELLS_PER_SUPER_VOXEL: usize = 4;
/// At most this many super-voxels along an axis.
const MAX_SUPER_VOXELS: usize = 64;

#[derive(Debug, Clone, PartialEq)]
pub struct Majorants {
    res: [usize; 3],
    /// Bounds of the unscaled σ_t, `(z·ny + y)·nx + x`.
    max: Vec<f32>,
    /// Whether σ_t is grey and equal to the bound throughout the
    /// super-voxel (every cell read holds the same value), so that
    /// Beer–Lambert gives its transmittance exactly.
    uniform: Vec<bool>,
}

impl Majorants {
    /// For σ_t given by `field`: one super-voxel of bound 1 for a constant
    /// (the caller multiplies by the cluster's largest σ_t), otherwise the
    /// largest value of the cells each super-voxel's lookups may read.
    pub fn of(field: &Field) -> Self {
        match field {
            Field::Constant { .. } => Self {
                res: [1; 3],
                max: vec![1.0],
                uniform: vec![false],
            },
            Field::Grid(g) => Self::of_grid(g),
        }
    }

    fn of_grid(g: &GridVolume) -> Self {
        let n = g.grid().resolution();
        let res = n.map(|n| n.div_ceil(CELLS_PER_SUPER_VOXEL).clamp(1, MAX_SUPER_VOXELS));
        // Per axis and super-voxel: the range of cells read inside it.
        let ranges: Vec<Vec<(usize, usize)>> = (0..3)
            .map(|a| {
                (0..res[a])
                    .map(|j| {
                        let m = res[a] as f64;
                        Grid::cells_read(j as f64 / m, (j + 1) as f64 / m, n[a])
                    })
                    .collect()
            })
            .collect();
        let mut max = Vec::with_capacity(res[0] * res[1] * res[2]);
        let mut uniform = Vec::with_capacity(res[0] * res[1] * res[2]);
        for &(z0, z1) in &ranges[2] {
            for &(y0, y1) in &ranges[1] {
                for &(x0, x1) in &ranges[0] {
                    let (mut lo, mut hi) = (f32::INFINITY, 0.0f32);
                    for z in z0..=z1 {
                        for y in y0..=y1 {
                            for x in x0..=x1 {
                                let v = g.cell_top((z * n[1] + y) * n[0] + x);
                                (lo, hi) = (lo.min(v), hi.max(v));
                            }
                        }
                    }
                    max.push(hi);
                    uniform.push(!g.is_rgb() && lo == hi);
                }
            }
        }
        Self { res, max, uniform }
    }

    pub fn resolution(&self) -> [usize; 3] {
        self.res
    }

    /// The largest bound.
    pub fn max(&self) -> f32 {
        self.max.iter().copied().fold(0.0, f32::max)
    }

    /// Walks the ray `o + t·d` (in the unit cube's space) over [t0, t1]
    /// (inside the cube), calling `f(ta, tb, bound, uniform)` for each
    /// super-voxel segment in order until it returns false.
    pub fn walk(
        &self,
        o: Vec3,
        d: Vec3,
        t0: f32,
        t1: f32,
        mut f: impl FnMut(f32, f32, f32, bool) -> bool,
    ) {
        let (oa, da) = ([o.x, o.y, o.z], [d.x, d.y, d.z]);
        let p = o + d * t0;
        let pa = [p.x, p.y, p.z];
        let mut cell = [0usize; 3];
        let mut next = [f32::INFINITY; 3];
        let mut delta = [f32::INFINITY; 3];
        for a in 0..3 {
            let m = self.res[a];
            cell[a] = ((pa[a] * m as f32).max(0.0) as usize).min(m - 1);
            if da[a] > 0.0 {
                next[a] = ((cell[a] + 1) as f32 / m as f32 - oa[a]) / da[a];
                delta[a] = 1.0 / (m as f32 * da[a]);
            } else if da[a] < 0.0 {
                next[a] = (cell[a] as f32 / m as f32 - oa[a]) / da[a];
                delta[a] = -1.0 / (m as f32 * da[a]);
            }
        }
        let mut t = t0;
        loop {
            // The axis whose boundary comes first.
            let a = if next[0] <= next[1] && next[0] <= next[2] {
                0
            } else if next[1] <= next[2] {
                1
            } else {
                2
            };
            let end = next[a].min(t1);
            let i = (cell[2] * self.res[1] + cell[1]) * self.res[0] + cell[0];
            if end > t && !f(t, end, self.max[i], self.uniform[i]) {
                return;
            }
            if next[a] >= t1 {
                return;
            }
            t = end;
            next[a] += delta[a];
            let stepped = if da[a] > 0.0 {
                cell[a] + 1
            } else {
                cell[a].wrapping_sub(1)
            };
            if stepped >= self.res[a] {
                return;
            }
            cell[a] = stepped;
        }
    }
}
