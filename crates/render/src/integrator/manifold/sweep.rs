//! The grid of a ball's search (`ball.rs`) for the paths through it,
//! straight and with one reflection inside, traced together: both share
//! the ray from `x`, its refraction in and its first chord. The grid's
//! angles are traced as lanes of plain loops over arrays, compiled for
//! the widest level the CPU has (`simd::Level`), where the compiler turns
//! them into vector instructions: four angles per instruction at AVX2.
//! The same IEEE operations run at every level, so every level gives the
//! same bits.

use std::sync::LazyLock;

use crate::simd::{Kernel, Level, Wide};

/// Grid steps over the angle of incidence, −90° to 90°.
pub const STEPS: usize = 12;

/// The grid's angles, padded with the last to a multiple of 8 lanes.
const LANES: usize = 16;

/// sin θ and cos θ at the grid's angles, a hair inside ±90°.
pub static GRID: LazyLock<[(f64, f64); STEPS + 1]> = LazyLock::new(|| {
    let edge = std::f64::consts::FRAC_PI_2 * (1.0 - 1e-6);
    std::array::from_fn(|k| {
        let theta = -edge + 2.0 * edge * k as f64 / STEPS as f64;
        theta.sin_cos()
    })
});

/// [`GRID`] as two arrays of lanes.
static LANED: LazyLock<([f64; LANES], [f64; LANES])> = LazyLock::new(|| {
    let at = |k: usize| GRID[k.min(STEPS)];
    (
        std::array::from_fn(|k| at(k).0),
        std::array::from_fn(|k| at(k).1),
    )
});

/// The ball in the plane of a search: `x` at (dx, 0), the centre at the
/// origin, `y` at `y`; radius `r`, index ratio `eta`.
#[derive(Clone, Copy)]
pub struct Setting {
    pub dx: f64,
    pub y: (f64, f64),
    pub r: f64,
    pub eta: f64,
}

/// At each grid angle (`GRID`'s order), for paths straight through
/// (`[0]`) and with one reflection inside (`[1]`): g, the signed distance
/// of `y` from the last ray, and whether `y` lies ahead on it.
pub struct Swept {
    pub g: [[f64; LANES]; 2],
    pub ahead: [[bool; LANES]; 2],
}

impl Setting {
    /// Both kinds' g at every grid angle.
    pub fn sweep(self) -> Swept {
        let [g0, along0, g1, along1] = Level::current().run(self);
        let ahead = |a: [f64; LANES]| a.map(|v| v > 0.0);
        Swept {
            g: [g0, g1],
            ahead: [ahead(along0), ahead(along1)],
        }
    }

    /// g and the last ray's length along towards `y`, per lane: the same
    /// steps as `Plane::trace`, written lane by lane.
    #[inline(always)]
    fn lanes(self) -> [[f64; LANES]; 4] {
        let Setting { dx, y, r, eta } = self;
        let (inv_r, inv_dx, inv_eta) = (1.0 / r, 1.0 / dx, 1.0 / eta);
        let (sines, cosines) = &*LANED;
        let mut out = [[0.0; LANES]; 4];
        for i in 0..LANES {
            let (s, c) = (sines[i], cosines[i]);
            // The ray from x meeting the ball at incidence θ, and where.
            let sin_a = r * s * inv_dx;
            let cos_a = (1.0 - sin_a * sin_a).sqrt();
            let t = dx * cos_a - r * c;
            let (ex, ey) = (dx - cos_a * t, sin_a * t);
            let (nx, ny) = (ex * inv_r, ey * inv_r);
            // Refracted in (Snell), and across the first chord.
            let cos_t = (1.0 - s * s * inv_eta * inv_eta).sqrt();
            let k = c * inv_eta - cos_t;
            let (ux, uy) = (-cos_a * inv_eta + nx * k, sin_a * inv_eta + ny * k);
            let m = -2.0 * (ex * ux + ey * uy);
            let (px, py) = (ex + ux * m, ey + uy * m);
            let (qx, qy) = (px * inv_r, py * inv_r);
            // Out there.
            let k_out = c - eta * cos_t;
            let (ox, oy) = (ux * eta + qx * k_out, uy * eta + qy * k_out);
            let (tx, ty) = (y.0 - px, y.1 - py);
            out[0][i] = ox * ty - oy * tx;
            out[1][i] = ox * tx + oy * ty;
            // Or reflected there, across a second chord and out.
            let f = -2.0 * (ux * qx + uy * qy);
            let (vx, vy) = (ux + qx * f, uy + qy * f);
            let m2 = -2.0 * (px * vx + py * vy);
            let (p2x, p2y) = (px + vx * m2, py + vy * m2);
            let (q2x, q2y) = (p2x * inv_r, p2y * inv_r);
            let (o2x, o2y) = (vx * eta + q2x * k_out, vy * eta + q2y * k_out);
            let (t2x, t2y) = (y.0 - p2x, y.1 - p2y);
            out[2][i] = o2x * t2y - o2y * t2x;
            out[3][i] = o2x * t2x + o2y * t2y;
        }
        out
    }
}

impl Kernel for Setting {
    type Output = [[f64; LANES]; 4];
    fn scalar(self) -> Self::Output {
        self.lanes()
    }
    #[inline(always)]
    fn wide<W: Wide>(self, _: W) -> Self::Output {
        self.lanes()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::splitmix::SplitMix;

    /// Every level the CPU has gives the same bits, the scalar's.
    #[test]
    fn every_level_sweeps_the_same_bits() {
        let mut rng = SplitMix(9);
        for _ in 0..200 {
            let setting = Setting {
                dx: 0.3 + 3.0 * rng.next_f32() as f64,
                y: (
                    4.0 * rng.next_f32() as f64 - 2.0,
                    2.0 * rng.next_f32() as f64,
                ),
                r: 0.25,
                eta: 1.2 + 0.6 * rng.next_f32() as f64,
            };
            let scalar = setting.lanes();
            for level in Level::available() {
                let got = level.run(setting);
                assert_eq!(
                    got.map(|k| k.map(f64::to_bits)),
                    scalar.map(|k| k.map(f64::to_bits)),
                    "{level}"
                );
            }
        }
    }
}
