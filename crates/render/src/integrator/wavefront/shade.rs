//! Stage: what every path does where its ray ended — lights at infinity
//! for escaped paths; emission, next-event estimation (a shadow ray left
//! for the next stage) and the next direction for hits. Lanes are taken
//! grouped by material, so one BSDF's code runs over consecutive paths.

use super::super::Renderer;
use super::lanes::{Lane, Scratch};
use crate::simd::Level;

/// Draws the next two sets of every lane that hit something, for all of
/// them at once: lanes at the same set (the same depth, mostly) share one
/// batched draw, bit-identical to their own samplers.
fn draw_numbers<const K: usize>(level: Level, lanes: &mut [Lane<K>], scratch: &mut Scratch) {
    let mut group = std::mem::take(&mut scratch.lanes);
    group.clear();
    group.extend((0..lanes.len() as u32).filter(|&i| lanes[i as usize].hit.is_some()));
    group.sort_unstable_by_key(|&i| (lanes[i as usize].sampler.next_set(), i));
    let mut start = 0;
    while start < group.len() {
        let set = lanes[group[start] as usize].sampler.next_set();
        let n = group[start..]
            .iter()
            .take_while(|&&i| lanes[i as usize].sampler.next_set() == set)
            .count();
        let members = &group[start..start + n];
        scratch.resize(n);
        for (k, &i) in members.iter().enumerate() {
            let s = &lanes[i as usize].sampler;
            scratch.keys[k] = s.pixel_key();
            scratch.indices[k] = s.index();
        }
        scratch.draw_sets(level, set, n);
        for (k, &i) in members.iter().enumerate() {
            let lane = &mut lanes[i as usize];
            lane.u = scratch.sets_of(k);
            lane.sampler.skip_sets(2);
        }
        start += n;
    }
    scratch.lanes = group;
}

/// Shades every lane, in the order `order` fills in; returns the rays
/// the bounces traced themselves.
pub fn shade<const K: usize>(
    r: &Renderer,
    level: Level,
    lanes: &mut [Lane<K>],
    by_material: &mut MaterialOrder,
    order: &mut Vec<u32>,
    scratch: &mut Scratch,
) -> u64 {
    let mut traced = 0;
    draw_numbers(level, lanes, scratch);
    by_material.order(lanes, r, order);
    for &i in order.iter() {
        let lane = &mut lanes[i as usize];
        match &lane.hit {
            None => {
                r.escape(&mut lane.path);
                lane.alive = false;
            }
            Some(hit) => {
                let b = r.bounce::<K, false>(&mut lane.path, lane.u, hit);
                traced += b.traced as u64;
                lane.shadow = b.shadow;
                lane.alive = b.goes_on;
            }
        }
    }
    traced
}

/// A counting sort of the lanes by the material they hit.
pub struct MaterialOrder {
    counts: Vec<u32>,
}

impl MaterialOrder {
    pub fn new(materials: usize) -> Self {
        Self {
            counts: vec![0; materials + 2],
        }
    }

    /// Lane indices into `order`: escaped paths, then by material.
    fn order<const K: usize>(&mut self, lanes: &[Lane<K>], r: &Renderer, order: &mut Vec<u32>) {
        let key = |lane: &Lane<K>| match &lane.hit {
            None => 0,
            Some(h) => 1 + r.scene.shape_material[h.shape as usize] as usize,
        };
        self.counts.iter_mut().for_each(|c| *c = 0);
        for lane in lanes {
            self.counts[key(lane) + 1] += 1;
        }
        for k in 1..self.counts.len() {
            self.counts[k] += self.counts[k - 1];
        }
        order.clear();
        order.resize(lanes.len(), 0);
        for (i, lane) in lanes.iter().enumerate() {
            let at = &mut self.counts[key(lane)];
            order[*at as usize] = i as u32;
            *at += 1;
        }
    }
}
