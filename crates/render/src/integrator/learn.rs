//! The guide's learning iterations (`crate::guiding`), which are the
//! image's own first [`LEARNED`] samples per pixel. Each learning sample
//! draws from the field the iterations before it learned, so each is an
//! unbiased estimate, and the image keeps them rather than paying for
//! them twice. The first iterations' fields are poor where guiding
//! matters (the prism's first samples are the unguided confetti, tens of
//! times a guided sample's variance), so a sample of iteration k weighs
//! `Guide::weight(k)` in the film, decided before the iteration from what
//! the guide learned: 2^(k − 4) while guiding goes on, 1 once it stopped
//! for want of anything to guide, within a fixed budget for all 16
//! (`guiding::BUDGET`) that keeps the pixel's weighted mean unbiased.
//! Before all of them a probe decides whether to guide at all, from
//! samples that are not the image's (`Renderer::probe`).
//!
//! The field after an iteration must be the same in every render of the
//! same seed (fresh, resumed, a shard of rows or of samples), and it
//! depends on the order its records are summed in. So an iteration is
//! learned from one pass over every row: the image's own pass when it is
//! exactly that, otherwise, once the image's samples of the iteration are
//! done (or before the first sample of a render that starts after them),
//! a pass of the same samples into a scratch film.

use std::sync::atomic::{AtomicBool, Ordering};

use crate::film::{Film, SampleCounts};
use crate::guiding::{
    next_boundary, probe_seed, probe_step, Guide, Stats, BOUNDARIES, DOUBTS, LEARNED,
};

use super::{RenderError, Renderer};

/// The samples `[b0, b1)` of the learning iteration that sample `done`
/// lies in, while learning goes on.
pub(super) fn iteration(done: u32) -> Option<(u32, u32)> {
    // The last boundary is LEARNED: none is found past it.
    let b1 = next_boundary(done)?;
    let b0 = BOUNDARIES.iter().copied().rfind(|&b| b <= done)?;
    Some((b0, b1))
}

impl Renderer<'_> {
    /// The learning iteration sample `done` lies in, when guiding is on
    /// and learning goes on.
    pub(super) fn learning(&self, done: u32) -> Option<(u32, u32)> {
        self.guiding.as_ref().and_then(|_| iteration(done))
    }

    /// Learns, in a scratch film, every iteration that ends at or before
    /// sample `done` (samples a resumed render or a later shard already
    /// holds or does not render). Stops early when `cancel` is set.
    pub(super) fn catch_up<const K: usize>(
        &mut self,
        seed: u32,
        done: u32,
        cancel: &AtomicBool,
    ) -> Result<(), RenderError> {
        self.probe::<K>(seed)?;
        while let Some((b0, b1)) = self.learned().and_then(iteration) {
            if b1 > done || cancel.load(Ordering::Relaxed) {
                break;
            }
            self.learn_apart::<K>(seed, b0, b1)?;
        }
        Ok(())
    }

    /// Renders samples `done..done + count` into `film` (within one
    /// learning iteration) and learns from them: from this very pass when
    /// it is the whole iteration over every row, otherwise from a scratch
    /// pass once the iteration's last sample is in the film.
    pub(super) fn learning_pass<const K: usize>(
        &mut self,
        seed: u32,
        film: &mut Film,
        done: u32,
        count: u32,
    ) -> Result<SampleCounts, RenderError> {
        let Some((b0, b1)) = iteration(done) else {
            return Ok(self.pass::<K>(seed, film, (done, count, 1.0), None));
        };
        let k = BOUNDARIES.iter().position(|&b| b == b0).unwrap_or(0);
        let Some(g) = self.guiding.as_ref() else {
            return Ok(self.pass::<K>(seed, film, (done, count, 1.0), None));
        };
        let samples = (done, count, g.guide.weight(k));
        if g.guide.stopped() {
            return Ok(self.pass::<K>(seed, film, samples, None));
        }
        let every_row = self.rows.start == 0 && self.rows.end >= film.height;
        if done == b0 && done + count == b1 && every_row {
            let mut stats = self.recording();
            let counts = self.pass::<K>(seed, film, samples, stats.as_mut());
            self.advance(stats);
            return Ok(counts);
        }
        let counts = self.pass::<K>(seed, film, samples, None);
        if done + count == b1 {
            self.learn_apart::<K>(seed, b0, b1)?;
        }
        Ok(counts)
    }

    /// Decides, before the image's first sample, whether guiding is worth
    /// its cost: learns [`DOUBTS`] iterations of 1 spp over every
    /// [`probe_step`]-th row from samples of another seed, into a film
    /// that is thrown away, and where the field is worth less than
    /// `guiding::STOP` declines to guide (`Guide::declined`); otherwise
    /// the image's learning starts afresh. It depends on the seed alone,
    /// so a resumed render or a shard decides as the whole render did.
    fn probe<const K: usize>(&mut self, seed: u32) -> Result<(), RenderError> {
        let Some(g) = self.guiding.as_ref().filter(|g| !g.probed) else {
            return Ok(());
        };
        let fresh = g.guide.clone();
        let step = probe_step(self.scene.camera.width, self.scene.camera.height);
        let iterations: Vec<(u32, u32)> = (0..u32::from(DOUBTS)).map(|k| (k, k + 1)).collect();
        self.learn_in_scratch::<K>(probe_seed(seed), step, &iterations)?;
        if let Some(g) = self.guiding.as_mut() {
            g.probed = true;
            g.guide = if g.guide.stopped() {
                Guide::declined(g.guide.field().clone())
            } else {
                fresh
            };
        }
        Ok(())
    }

    /// The samples per pixel the guide has learned from, while learning
    /// goes on.
    fn learned(&self) -> Option<u32> {
        let g = self.guiding.as_ref().filter(|g| !g.guide.stopped())?;
        BOUNDARIES
            .get(g.guide.learned())
            .copied()
            .filter(|&j| j < LEARNED)
    }

    /// Learns the iteration of samples `s0..s1` from a pass over every row
    /// into a film that is thrown away.
    fn learn_apart<const K: usize>(
        &mut self,
        seed: u32,
        s0: u32,
        s1: u32,
    ) -> Result<(), RenderError> {
        self.learn_in_scratch::<K>(seed, 1, &[(s0, s1)])
    }

    /// Learns each iteration of `iterations` (samples `s0..s1`, in turn)
    /// from a pass over every `step`-th row of the film into a film that
    /// is thrown away.
    fn learn_in_scratch<const K: usize>(
        &mut self,
        seed: u32,
        step: u32,
        iterations: &[(u32, u32)],
    ) -> Result<(), RenderError> {
        let (width, height) = (self.scene.camera.width, self.scene.camera.height);
        let mut scratch =
            Film::try_new(width, height, None).map_err(|e| RenderError::TooLarge(Box::new(e)))?;
        let rows = std::mem::replace(&mut self.rows, 0..u32::MAX);
        self.row_step = step;
        for &(s0, s1) in iterations {
            let mut stats = self.recording();
            self.pass::<K>(seed, &mut scratch, (s0, s1 - s0, 1.0), stats.as_mut());
            self.advance(stats);
        }
        self.rows = rows;
        self.row_step = 1;
        Ok(())
    }

    /// Empty records for the field learned so far, with the integrators
    /// told to record.
    fn recording(&mut self) -> Option<Stats> {
        self.guiding.as_mut().map(|g| {
            g.learning = true;
            Stats::new(g.guide.field())
        })
    }

    /// The next field, from an iteration's records.
    fn advance(&mut self, stats: Option<Stats>) {
        if let (Some(g), Some(stats)) = (self.guiding.as_mut(), stats) {
            g.learning = false;
            g.guide.advance(&stats);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::iteration;

    #[test]
    fn learning_iterations_are_the_first_samples_cut_at_the_boundaries() {
        let cut: Vec<_> = [0, 1, 2, 3, 5, 7, 8, 15, 16, 40].map(iteration).to_vec();
        let expected = [
            Some((0, 1)),
            Some((1, 2)),
            Some((2, 4)),
            Some((2, 4)),
            Some((4, 8)),
            Some((4, 8)),
            Some((8, 16)),
            Some((8, 16)),
            None,
            None,
        ];
        assert_eq!(cut, expected);
    }
}
