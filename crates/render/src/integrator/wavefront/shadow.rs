//! Stage: the shadow rays of next-event estimation; an unoccluded one adds
//! its contribution to its path.

use super::lanes::Lane;
use crate::accel::Aggregate;

/// Traces every pending shadow ray; returns the rays traced.
pub fn shadow<const K: usize>(geometry: &Aggregate, lanes: &mut [Lane<K>]) -> u64 {
    let mut rays = 0;
    for lane in lanes.iter_mut() {
        if let Some((ray, contribution)) = lane.shadow.take() {
            rays += 1;
            if !geometry.occluded(&ray) {
                lane.path.l += contribution;
            }
        }
    }
    rays
}
