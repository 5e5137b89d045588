//! The grid of a ball's search (`ball.rs`) for the paths through it,
//! straight and with up to three reflections inside, traced together:
//! each shares the ray from `x`, its refraction in and its chords with
//! the kinds before it. The grid's angles are traced as lanes of plain
//! loops over arrays, compiled for the widest level the CPU has
//! (`simd::Level`), where the compiler turns them into vector
//! instructions: four angles per instruction at AVX2.
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

/// How many kinds through the ball the grid traces: straight through and
/// with one, two and three reflections inside.
pub const THROUGH: usize = 4;

/// At each grid angle (`GRID`'s order), for paths through the ball with
/// `k` reflections inside (`[k]`): g, the signed distance of `y` from the
/// last ray, and whether `y` lies ahead on it.
pub struct Swept {
    pub g: [[f64; LANES]; THROUGH],
    pub ahead: [[bool; LANES]; THROUGH],
}

impl Setting {
    /// Every kind's g at every grid angle.
    pub fn sweep(self) -> Swept {
        let [g, along] = Level::current().run(self);
        Swept {
            g,
            ahead: along.map(|a| a.map(|v| v > 0.0)),
        }
    }

    /// g and the last ray's length along towards `y`, per kind and lane:
    /// the same steps as `Plane::trace`, written lane by lane.
    #[inline(always)]
    fn lanes(self) -> [[[f64; LANES]; THROUGH]; 2] {
        let Setting { dx, y, r, eta } = self;
        let (inv_r, inv_dx, inv_eta) = (1.0 / r, 1.0 / dx, 1.0 / eta);
        let (sines, cosines) = &*LANED;
        // Each lane's point on the ball, direction inside, and the
        // factor Snell's law out needs.
        let [mut px, mut py, mut ux, mut uy, mut k_out] = [[0.0; LANES]; 5];
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
            (ux[i], uy[i]) = (-cos_a * inv_eta + nx * k, sin_a * inv_eta + ny * k);
            let m = -2.0 * (ex * ux[i] + ey * uy[i]);
            (px[i], py[i]) = (ex + ux[i] * m, ey + uy[i] * m);
            k_out[i] = c - eta * cos_t;
        }
        let [mut g, mut along] = [[[0.0; LANES]; THROUGH]; 2];
        for (g, along) in g.iter_mut().zip(&mut along) {
            for i in 0..LANES {
                let (qx, qy) = (px[i] * inv_r, py[i] * inv_r);
                // Out here,
                let (ox, oy) = (ux[i] * eta + qx * k_out[i], uy[i] * eta + qy * k_out[i]);
                let (tx, ty) = (y.0 - px[i], y.1 - py[i]);
                g[i] = ox * ty - oy * tx;
                along[i] = ox * tx + oy * ty;
                // or reflected here, across the next chord.
                let f = -2.0 * (ux[i] * qx + uy[i] * qy);
                (ux[i], uy[i]) = (ux[i] + qx * f, uy[i] + qy * f);
                let m = -2.0 * (px[i] * ux[i] + py[i] * uy[i]);
                (px[i], py[i]) = (px[i] + ux[i] * m, py[i] + uy[i] * m);
            }
        }
        [g, along]
    }
}

impl Kernel for Setting {
    type Output = [[[f64; LANES]; THROUGH]; 2];
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
                    got.map(|a| a.map(|k| k.map(f64::to_bits))),
                    scalar.map(|a| a.map(|k| k.map(f64::to_bits))),
                    "{level}"
                );
            }
        }
    }
}
