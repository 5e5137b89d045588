//! Stage: finished paths give their estimates; new camera samples take
//! their slots while the row has work, so the batch stays full.

use super::super::path::CameraSample;
use super::super::Renderer;
use super::generate::{start, RowWork};
use super::lanes::Lane;

/// Retires the lanes that are done; `next` is the row's next work item.
pub fn retire<const K: usize>(
    r: &Renderer,
    work: &RowWork,
    lanes: &mut Vec<Lane<K>>,
    next: &mut usize,
    results: &mut [Option<CameraSample<K>>],
) {
    let mut i = 0;
    while i < lanes.len() {
        if lanes[i].alive {
            i += 1;
            continue;
        }
        results[lanes[i].slot as usize] = Renderer::finish(&lanes[i].path);
        if *next < work.items() {
            lanes[i] = start(r, work, *next);
            *next += 1;
            i += 1;
        } else {
            lanes.swap_remove(i);
        }
    }
}
