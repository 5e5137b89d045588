//! A voxel grid of 1, 3 or 6 channels over a box (Mitsuba's `gridvolume`
//! data), read by trilinear interpolation. As Mitsuba 3 (its Dr.Jit
//! textures), values sit at the cell centres, (i + ½)/n along each axis of
//! the unit cube, and lookups outside the centres clamp to the edge cells.

use crate::math::{Aabb, Vec3};

#[derive(Debug, Clone, PartialEq)]
pub struct Grid {
    /// Cells along x, y, z.
    res: [usize; 3],
    channels: usize,
    /// `data[((z·ny + y)·nx + x)·channels + c]`.
    data: Vec<f32>,
    /// The box the grid spans (its file's, before any `to_world`).
    pub bounds: Aabb,
    /// Largest value of each channel: the majorant of a density grid.
    max: Vec<f32>,
}

impl Grid {
    /// A grid of `res` cells and `channels` values per cell; `data` must
    /// hold exactly that many values. Errors say what is inconsistent.
    pub fn new(
        res: [usize; 3],
        channels: usize,
        bounds: Aabb,
        data: Vec<f32>,
    ) -> Result<Self, String> {
        if !matches!(channels, 1 | 3 | 6) {
            return Err(format!("{channels} channels: a grid has 1, 3 or 6"));
        }
        let cells = res
            .iter()
            .try_fold(1usize, |a, &n| a.checked_mul(n).filter(|_| n > 0));
        let expected = cells.and_then(|c| c.checked_mul(channels));
        if expected != Some(data.len()) {
            return Err(format!(
                "{} × {} × {} cells of {channels} channels need {} values, got {}",
                res[0],
                res[1],
                res[2],
                expected.map_or("too many".into(), |e| e.to_string()),
                data.len()
            ));
        }
        let mut max = vec![f32::NEG_INFINITY; channels];
        for cell in data.chunks_exact(channels) {
            for (m, v) in max.iter_mut().zip(cell) {
                *m = m.max(*v);
            }
        }
        Ok(Self {
            res,
            channels,
            data,
            bounds,
            max,
        })
    }

    pub fn resolution(&self) -> [usize; 3] {
        self.res
    }

    pub fn channels(&self) -> usize {
        self.channels
    }

    /// The largest value of channel `c`.
    pub fn max(&self, c: usize) -> f32 {
        self.max[c]
    }

    /// Channel `c` of cell number `cell` (`(z·ny + y)·nx + x`).
    #[inline]
    pub fn value(&self, cell: usize, c: usize) -> f32 {
        self.data[cell * self.channels + c]
    }

    /// The eight cells whose centres surround `p` (in the unit cube of
    /// the grid), clamped at the edges, with their trilinear weights
    /// (which sum to 1).
    #[inline]
    pub fn corners(&self, p: Vec3) -> [(usize, f32); 8] {
        // Per axis: the lower cell and the weight of the upper one.
        let axis = |u: f32, n: usize| -> (usize, usize, f32) {
            let x = (u * n as f32 - 0.5).clamp(0.0, (n - 1) as f32);
            let i = (x as usize).min(n - 1);
            (i, (i + 1).min(n - 1), x - i as f32)
        };
        let (x0, x1, fx) = axis(p.x, self.res[0]);
        let (y0, y1, fy) = axis(p.y, self.res[1]);
        let (z0, z1, fz) = axis(p.z, self.res[2]);
        let at = |x: usize, y: usize, z: usize| (z * self.res[1] + y) * self.res[0] + x;
        std::array::from_fn(|i| {
            let (x, wx) = if i & 1 == 0 { (x0, 1.0 - fx) } else { (x1, fx) };
            let (y, wy) = if i & 2 == 0 { (y0, 1.0 - fy) } else { (y1, fy) };
            let (z, wz) = if i & 4 == 0 { (z0, 1.0 - fz) } else { (z1, fz) };
            (at(x, y, z), wx * wy * wz)
        })
    }

    /// The cell holding `p` (in the unit cube of the grid), clamped: the
    /// nearest-neighbour lookup.
    #[inline]
    pub fn nearest(&self, p: Vec3) -> usize {
        let axis = |u: f32, n: usize| ((u * n as f32).max(0.0) as usize).min(n - 1);
        let (x, y, z) = (
            axis(p.x, self.res[0]),
            axis(p.y, self.res[1]),
            axis(p.z, self.res[2]),
        );
        (z * self.res[1] + y) * self.res[0] + x
    }

    /// The cells along one axis of `n` that trilinear lookups (or nearest
    /// ones) inside [a, b] of the unit interval may read.
    pub fn cells_read(a: f64, b: f64, n: usize) -> (usize, usize) {
        let top = (n - 1) as f64;
        let lo = (a * n as f64 - 0.5).floor().clamp(0.0, top) as usize;
        let hi = ((b * n as f64 - 0.5).floor() + 1.0).clamp(0.0, top) as usize;
        (lo, hi)
    }

    /// Channel `c` at `p` in the unit cube of the grid (0..1 on each
    /// axis), interpolated trilinearly between cell centres.
    pub fn lookup(&self, p: Vec3, c: usize) -> f32 {
        // Per axis: the lower cell and the weight of the upper one.
        let axis = |u: f32, n: usize| -> (usize, usize, f32) {
            let x = (u * n as f32 - 0.5).clamp(0.0, (n - 1) as f32);
            let i = (x as usize).min(n - 1);
            (i, (i + 1).min(n - 1), x - i as f32)
        };
        let (x0, x1, fx) = axis(p.x, self.res[0]);
        let (y0, y1, fy) = axis(p.y, self.res[1]);
        let (z0, z1, fz) = axis(p.z, self.res[2]);
        let at = |x: usize, y: usize, z: usize| {
            self.data[((z * self.res[1] + y) * self.res[0] + x) * self.channels + c]
        };
        // Nested lerps: a constant grid reads back exactly.
        let lerp = |a: f32, b: f32, t: f32| a + (b - a) * t;
        let plane = |z: usize| {
            lerp(
                lerp(at(x0, y0, z), at(x1, y0, z), fx),
                lerp(at(x0, y1, z), at(x1, y1, z), fx),
                fy,
            )
        };
        lerp(plane(z0), plane(z1), fz)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit() -> Aabb {
        Aabb {
            min: Vec3::ZERO,
            max: Vec3::splat(1.0),
        }
    }

    #[test]
    fn a_linear_field_is_reproduced_between_the_cell_centres() {
        // f = 2x + 3y − z + 1 sampled at the centres of a 4 × 3 × 5 grid
        // is interpolated exactly inside them, and clamps outside.
        let res = [4usize, 3, 5];
        let f = |x: f32, y: f32, z: f32| 2.0 * x + 3.0 * y - z + 1.0;
        let centre = |i: usize, n: usize| (i as f32 + 0.5) / n as f32;
        let mut data = Vec::new();
        for z in 0..res[2] {
            for y in 0..res[1] {
                for x in 0..res[0] {
                    data.push(f(centre(x, 4), centre(y, 3), centre(z, 5)));
                }
            }
        }
        let g = Grid::new(res, 1, unit(), data).unwrap();
        for p in [[0.3f32, 0.5, 0.4], [0.2, 0.2, 0.8], [0.6, 0.7, 0.15]] {
            let v = g.lookup(Vec3::new(p[0], p[1], p[2]), 0);
            assert!((v - f(p[0], p[1], p[2])).abs() < 1e-5, "{p:?}: {v}");
        }
        // Below the first centre along x: the edge value.
        let edge = g.lookup(Vec3::new(0.0, 0.5, 0.5), 0);
        assert!((edge - f(centre(0, 4), 0.5, 0.5)).abs() < 1e-5);
        assert!((g.max(0) - f(centre(3, 4), centre(2, 3), centre(0, 5))).abs() < 1e-6);
    }

    #[test]
    fn channels_are_kept_apart_and_sizes_are_checked() {
        let data: Vec<f32> = (0..2 * 2 * 2 * 3).map(|i| (i % 3) as f32).collect();
        let g = Grid::new([2, 2, 2], 3, unit(), data).unwrap();
        assert_eq!(g.lookup(Vec3::splat(0.4), 2), 2.0);
        assert!(Grid::new([2, 2, 2], 3, unit(), vec![0.0; 23])
            .unwrap_err()
            .contains("need 24"));
        assert!(Grid::new([2, 2, 2], 2, unit(), vec![0.0; 16]).is_err());
        assert!(Grid::new([0, 2, 2], 1, unit(), vec![]).is_err());
        assert!(Grid::new([usize::MAX, 2, 2], 1, unit(), vec![]).is_err());
    }
}
