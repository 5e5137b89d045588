//! Stage: new camera samples (sampler, filter, wavelength cluster, camera
//! ray) for the work items of a row.

use super::super::Renderer;
use super::lanes::Lane;
use crate::sampling::sobol::Sampler;

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
}

/// The lane that starts work item `item`.
pub fn start<const K: usize>(r: &Renderer, work: &RowWork, item: usize) -> Lane<K> {
    let count = work.count as usize;
    let (x, j) = ((item / count) as u32, (item % count) as u32);
    let mut sampler = Sampler::new(work.seed);
    let path = r.start_path::<K>(&mut sampler, [x, work.y], work.first + j);
    Lane {
        path,
        sampler,
        slot: item as u32,
        hit: None,
        shadow: None,
        alive: true,
    }
}
