//! Stage: finished paths give their estimates and free their lanes.

use super::super::path::CameraSample;
use super::super::Renderer;
use super::lanes::Lane;

/// Writes the estimates of the lanes that are done into `results` and
/// lists those lanes in `free`.
pub fn retire<const K: usize>(
    lanes: &[Lane<K>],
    free: &mut Vec<usize>,
    results: &mut [Option<CameraSample<K>>],
) {
    free.clear();
    for (i, lane) in lanes.iter().enumerate() {
        if !lane.alive {
            results[lane.slot as usize] = Renderer::finish(&lane.path);
            free.push(i);
        }
    }
}
