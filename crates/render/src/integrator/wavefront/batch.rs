//! A row's camera samples traced in batches of paths, stage by stage.

use scotopia_color::SampledSpectrum;

use super::super::path::{CameraSample, PathState};
use super::super::Renderer;
use crate::geometry::Hit;
use crate::math::Ray;
use crate::sampling::sobol::Sampler;

/// Paths in flight per batch: enough that each stage's loop amortises its
/// set-up, few enough that the batch (about 250 bytes a path at K = 4)
/// stays in the L2 cache.
pub const BATCH: usize = 1024;

/// One path in flight with what the stages pass between them.
struct Lane<const K: usize> {
    path: PathState<K>,
    sampler: Sampler,
    /// Where its estimate goes in the row's results.
    slot: u32,
    /// The intersect stage's result.
    hit: Option<Hit>,
    /// The shade stage's shadow ray and what it carries if unoccluded.
    shadow: Option<(Ray, SampledSpectrum<K>)>,
    alive: bool,
}

/// The estimates of samples `first..first + count` of every pixel of row
/// `y` (`width` pixels): entry `x · count + j` is sample `first + j` of
/// pixel x (`None`: not finite). Adds the rays traced to `rays`.
pub fn trace_row<const K: usize>(
    r: &Renderer,
    seed: u32,
    y: u32,
    width: u32,
    (first, count): (u32, u32),
    rays: &mut u64,
) -> Vec<Option<CameraSample<K>>> {
    let total = width as usize * count as usize;
    let mut results: Vec<Option<CameraSample<K>>> = (0..total).map(|_| None).collect();
    let start = |item: usize| {
        let (x, j) = (
            (item / count as usize) as u32,
            (item % count as usize) as u32,
        );
        let mut sampler = Sampler::new(seed);
        let path = r.start_path::<K>(&mut sampler, [x, y], first + j);
        Lane {
            path,
            sampler,
            slot: item as u32,
            hit: None,
            shadow: None,
            alive: true,
        }
    };
    let mut lanes: Vec<Lane<K>> = (0..total.min(BATCH)).map(start).collect();
    let mut next = lanes.len();
    let mut order = Vec::with_capacity(BATCH);
    let mut by_material = MaterialOrder::new(r.scene.materials.len());
    let geometry = &r.scene.geometry;
    while !lanes.is_empty() {
        // Intersect.
        for lane in lanes.iter_mut() {
            lane.hit = geometry.intersect(&lane.path.ray);
        }
        *rays += lanes.len() as u64;
        // Shade, grouped by material (escaped paths first).
        by_material.order(&lanes, r, &mut order);
        for &i in &order {
            let lane = &mut lanes[i as usize];
            match &lane.hit {
                None => {
                    r.escape(&mut lane.path);
                    lane.alive = false;
                }
                Some(hit) => {
                    let b = r.bounce(&mut lane.path, &mut lane.sampler, hit);
                    lane.shadow = b.shadow;
                    lane.alive = b.goes_on;
                }
            }
        }
        // Shadow rays.
        for lane in lanes.iter_mut() {
            if let Some((ray, contribution)) = lane.shadow.take() {
                *rays += 1;
                if !geometry.occluded(&ray) {
                    lane.path.l += contribution;
                }
            }
        }
        // Retire finished paths; new camera samples take their slots.
        let mut i = 0;
        while i < lanes.len() {
            if lanes[i].alive {
                i += 1;
                continue;
            }
            results[lanes[i].slot as usize] = Renderer::finish(&lanes[i].path);
            if next < total {
                lanes[i] = start(next);
                next += 1;
                i += 1;
            } else {
                lanes.swap_remove(i);
            }
        }
    }
    results
}

/// A counting sort of the lanes by the material they hit.
struct MaterialOrder {
    counts: Vec<u32>,
}

impl MaterialOrder {
    fn new(materials: usize) -> Self {
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
