//! Stage: new camera samples (sampler, filter, wavelength cluster, camera
//! ray) in the lanes that retired paths left free, their first two sets
//! of random numbers drawn for all of them at once.

use super::super::Renderer;
use super::lanes::{Lane, Scratch, BATCH};
use crate::sampling::sobol::Sampler;
use crate::sampling::sobol_batch::pixel_keys;
use crate::simd::Level;

/// The work of a row: `count` samples from `first` of each of `width`
/// pixels; item `x · count + j` is sample `first + j` of pixel x.
#[derive(Clone, Copy)]
pub struct RowWork {
    pub seed: u32,
    pub y: u32,
    pub width: u32,
    pub first: u32,
    pub count: u32,
}

impl RowWork {
    pub fn items(&self) -> usize {
        self.width as usize * self.count as usize
    }

    /// Pixel x and sample index of work item `item`.
    fn item(&self, item: usize) -> (u32, u32) {
        let count = self.count as usize;
        ((item / count) as u32, self.first + (item % count) as u32)
    }
}

/// Starts the row's next work items (from `*next`) in the lanes listed in
/// `free` and in new lanes up to [`BATCH`]; free lanes left when the row
/// has no more work are removed. Returns the rays their light subpaths
/// traced (`manifold::seen`).
pub fn refill<const K: usize>(
    r: &Renderer,
    work: &RowWork,
    level: Level,
    lanes: &mut Vec<Lane<K>>,
    free: &mut Vec<usize>,
    next: &mut usize,
    scratch: &mut Scratch,
) -> u64 {
    let mut rays = 0;
    let room = free.len() + (BATCH - lanes.len());
    let n = room.min(work.items() - *next);
    scratch.resize(n);
    for k in 0..n {
        let (x, index) = work.item(*next + k);
        scratch.xs[k] = x;
        scratch.ys[k] = work.y;
        scratch.indices[k] = index;
    }
    let (xs, ys) = (&scratch.xs[..n], &scratch.ys[..n]);
    pixel_keys(level, work.seed, xs, ys, &mut scratch.keys[..n]);
    scratch.draw_sets(level, 0, n);
    free.sort_unstable_by(|a, b| b.cmp(a));
    for k in 0..n {
        let sampler = Sampler::resume(work.seed, scratch.keys[k], scratch.indices[k], 2);
        let mut path = r.start_path_with::<K>([scratch.xs[k], work.y], scratch.sets_of(k));
        // The path's own stream, as the scalar tracer's (`start_path`).
        path.rng = sampler.stream();
        rays += r.draw_caustic(&mut path) as u64;
        let lane = Lane {
            path,
            sampler,
            slot: (*next + k) as u32,
            hit: None,
            u: [[0.0; 4]; 2],
            shadow: None,
            alive: true,
        };
        match free.pop() {
            Some(i) => lanes[i] = lane,
            None => lanes.push(lane),
        }
    }
    *next += n;
    // Free lanes past the work (still highest first: `pop` took the
    // lowest), so each removal moves a live lane (or none) into the hole.
    for i in free.drain(..) {
        lanes.swap_remove(i);
    }
    rays
}
