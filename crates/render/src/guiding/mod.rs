//! Path guiding: the light arriving at each part of the scene, learned
//! while the render runs, to draw bounce directions from (Müller, Gross &
//! Novák 2017, "Practical Path Guiding for Efficient Light-Transport
//! Simulation"). A binary tree over space ([`SpatialTree`]) holds in each
//! cell a quadtree over directions ([`DTree`]) whose energy is the
//! radiance that paths found arriving there from each direction.
//!
//! **Learning in iterations, in the image.** With guiding on, a
//! render's first [`LEARNED`] samples per pixel are cut into iterations
//! at [`BOUNDARIES`] (1, 1, 2, 4 and 8 spp; `integrator/learn.rs`).
//! Samples of iteration k draw from the field that iterations before k
//! learned and record, at every vertex that sampled a direction, the
//! radiance the path then found along it over that direction's density
//! (an unbiased estimate of each quadrant's ∫L dω). At the end of an
//! iteration the records become the next field: each cell's quadtree
//! takes the recorded energy, cells that received many records are
//! halved, and each quadtree's topology is refined where its energy is.
//! Every later sample draws from the last field. The image keeps the
//! learning samples: each drew from a field learned without it, so each
//! is an unbiased estimate. Müller et al. 2017 keep only the last
//! iteration's image, because the first guides are poor; here iteration
//! k's samples weigh 2^(k − 4) in the film instead, within a fixed
//! budget for all of them ([`BUDGET`]), so that the first, barely guided
//! samples add little noise. Before the first of them a probe, 2 spp
//! of another seed over every [`probe_step`]-th row, learns a field apart
//! from the image; where it is not worth its cost ([`Field::worth`],
//! [`STOP`]: the Cornell box) the guide declines, and the image is the
//! unguided one. Where the image's own field is not worth its cost after
//! two iterations, learning and guiding stop, and the rest of the
//! learning samples weigh 1.
//!
//! **Deterministic.** A field depends only on the records of the samples
//! before its boundary, and those only on (seed, sample index, pixel).
//! Each row's records are summed in sample order and the rows' sums added
//! in row order, so the field, and the image, are the same on any number
//! of threads. An iteration is always learned from one pass over every
//! row; a render resumed from a checkpoint, or a shard, learns the
//! iterations it does not render whole in a scratch film (the same
//! samples again), so it uses the very field the uninterrupted render
//! used.
//!
//! The integrators draw from a field in a one-sample mixture with the
//! BSDF or phase function and weigh by the mixture's density (MIS, Veach
//! 1997 §9.2.2), so the estimate stays unbiased whatever the field holds.

mod dtree;
mod spatial;
#[cfg(test)]
mod tests;

pub use dtree::{from_square, to_square, DTree};
pub use spatial::SpatialTree;

use crate::math::Vec3;

/// The sample counts at which an iteration ends and a new field is
/// learned: iterations of 1, 1, 2, 4 and 8 spp (Müller et al. 2017:
/// each iteration twice the samples of the one before).
pub const BOUNDARIES: [u32; 6] = [0, 1, 2, 4, 8, 16];

/// Samples per pixel the guide learns from.
pub const LEARNED: u32 = 16;

/// A cell is halved when an iteration of n spp recorded more than c·√n
/// vertices in it (Müller et al. 2017, the spatial tree: c·√(2^k) for iteration k of
/// 2^k spp, c = 12 000).
pub const SPLIT: f64 = 12_000.0;

/// Most halvings of one cell after one iteration.
const MAX_HALVINGS: u32 = 12;

/// Records that found light a cell's density must have learned from
/// before it guides: a handful of lucky paths would otherwise send half
/// of every bounce in the cell where those few found light.
pub const MIN_LIT: u64 = 32;

/// The least peak density (per steradian) a cell's density must reach
/// to guide: 4× the peak of cosine sampling (1/π). Flatter light (the
/// Cornell box's walls) is sampled about as well by the BSDF, and guiding
/// it costs time for nothing.
pub const MIN_PEAK: f32 = 4.0 / std::f32::consts::PI;

/// The largest predicted gain ([`DTree::gain`]: the bounce's variance
/// with guiding over without) at which a surface's cell guides. A guided
/// vertex costs two quadtree walks more (the Cornell box's guided
/// sample cost 1.6× an unguided one when every cell with a peak above
/// [`MIN_PEAK`] guided), its bounce is only part of a pixel's variance,
/// and a gain learned from a few hundred records is noisy, so a cell
/// guides only where it is predicted to quarter it. Measured at 320×180
/// after 16 spp: the Cornell box's surface cells predict 0.2–0.5 where
/// their indirect light is most peaked, and letting those up to 0.5
/// guide bought nothing at equal time (relMSE of Y 0.98× as good at 6 %
/// fewer samples per second); the hidden lamp's floor predicts 0.06, the
/// night street's most peaked cells 0.0–0.23.
pub const MAX_GAIN: f32 = 0.25;

/// The predicted gain above which a surface's cell doubts it will guide:
/// a density that would not lower its bounce's variance at all (uniform
/// light predicts 1.40). After [`DOUBTS`] such iterations in a row it
/// stops recording — keeping what it learned, guiding nowhere — since
/// each record costs its vertex a walk down both trees (on the Cornell
/// box, 16 spp of learning cost 0.35 s of a 10 s render). Not after one:
/// a first quadtree of four quadrants predicts no gain even for a narrow
/// beam, which the tree refined where the energy is then resolves.
pub const GIVE_UP: f32 = 0.5;

/// Iterations in a row predicting more than [`GIVE_UP`] after which a
/// cell stops learning.
pub const DOUBTS: u8 = 2;

/// Share of guided directions at a guided vertex: the other half comes
/// from the BSDF or phase function (Müller et al. 2017: a fixed 50 %).
pub const SHARE: f32 = 0.5;

/// The end of the iteration `done` samples lie in, while learning goes on.
pub fn next_boundary(done: u32) -> Option<u32> {
    BOUNDARIES.iter().copied().find(|&b| b > done)
}

/// The sides a cell keeps a density for: surfaces facing +x, −x, +y, −y,
/// +z, −z (by their normal's largest component, on the side the path
/// is), and points in media. A surface's vertices see light from the
/// hemisphere it faces alone; a density shared by a cell's floor and wall
/// would send half its samples into each (a rule of ours, after the
/// normal-aware guiding of later work: Müller et al. 2017 keep one
/// density per cell).
pub const SIDES: usize = 7;

/// The side (of [`SIDES`]) of a vertex whose normal, turned to the side
/// the path is on, is `n`; `None` in a medium.
pub fn side(n: Option<Vec3>) -> usize {
    let Some(n) = n else {
        return SIDES - 1;
    };
    let a = n.abs();
    let axis = if a.x >= a.y && a.x >= a.z {
        0
    } else if a.y >= a.z {
        1
    } else {
        2
    };
    2 * axis + usize::from(n.to_array()[axis] < 0.0)
}

/// One cell's density for one side: the density it guides with and the
/// topology it records in.
#[derive(Debug, Clone, PartialEq)]
struct Cell {
    /// What the iterations before learned (no energy: not guided yet).
    sampling: DTree,
    /// Whether `sampling` learned from [`MIN_LIT`] records or more that
    /// found light.
    guides: bool,
    /// Iterations in a row that predicted no gain ([`GIVE_UP`]); it
    /// records while fewer than [`DOUBTS`].
    doubts: u8,
    /// Where this iteration's records go.
    building: DTree,
    /// Its first slot among the field's.
    offset: u32,
    /// Records per spp in the last iteration it learned in: how often
    /// paths bounce here ([`Field::worth`]).
    rate: f32,
    /// The share of its bounces' variance guiding is predicted to remove:
    /// 1 − [`DTree::gain`] (within 0..1), 1 in media and at lamps.
    removes: f32,
}

impl Cell {
    /// Whether it still records.
    fn learns(&self) -> bool {
        self.doubts < DOUBTS
    }
}

/// What a cell learned in an iteration: the density it samples with,
/// whether it guides, its records (and those that found light), and its
/// doubts ([`GIVE_UP`]).
#[derive(Clone)]
struct Learned {
    sampling: DTree,
    guides: bool,
    count: u64,
    lit: u64,
    doubts: u8,
    rate: f32,
    removes: f32,
}

/// The learned light field of one iteration.
#[derive(Debug, Clone, PartialEq)]
pub struct Field {
    tree: SpatialTree,
    cells: Vec<Cell>,
    slots: usize,
    /// For each side, the box around the cells that guide on it (`None`
    /// where none does): vertices outside it skip the lookup, which
    /// where few cells guide (the Cornell box) would otherwise cost every
    /// vertex a walk down the tree for nothing.
    guided: [Option<(Vec3, Vec3)>; SIDES],
    /// For each side, the box around the cells that still learn on it:
    /// vertices outside it make no record.
    learning: [Option<(Vec3, Vec3)>; SIDES],
    /// The share of all bounces' variance that the cells which guide or
    /// still learn are predicted to remove, each cell counted by how
    /// often paths bounce in it ([`Field::worth`]).
    worth: f32,
}

/// A cell of a field, found from a point.
#[derive(Debug, Clone, Copy)]
pub struct Spot<'a> {
    field: &'a Field,
    cell: u32,
}

impl Field {
    /// Nothing learned, one cell over the box `lo`..`hi`.
    pub fn new(lo: Vec3, hi: Vec3) -> Self {
        let building = DTree::default();
        let slots = building.slots();
        Self {
            tree: SpatialTree::new(lo, hi),
            guided: [None; SIDES],
            learning: [Some((lo, hi)); SIDES],
            slots: SIDES * slots,
            cells: (0..SIDES)
                .map(|s| Cell {
                    sampling: DTree::default(),
                    guides: false,
                    doubts: 0,
                    building: building.clone(),
                    offset: (s * slots) as u32,
                    rate: 0.0,
                    removes: 0.0,
                })
                .collect(),
            worth: 1.0,
        }
    }

    /// The density at `p` for a vertex on side `side` ([`side`]).
    #[inline]
    pub fn at(&self, p: Vec3, side: usize) -> Spot<'_> {
        Spot {
            field: self,
            cell: self.tree.cell(p) * SIDES as u32 + side.min(SIDES - 1) as u32,
        }
    }

    /// The density for side `side` at a point jittered from `p` by
    /// (`u` − ½)/2 times the size of `p`'s cell, kept inside the field's
    /// box.
    pub fn jittered(&self, p: Vec3, side: usize, u: [f32; 3]) -> Spot<'_> {
        let size = self.tree.size_at(p);
        let q = p + size.mul_elem(Vec3::new(u[0] - 0.5, u[1] - 0.5, u[2] - 0.5)) * 0.5;
        self.at(self.tree.clamp(q), side)
    }

    /// Whether any cell guides.
    #[inline]
    pub fn guides(&self) -> bool {
        self.guided.iter().any(Option::is_some)
    }

    /// Whether a cell that guides on side `side` may hold `p`.
    #[inline]
    pub fn may_guide(&self, p: Vec3, side: usize) -> bool {
        within(self.guided[side.min(SIDES - 1)], p)
    }

    /// Whether a cell that still learns on side `side` may hold `p`
    /// (kept inside the field's box, as its record would be).
    #[inline]
    pub fn may_learn(&self, p: Vec3, side: usize) -> bool {
        within(self.learning[side.min(SIDES - 1)], self.tree.clamp(p))
    }

    /// The share of the variance of all the bounces paths made in the
    /// last iteration that the cells which guide or still learn are
    /// predicted to remove: Σ rate·(1 − gain) over those cells, over
    /// Σ rate over all, a cell's rate being its records per spp when it
    /// last learned; cells in media and at lamps, for which no gain is
    /// predicted, and cells whose light is too rare yet to predict from
    /// ([`MIN_LIT`]) count as removing all of it, cells that never found
    /// light as removing nothing. 1 before anything is
    /// learned. Where it is small (the Cornell box's 0.02), guiding cannot
    /// pay for its lookups and records ([`Guide::advance`] stops it).
    pub fn worth(&self) -> f32 {
        self.worth
    }

    /// Slots of statistics an iteration records into.
    pub fn slots(&self) -> usize {
        self.slots
    }

    /// Cells and their quadtrees' leaves, for reports.
    pub fn size(&self) -> (usize, usize) {
        let leaves = self.cells.iter().map(|c| c.sampling.leaves()).sum();
        (self.cells.len() / SIDES, leaves)
    }

    /// The field learned from `stats`, recorded into this one's slots by
    /// an iteration of `spp` samples per pixel.
    pub fn next(&self, stats: &Stats, spp: u32) -> Self {
        let threshold = SPLIT * f64::from(spp.max(1)).sqrt();
        let learned: Vec<Learned> = self
            .cells
            .iter()
            .enumerate()
            .map(|(i, c)| {
                // A cell that gave up keeps what it knew, whatever a
                // jittered neighbour's record brought it.
                let kept = |count, lit| Learned {
                    sampling: c.sampling.clone(),
                    guides: c.guides,
                    count,
                    lit,
                    doubts: c.doubts,
                    rate: c.rate,
                    removes: c.removes,
                };
                if !c.learns() {
                    return kept(0, 0);
                }
                let range = c.offset as usize..c.offset as usize + c.building.slots();
                let count: u64 = stats.count[range.clone()].iter().sum();
                let rate = count as f32 / spp.max(1) as f32;
                let lit: u64 = stats.lit[range.clone()].iter().sum();
                let tree = c.building.with_energy(
                    &stats.energy[range.clone()],
                    &stats.square[range.clone()],
                    &stats.lit[range],
                );
                // A cell that found too little light keeps what it knew.
                if tree.energy() > 0.0 && lit >= MIN_LIT {
                    // Surfaces guide where guiding is predicted to pay;
                    // media where their light is peaked.
                    let gain = tree.gain(i % SIDES);
                    let (guides, doubts) = match gain {
                        Some(gain) if gain > GIVE_UP => (false, c.doubts + 1),
                        Some(gain) => (gain <= MAX_GAIN, 0),
                        None => (tree.peak() >= MIN_PEAK, 0),
                    };
                    Learned {
                        sampling: tree,
                        guides,
                        count,
                        lit,
                        doubts,
                        rate,
                        removes: gain.map_or(1.0, |g| (1.0 - g).clamp(0.0, 1.0)),
                    }
                } else if c.guides || tree.energy() <= 0.0 {
                    Learned {
                        rate,
                        ..kept(count, lit)
                    }
                } else {
                    // Not enough to guide by, but enough to refine where
                    // the next iteration records. Light found too rarely
                    // to predict from (the hidden lamp's floor after 2
                    // spp, a small image's cells) may be what guiding is
                    // for: counted as worth all.
                    Learned {
                        sampling: tree,
                        guides: false,
                        rate,
                        removes: 1.0,
                        ..kept(count, lit)
                    }
                }
            })
            .collect();
        // Halved while the records are many, but not so far that the next
        // iteration (twice as long) leaves a half with fewer than
        // [`MIN_LIT`] records that found light.
        let halvings = |cell: u32| {
            let sides = &learned[cell as usize * SIDES..(cell as usize + 1) * SIDES];
            let count: u64 = sides.iter().map(|l| l.count).sum();
            let lit: u64 = sides.iter().map(|l| l.lit).sum();
            let (mut n, mut lit) = (count as f64, lit as f64);
            let mut k = 0;
            while n > threshold && lit >= MIN_LIT as f64 && k < MAX_HALVINGS {
                n *= 0.5;
                lit *= 0.5;
                k += 1;
            }
            k
        };
        let (tree, origin) = self.tree.split(halvings);
        // A halved cell's bounces are shared among its parts.
        let mut parts = vec![0u32; self.cells.len() / SIDES];
        for &old in &origin {
            parts[old as usize] += 1;
        }
        let mut offset = 0;
        let cells = origin
            .iter()
            .flat_map(|&old| (0..SIDES).map(move |s| old as usize * SIDES + s))
            .map(|old| {
                let Learned {
                    sampling,
                    guides,
                    doubts,
                    rate,
                    removes,
                    ..
                } = learned[old].clone();
                let building = if sampling.energy() > 0.0 {
                    sampling.refined()
                } else {
                    self.cells[old].building.clone()
                };
                let cell = Cell {
                    offset,
                    sampling,
                    guides,
                    doubts,
                    building,
                    rate: rate / parts[old / SIDES].max(1) as f32,
                    removes,
                };
                offset += cell.building.slots() as u32;
                cell
            })
            .collect::<Vec<Cell>>();
        let boxes = tree.boxes();
        let around = |keep: fn(&Cell) -> bool| {
            let mut sides = [None; SIDES];
            for (i, _) in cells.iter().enumerate().filter(|(_, c)| keep(c)) {
                let (lo, hi) = boxes[i / SIDES];
                let b: &mut Option<(Vec3, Vec3)> = &mut sides[i % SIDES];
                *b = Some(b.map_or((lo, hi), |(l, h)| (l.min(lo), h.max(hi))));
            }
            sides
        };
        let (guided, learning) = (around(|c| c.guides), around(Cell::learns));
        let all: f64 = cells.iter().map(|c| f64::from(c.rate)).sum();
        let removed: f64 = cells
            .iter()
            .filter(|c| c.guides || c.learns())
            .map(|c| f64::from(c.rate * c.removes))
            .sum();
        Self {
            tree,
            guided,
            learning,
            cells,
            slots: offset as usize,
            worth: if all > 0.0 {
                (removed / all) as f32
            } else {
                0.0
            },
        }
    }
}

/// Whether `p` lies in the box `b`.
#[inline]
fn within(b: Option<(Vec3, Vec3)>, p: Vec3) -> bool {
    b.is_some_and(|(lo, hi)| p.max(lo) == p && p.min(hi) == p)
}

impl<'a> Spot<'a> {
    /// The density this cell guides with; `None` before it learned any
    /// light (the integrator then samples as it would unguided).
    #[inline]
    pub fn guide(&self) -> Option<&'a DTree> {
        let c = &self.field.cells[self.cell as usize];
        c.guides.then_some(&c.sampling)
    }

    /// The slot a record of direction `d` (unit, world) goes to.
    #[inline]
    pub fn slot(&self, d: Vec3) -> u32 {
        let c = &self.field.cells[self.cell as usize];
        c.offset + c.building.slot(d)
    }
}

/// What an iteration recorded: per slot, the energy, the number of
/// records and of those that found light.
#[derive(Debug, Clone, Default)]
pub struct Stats {
    energy: Vec<f64>,
    /// Σ e² per slot: what the energy's square owes to the records'
    /// noise ([`DTree::gain`]).
    square: Vec<f64>,
    count: Vec<u64>,
    lit: Vec<u64>,
}

impl Stats {
    /// Empty statistics for `field`.
    pub fn new(field: &Field) -> Self {
        Self {
            energy: vec![0.0; field.slots()],
            square: vec![0.0; field.slots()],
            count: vec![0; field.slots()],
            lit: vec![0; field.slots()],
        }
    }

    /// Adds one row's records (rows must come in the same order on every
    /// run for the sums to be the same).
    pub fn add(&mut self, row: &RowStats) {
        for &(slot, e, e2, n, lit) in &row.0 {
            if let Some(s) = self.energy.get_mut(slot as usize) {
                *s += e;
                self.square[slot as usize] += e2;
                self.count[slot as usize] += u64::from(n);
                self.lit[slot as usize] += u64::from(lit);
            }
        }
    }
}

/// One row's records summed per slot, in the order the row made them.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RowStats(Vec<(u32, f64, f64, u32, u32)>);

impl RowStats {
    /// Sums `records` (slot, energy) per slot, and their squares; a
    /// stable sort keeps each slot's records in the order they were made.
    pub fn of(mut records: Vec<(u32, f32)>) -> Self {
        records.sort_by_key(|r| r.0);
        let mut out: Vec<(u32, f64, f64, u32, u32)> = Vec::new();
        for (slot, e) in records {
            let lit = u32::from(e > 0.0);
            let e = f64::from(e);
            match out.last_mut() {
                Some(last) if last.0 == slot => {
                    last.1 += e;
                    last.2 += e * e;
                    last.3 += 1;
                    last.4 += lit;
                }
                _ => out.push((slot, e, e * e, 1, lit)),
            }
        }
        Self(out)
    }
}

/// The field learned so far, how many iterations learned it, and the
/// weights in the film of the learning iterations' samples.
#[derive(Debug, Clone, PartialEq)]
pub struct Guide {
    field: Field,
    learned: usize,
    /// The weight of a sample of each iteration decided so far: each is
    /// decided before its iteration's first sample ([`Guide::weight`]).
    weights: Vec<f32>,
    /// Whether learning and guiding stopped ([`STOP`]).
    stopped: bool,
}

/// The learning iterations' samples weigh, all together, as many as
/// `BUDGET` of the later samples: iteration k's samples weigh w_k each,
/// and Σ n_k·w_k = `BUDGET` over the [`LEARNED`] samples. A pixel is
/// (Σ n_k·w_k·Ī_k + n·Ī)/(BUDGET + n) after n more samples of mean Ī.
/// Each w_k is decided before iteration k from what the iterations
/// before it learned (and the last is what is left of the budget), so
/// E[w_k·Ī_k] = E[w_k]·μ, and with the sum of the weights fixed the
/// pixel's mean is unbiased whatever the weights: adaptive weights
/// normalised by their own sum would not be. 12 trades the two cases:
/// after guiding stopped ([`STOP`]) the last iteration's samples weigh
/// 0.73 and the 16 are worth 14.1 equal ones ((Σw)²/Σw²; 14.4 with a
/// budget of 14, 12.5 with the weights 2^(k − 4) alone), and where
/// guiding goes on they weigh 1.16, their field learned from half of the
/// learning samples (1.41 with 14, with which the prism rendered 0.83×
/// as well at 64 spp as with 12's 0.92×, ± 0.09 and ± 0.04: docs/guiding.md).
pub const BUDGET: f32 = 12.0;

/// The least [`Field::worth`] at which guiding goes on after [`DOUBTS`]
/// iterations: below it learning stops, nothing guides, and the
/// remaining learning iterations' samples weigh 1 (but the last, which
/// takes what is left of [`BUDGET`]). A field worth 5 % can lower the
/// variance by at most about that, while its records and lookups cost
/// about 3 % of a 128-spp render's time (the Cornell box). Measured
/// after 2 spp: the Cornell box 0.008–0.023 (160×90 to 640×360: two
/// cells guide, the surfaces gave up), the long street 0.08, the night
/// street and the glass scene 0.24, the foggy street and the material
/// showcase 0.5, the hidden lamp's floor of `crates/scene/tests/guiding.rs`
/// 0.64, and 1 where the bidirectional tracer guides its lamps' emission.
pub const STOP: f32 = 0.05;

/// The probe (`integrator/learn.rs`) learns from every
/// [`probe_step`]-th row of the film, at least this many pixels where the
/// film has them: from fewer, more of its cells find light too rarely to
/// predict from and count as worth all (the Cornell box at 160 × 90 from
/// every 4th row: 0.05–0.06, from every row 0.01–0.02).
pub const PROBE_PIXELS: u32 = 14_400;

/// Every how many rows of a `width` × `height` film the probe renders:
/// as many as keep [`PROBE_PIXELS`], at most 4, so that its 2 spp cost at
/// most half a sample per pixel of the image's time where the image is
/// large. Its field's worth, measured from every 4th row on the Cornell
/// box at 320 × 180 to 1920 × 1080: 0.002–0.040 (from every 8th row up
/// to 0.052, from every 16th up to 0.06); at 320 × 180, seeds 1–6, the
/// long street 0.07–0.12, the night street 0.09–0.20, the material
/// showcase 0.09–0.74, the glass scene 0.044–0.28 (one seed of six
/// declined), the foggy street 0.3–0.4, the bidirectional tracer's lamps 1.
pub fn probe_step(width: u32, height: u32) -> u32 {
    let pixels = u64::from(width) * u64::from(height);
    (pixels / u64::from(PROBE_PIXELS)).clamp(1, 4) as u32
}

/// The seed of the probe's samples: not the image's, so that a decision
/// taken from them is independent of the image's samples.
pub fn probe_seed(seed: u32) -> u32 {
    // A fixed odd constant (the 32-bit golden ratio) added: any other
    // seed would do.
    seed.wrapping_add(0x9e37_79b9)
}

impl Guide {
    /// Nothing learned yet, over the box `lo`..`hi` (the scene's).
    pub fn new(lo: Vec3, hi: Vec3) -> Self {
        Self {
            field: Field::new(lo, hi),
            learned: 0,
            // The first iteration draws from nothing learned: where
            // guiding matters its samples are the unguided ones, tens of
            // times a guided sample's variance (the prism's confetti).
            weights: vec![Self::halved(0)],
            stopped: false,
        }
    }

    /// A guide that stopped before the image's first sample: the probe
    /// (`integrator/learn.rs`) learned `probe` and found it worth less
    /// than [`STOP`]. Every learning sample weighs 1, so the image is the
    /// unguided render's, bit for bit. The probe's samples are not the
    /// image's (another seed), so weights decided from it keep the
    /// pixel's mean unbiased without [`BUDGET`].
    pub fn declined(probe: Field) -> Self {
        Self {
            field: probe,
            learned: 0,
            weights: vec![1.0; BOUNDARIES.len() - 1],
            stopped: true,
        }
    }

    /// The weight 2^(k − 4) of iteration k's samples while guiding goes
    /// on: each iteration's field learned from twice the samples of the
    /// one before.
    fn halved(k: usize) -> f32 {
        0.5f32.powi((BOUNDARIES.len() - 2 - k) as i32)
    }

    /// The weight in the film of a sample of learning iteration `k` (1
    /// after the last); decided before the iteration's first sample.
    pub fn weight(&self, k: usize) -> f32 {
        self.weights.get(k).copied().unwrap_or(1.0)
    }

    /// Whether learning and guiding stopped: the field was not worth its
    /// cost ([`STOP`]).
    pub fn stopped(&self) -> bool {
        self.stopped
    }

    /// The field learned so far: the one samples draw from, and the one
    /// an iteration records into.
    pub fn field(&self) -> &Field {
        &self.field
    }

    /// Iterations learned so far.
    pub fn learned(&self) -> usize {
        self.learned
    }

    /// Learns the next field from what the last iteration recorded into
    /// this one; nothing after the last iteration of [`BOUNDARIES`].
    pub fn advance(&mut self, stats: &Stats) {
        let k = self.learned;
        if k + 1 >= BOUNDARIES.len() || self.stopped {
            return;
        }
        let spp = BOUNDARIES[k + 1] - BOUNDARIES[k];
        self.field = self.field.next(stats, spp);
        self.learned += 1;
        self.stopped = self.learned >= usize::from(DOUBTS) && self.field.worth() < STOP;
        // The weights of the iterations about to run: the next one, or,
        // once stopped, all that are left.
        let last = BOUNDARIES.len() - 2;
        let upto = if self.stopped {
            last
        } else {
            self.learned.min(last)
        };
        for j in self.weights.len()..=upto {
            let w = if j == last {
                let spent: f32 = (0..last)
                    .map(|i| self.weights[i] * (BOUNDARIES[i + 1] - BOUNDARIES[i]) as f32)
                    .sum();
                (BUDGET - spent) / (BOUNDARIES[last + 1] - BOUNDARIES[last]) as f32
            } else if self.stopped {
                1.0
            } else {
                Self::halved(j)
            };
            self.weights.push(w);
        }
    }
}
