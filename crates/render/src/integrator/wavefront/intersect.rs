//! Stage: the closest hit of every path's ray.

use super::lanes::Lane;
use crate::accel::Aggregate;

/// Intersects every lane's ray; returns the rays traced.
pub fn intersect<const K: usize>(geometry: &Aggregate, lanes: &mut [Lane<K>]) -> u64 {
    for lane in lanes.iter_mut() {
        lane.hit = geometry.intersect(&lane.path.ray);
    }
    lanes.len() as u64
}
