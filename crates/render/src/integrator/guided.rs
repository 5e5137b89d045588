//! Path guiding in the path and volume path tracers: bounces drawn half
//! from the light field learned so far (`crate::guiding`), half as they
//! would be unguided, weighed by the mixture's density (one-sample MIS,
//! Veach 1997 §9.2.2, balance heuristic); next-event estimation and
//! emitters hit weigh against the same density. While the guide learns,
//! every vertex that drew a direction leaves a mark on its path, and the
//! light the path finds after it becomes that vertex's record.

use scotopia_color::{SampledSpectrum, SampledWavelengths};

use super::halo::{self, Halos};
use super::path::ScatterPoint;
use super::reflectors::{self, Reflectors};
use super::select::Integrator;
use super::Renderer;
use crate::bsdf::{Bsdf, BsdfSample, Transport};
use crate::guiding::{side, DTree, Field, Guide, Spot, SHARE};
use crate::math::Vec3;
use crate::medium::Phase;
use crate::sampling::splitmix::SplitMix;

/// A render's guiding state: the field learned, and whether the pass that
/// runs records.
#[derive(Debug, Clone)]
pub(super) struct GuideState {
    pub guide: Guide,
    pub learning: bool,
    /// Whether the probe decided if guiding is worth it (`learn.rs`).
    pub probed: bool,
}

/// Vertices of a path that wait for their record: at most this many (the
/// first ones: deeper vertices carry little light and many records).
const MAX_MARKS: usize = 8;

/// A vertex's record to be: where it goes, and what turns the light the
/// path finds after it into the record (1/(Σβ·q): the throughput after the
/// vertex summed over the cluster, and the density of its direction).
#[derive(Debug, Clone, Copy, Default)]
pub struct Mark {
    slot: u32,
    inv: f32,
    /// The path's light (summed over the cluster) when the vertex was left.
    at: f32,
}

/// A path's marks.
#[derive(Debug, Clone, Copy, Default)]
pub struct Trail {
    n: u8,
    /// Whether the last mark is the vertex the path just left.
    fresh: bool,
    marks: [Mark; MAX_MARKS],
}

/// A mark before the path's light at the vertex is known.
#[derive(Debug, Clone, Copy)]
pub struct Pending {
    slot: u32,
    inv: f32,
}

impl Trail {
    /// Leaves `p`'s mark with the path's light so far, `light`.
    #[inline]
    pub(super) fn push(&mut self, p: Pending, light: f32) {
        self.fresh = false;
        if let Some(m) = self.marks.get_mut(self.n as usize) {
            self.fresh = true;
            *m = Mark {
                slot: p.slot,
                inv: p.inv,
                at: light,
            };
            self.n += 1;
        }
    }

    /// The path left a vertex without a mark (a delta bounce, a null
    /// surface passed).
    #[inline]
    pub(super) fn unmarked(&mut self) {
        self.fresh = false;
    }

    /// Light `light` that the path found by hitting an emitter: direct
    /// light for the vertex it just left, which next-event estimation
    /// samples there, so not that vertex's to learn (the guide learns the
    /// light that only bounces find); indirect for the vertices before.
    #[inline]
    pub(super) fn direct<const K: usize>(&mut self, light: &SampledSpectrum<K>) {
        if self.fresh {
            if let Some(m) = self.marks[..self.n as usize].last_mut() {
                m.at += light.0.iter().sum::<f32>();
            }
        }
    }

    /// Each mark's record, from the path's final light `light`: the
    /// incident radiance along its direction over the direction's density.
    pub(super) fn records(&self, light: f32, out: &mut Vec<(u32, f32)>) {
        for m in &self.marks[..self.n as usize] {
            let e = (light - m.at).max(0.0) * m.inv;
            if e.is_finite() {
                out.push((m.slot, e));
            }
        }
    }
}

/// Whether a vertex of `bsdf` draws from the guide: surfaces with a
/// diffuse part. Glossy metals and glass keep their own sampling, which
/// a field of 1 % quadrants cannot beat.
fn guided(bsdf: &Bsdf) -> bool {
    match bsdf {
        Bsdf::Diffuse(_)
        | Bsdf::Plastic(_)
        | Bsdf::RoughPlastic(_)
        | Bsdf::PolarizedPlastic(_)
        | Bsdf::Principled(_) => true,
        Bsdf::TwoSided(inner) => guided(inner),
        Bsdf::Mask(b) => guided(&b.inner),
        Bsdf::NormalMap(b) => guided(&b.inner),
        Bsdf::BumpMap(b) => guided(&b.inner),
        Bsdf::Blend(b) => guided(&b.first) || guided(&b.second),
        _ => false,
    }
}

/// The largest mean cosine |g| of a phase function whose scattering is
/// guided. The guide learns the light arriving, not its product with the
/// phase function: for a strongly forward phase function (fog's g = 0.85)
/// the guided half of the directions mostly lands where the phase
/// function is small, and the foggy street rendered worse with it (0.31
/// against 0.23 relMSE of Y at 48 spp). Herholz et al. 2019 guide the
/// product; until then, only phase functions this close to isotropic.
const MAX_GUIDED_G: f32 = 0.5;

/// Whether scattering by `phase` draws from the guide.
fn guided_phase(phase: &Phase) -> bool {
    match phase {
        Phase::Isotropic => true,
        Phase::HenyeyGreenstein { g } => g.abs() <= MAX_GUIDED_G,
    }
}

/// A number u ≥ `share` that chose a mixture's second strategy, rescaled
/// to [0, 1) for that strategy's own use.
#[inline]
fn past(u: f32, share: f32) -> f32 {
    ((u - share) / (1.0 - share)).min(1.0 - f32::EPSILON)
}

/// The guided mixture's density from the unguided density `p` and the
/// guide's `g`.
#[inline]
fn mixed(p: f32, g: f32) -> f32 {
    (1.0 - SHARE) * p + SHARE * g
}

/// The density with the halos' share (`halo`) from the density `p` of
/// the other strategies and the halos' `h`.
#[inline]
fn with_halo(p: f32, h: f32) -> f32 {
    (1.0 - halo::SHARE) * p + halo::SHARE * h
}

/// The density with the reflectors' share at medium points
/// (`reflectors::MEDIUM_SHARE`) from the density `p` of the other
/// strategies and the reflectors' `r`.
#[inline]
fn with_reflectors(p: f32, r: f32) -> f32 {
    (1.0 - reflectors::MEDIUM_SHARE) * p + reflectors::MEDIUM_SHARE * r
}

/// A direction from phase function `phase`, drawn half from `guide` when
/// there is one: the direction, the phase function's value f there and
/// the mixture's density q.
fn sample_unhaloed_phase(
    guide: Option<&DTree>,
    phase: &Phase,
    wi: Vec3,
    u_pick: f32,
    u: [f32; 2],
) -> Option<(Vec3, f32, f32)> {
    let Some(g) = guide else {
        // The phase function is sampled exactly: f = pdf.
        let (wo, pdf) = phase.sample(wi, u);
        return Some((wo, pdf, pdf));
    };
    let wo = if u_pick < SHARE {
        g.sample(u)?.0
    } else {
        phase.sample(wi, u).0
    };
    let f = phase.eval(wi, wo);
    let q = mixed(f, g.pdf(wo));
    (f > 0.0 && q > 0.0 && q.is_finite()).then_some((wo, f, q))
}

impl Renderer<'_> {
    /// The field the pass draws from, when guiding.
    #[inline]
    pub(super) fn field(&self) -> Option<&Field> {
        self.guiding
            .as_ref()
            .filter(|g| !g.guide.stopped())
            .map(|g| g.guide.field())
    }

    /// The field's density at `p` for a vertex whose normal, turned to
    /// the side the path is on, is `n` (`None` in a medium), when guiding
    /// and a cell near it guides.
    #[inline]
    pub(super) fn spot(&self, p: Vec3, n: Option<Vec3>) -> Option<Spot<'_>> {
        let side = side(n);
        self.field()
            .filter(|f| f.may_guide(p, side))
            .map(|f| f.at(p, side))
    }

    /// The guide a vertex of `bsdf` draws from at `spot`, if any.
    #[inline]
    pub(super) fn surface_guide<'f>(
        &self,
        spot: Option<Spot<'f>>,
        bsdf: &Bsdf,
    ) -> Option<&'f DTree> {
        spot.and_then(|s| s.guide()).filter(|_| guided(bsdf))
    }

    /// The lamps' halos bounces aim at: the volume path tracer's.
    #[inline]
    pub(super) fn halos(&self) -> Option<&Halos> {
        match &self.integrator {
            Integrator::VolPath(m) if !m.halos.is_empty() => Some(&m.halos),
            _ => None,
        }
    }

    /// The halos a bounce at a vertex of `bsdf` aims at, if any: at
    /// surfaces with a diffuse part, as guiding.
    #[inline]
    fn surface_halos(&self, bsdf: &Bsdf) -> Option<&Halos> {
        self.halos().filter(|_| guided(bsdf))
    }

    /// The guide scattering by `phase` draws from at `spot`, if any.
    #[inline]
    pub(super) fn phase_guide<'f>(
        &self,
        spot: Option<Spot<'f>>,
        phase: &Phase,
    ) -> Option<&'f DTree> {
        spot.and_then(|s| s.guide()).filter(|_| guided_phase(phase))
    }

    /// The density of a bounce from `x` at a vertex of `bsdf` in world
    /// direction `d`, given the BSDF's own `bsdf_pdf`: what next-event
    /// estimation weighs a light against.
    #[inline]
    pub(super) fn bounce_pdf(
        &self,
        guide: Option<&DTree>,
        bsdf: &Bsdf,
        x: Vec3,
        d: Vec3,
        bsdf_pdf: f32,
    ) -> f32 {
        let p = self.reflectors.pdf(bsdf, x, d, bsdf_pdf);
        let p = match guide {
            Some(g) => mixed(p, g.pdf(d)),
            None => p,
        };
        match self.surface_halos(bsdf) {
            Some(h) => with_halo(p, h.pdf(x, d)),
            None => p,
        }
    }

    /// The path tracer's bounce at `point`: unguided (`reflectors`), or
    /// with probability [`SHARE`] a direction from `guide`; its weight
    /// f·cos/q and density q. `u`: the lobe's number, then the
    /// direction's two.
    pub(super) fn sample_bounce<const K: usize>(
        &self,
        guide: Option<&DTree>,
        bsdf: &Bsdf,
        wl: &SampledWavelengths<K>,
        point: &ScatterPoint,
        wi: Vec3,
        [u_lobe, u0, u1]: [f32; 3],
    ) -> Option<BsdfSample<K>> {
        match self.surface_halos(bsdf) {
            None => self.sample_unhaloed(guide, bsdf, wl, point, wi, [u_lobe, u0, u1]),
            Some(h) => self.sample_haloed(guide, bsdf, wl, point, wi, (h, [u_lobe, u0, u1])),
        }
    }

    /// [`Self::sample_bounce`] in media, where a share of the bounces aims
    /// at the lamps' halos (`halo`); the density of every direction is the
    /// mixture's. Kept out of line: the path tracer without media never
    /// comes here, and its bounce stays small enough to inline.
    #[inline(never)]
    fn sample_haloed<const K: usize>(
        &self,
        guide: Option<&DTree>,
        bsdf: &Bsdf,
        wl: &SampledWavelengths<K>,
        point: &ScatterPoint,
        wi: Vec3,
        (h, [u_lobe, u0, u1]): (&Halos, [f32; 3]),
    ) -> Option<BsdfSample<K>> {
        let x = point.p;
        if u_lobe < halo::SHARE {
            let d = h.sample(x, u_lobe / halo::SHARE, [u0, u1])?;
            let wo = point.frame.to_local(d);
            let f = bsdf.eval(wl, point.at, wi, wo, Transport::Radiance);
            let q = self.bounce_pdf(guide, bsdf, x, d, bsdf.pdf_at(wl, point.at, wi, wo));
            return BsdfSample::mixed(wo, f, q);
        }
        let u_lobe = past(u_lobe, halo::SHARE);
        let mut bs = self.sample_unhaloed(guide, bsdf, wl, point, wi, [u_lobe, u0, u1])?;
        if bs.delta {
            // Drawn by the other share only.
            bs.weight *= 1.0 / (1.0 - halo::SHARE);
            return Some(bs);
        }
        let q = with_halo(bs.pdf, h.pdf(x, point.frame.to_world(bs.wo)));
        // The weight f/p becomes f/q.
        bs.weight *= bs.pdf / q;
        bs.pdf = q;
        (q > 0.0 && q.is_finite()).then_some(bs)
    }

    /// [`Self::sample_bounce`] without the halos' share.
    #[inline]
    fn sample_unhaloed<const K: usize>(
        &self,
        guide: Option<&DTree>,
        bsdf: &Bsdf,
        wl: &SampledWavelengths<K>,
        point: &ScatterPoint,
        wi: Vec3,
        [u_lobe, u0, u1]: [f32; 3],
    ) -> Option<BsdfSample<K>> {
        let u = [u0, u1];
        let Some(g) = guide else {
            return self.reflectors.sample(bsdf, wl, point, wi, u_lobe, u);
        };
        let ScatterPoint {
            p: x, frame, at, ..
        } = *point;
        // The guide's density of the direction: from the walk that drew
        // it, or by a walk for the BSDF's.
        let (wo, d, p_guide) = if u_lobe < SHARE {
            let (d, p) = g.sample(u)?;
            (frame.to_local(d), d, p)
        } else {
            let u_lobe = past(u_lobe, SHARE);
            let mut bs = self.reflectors.sample(bsdf, wl, point, wi, u_lobe, u)?;
            if bs.delta {
                // The guide draws no delta direction: this lobe was
                // chosen with the unguided share only.
                bs.weight *= 1.0 / (1.0 - SHARE);
                return Some(bs);
            }
            let d = frame.to_world(bs.wo);
            (bs.wo, d, g.pdf(d))
        };
        let f = bsdf.eval(wl, at, wi, wo, Transport::Radiance);
        let unguided = self.reflectors.pdf(bsdf, x, d, bsdf.pdf_at(wl, at, wi, wo));
        let q = mixed(unguided, p_guide);
        BsdfSample::mixed(wo, f, q)
    }

    /// A direction from phase function `phase` at a medium point, drawn
    /// half from `guide` when there is one, a share aimed at the lamps'
    /// halos (`halo`) and a share at lamp-lit glossy reflectors
    /// (`reflectors`): the direction, the phase function's value f there
    /// and the mixture's density q.
    pub(super) fn sample_phase(
        &self,
        guide: Option<&DTree>,
        (phase, x): (&Phase, Vec3),
        wi: Vec3,
        u_pick: f32,
        u: [f32; 2],
    ) -> Option<(Vec3, f32, f32)> {
        const C: f32 = reflectors::MEDIUM_SHARE;
        let (wo, f, q) = match self.medium_reflectors() {
            Some(r) if u_pick < C => {
                let wo = r.sample_refl(x, u_pick / C, u)?;
                let f = phase.eval(wi, wo);
                (wo, f, self.phase_pdf(guide, x, f, wo))
            }
            Some(r) => {
                let (wo, f, q) =
                    self.sample_unreflected_phase(guide, (phase, x), wi, past(u_pick, C), u)?;
                (wo, f, with_reflectors(q, r.pdf_refl(x, wo)))
            }
            None => self.sample_unreflected_phase(guide, (phase, x), wi, u_pick, u)?,
        };
        (f > 0.0 && q > 0.0 && q.is_finite()).then_some((wo, f, q))
    }

    /// [`Self::sample_phase`] without the reflectors' share.
    fn sample_unreflected_phase(
        &self,
        guide: Option<&DTree>,
        (phase, x): (&Phase, Vec3),
        wi: Vec3,
        u_pick: f32,
        u: [f32; 2],
    ) -> Option<(Vec3, f32, f32)> {
        let Some(h) = self.halos() else {
            return sample_unhaloed_phase(guide, phase, wi, u_pick, u);
        };
        let (wo, f, q) = if u_pick < halo::SHARE {
            let wo = h.sample(x, u_pick / halo::SHARE, u)?;
            let f = phase.eval(wi, wo);
            (wo, f, self.unreflected_phase_pdf(guide, x, f, wo))
        } else {
            let u_pick = past(u_pick, halo::SHARE);
            let (wo, f, q) = sample_unhaloed_phase(guide, phase, wi, u_pick, u)?;
            (wo, f, with_halo(q, h.pdf(x, wo)))
        };
        (f > 0.0 && q > 0.0 && q.is_finite()).then_some((wo, f, q))
    }

    /// The density a medium point `x`'s bounce has in direction `d`,
    /// where the phase function's value is `f`.
    #[inline]
    pub(super) fn phase_pdf(&self, guide: Option<&DTree>, x: Vec3, f: f32, d: Vec3) -> f32 {
        let p = self.unreflected_phase_pdf(guide, x, f, d);
        match self.medium_reflectors() {
            Some(r) => with_reflectors(p, r.pdf_refl(x, d)),
            None => p,
        }
    }

    /// The reflectors a medium point's bounce aims at, if the scene has
    /// any. Fog beside a lamp-lit pole sees the lamp's glossy reflection
    /// in it, thousands of cd/m² over a few square centimetres: reached
    /// by the phase function or a halo's cone alone, one such bounce in
    /// a thousand pixels' samples made the foggy street's last fireflies.
    #[inline]
    fn medium_reflectors(&self) -> Option<&Reflectors> {
        (!self.reflectors.is_empty()).then_some(&self.reflectors)
    }

    /// [`Self::phase_pdf`] without the reflectors' share.
    #[inline]
    fn unreflected_phase_pdf(&self, guide: Option<&DTree>, x: Vec3, f: f32, d: Vec3) -> f32 {
        let p = match guide {
            Some(g) => mixed(f, g.pdf(d)),
            None => f,
        };
        match self.halos() {
            Some(h) => with_halo(p, h.pdf(x, d)),
            None => p,
        }
    }

    /// The mark a vertex at `p` (normal `n` turned to the path's side,
    /// `None` in a medium) leaves for a bounce along world direction `d`
    /// drawn with density `q`, its throughput after the bounce `beta`:
    /// only while the guide learns. The record goes to the cell at a point
    /// jittered within a box half the size of `p`'s cell (numbers from
    /// `rng`): the stochastic spatial filter of Müller 2019 ("Practical Path
    /// Guiding in Production", SIGGRAPH course notes)
    /// (theirs the cell's whole size), so that neighbouring cells learn
    /// alike and the noise shows no seams at their borders. On the hidden
    /// lamp test scene at 256 × 192, 64 spp, the seam across the floor
    /// went; relMSE of Y over the floor 0.92 without the filter, 1.14 with
    /// half the size, 1.30 with the whole.
    #[inline]
    pub(super) fn pending<const K: usize>(
        &self,
        (p, n): (Vec3, Option<Vec3>),
        d: Vec3,
        q: f32,
        beta: &SampledSpectrum<K>,
        rng: &mut SplitMix,
    ) -> Option<Pending> {
        let field = self
            .field()
            .filter(|_| self.guiding.as_ref().is_some_and(|g| g.learning))?;
        let side = side(n);
        if !field.may_learn(p, side) {
            return None;
        }
        let inv = 1.0 / (beta.0.iter().sum::<f32>() * q);
        let u = [rng.next_f32(), rng.next_f32(), rng.next_f32()];
        inv.is_finite().then(|| Pending {
            slot: field.jittered(p, side, u).slot(d),
            inv,
        })
    }
}
