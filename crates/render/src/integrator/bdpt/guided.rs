//! Guided emission, the bidirectional tracer's path guiding (with
//! `--guiding on`): a light subpath leaves its light in a direction drawn
//! half from the field learned at the light's point (`crate::guiding`),
//! half as the light itself emits, and its weight and every MIS density
//! of that first segment use the mixture's density (one-sample MIS, Veach
//! 1997 §9.2.2). The field learns, at the light vertex, the light paths'
//! MIS-weighted contributions through every strategy that used the
//! direction (s ≥ 2) over its density: the directions whose light reaches
//! the camera through connections and light tracing. A lamp at the back of
//! a tube, or behind a slit, then sends its light paths out of the opening
//! instead of into the walls (the idea of guiding light subpaths as well
//! as camera subpaths is Vorba et al. 2014's, "On-line Learning of
//! Parametric Mixture Models for Light Transport Simulation").
//!
//! Lights at infinity and directional lights emit from a disk already
//! aimed at the shapes that cast caustics (`light::emit_disk`); they are
//! not guided.

use scotopia_color::SampledWavelengths;

use crate::guiding::{side, DTree, SHARE};
use crate::integrator::Renderer;
use crate::light::{Emission, Light};
use crate::math::Vec3;
use crate::sampling::splitmix::SplitMix;

/// The field's side a light's emission learns and draws from: one per
/// cell whatever the light's normal, so that a light point's density
/// needs no orientation (the camera side's seven are for surfaces that
/// see only the hemisphere they face).
const EMITTING: Option<Vec3> = None;

impl Renderer<'_> {
    /// The learned density that light leaving `light` at `p` draws half
    /// its directions from, when guiding has learned one there.
    #[inline]
    pub(super) fn emission_guide(&self, light: &Light, p: Vec3) -> Option<&DTree> {
        self.spot(p, EMITTING).filter(|_| guided(light))?.guide()
    }

    /// The density of light subpaths leaving `light` at `p` in direction
    /// `d`, where the light's own density is `own`.
    #[inline]
    pub(super) fn emission_pdf(&self, light: &Light, p: Vec3, d: Vec3, own: f32) -> f32 {
        match self.emission_guide(light, p) {
            Some(g) => (1.0 - SHARE) * own + SHARE * g.pdf(d),
            None => own,
        }
    }

    /// Emission `e` of `light` drawn with direction numbers `u_dir`, its
    /// direction redrawn from the guide with probability [`SHARE`] (the
    /// choice from `rng`), its density the mixture's. `None` when the
    /// guide draws nothing.
    pub(super) fn guide_emission<const K: usize>(
        &self,
        light: &Light,
        e: Emission<K>,
        wl: &SampledWavelengths<K>,
        u_dir: [f32; 2],
        rng: &mut SplitMix,
    ) -> Option<Emission<K>> {
        let Some(g) = self.emission_guide(light, e.p) else {
            return Some(e);
        };
        if rng.next_f32() >= SHARE {
            return Some(Emission {
                pdf_dir: (1.0 - SHARE) * e.pdf_dir + SHARE * g.pdf(e.d),
                ..e
            });
        }
        let (d, p_guide) = g.sample(u_dir)?;
        let n = e.n.unwrap_or(Vec3::ZERO);
        let own = light.pdf_le(&self.extent(), e.p, n, d).dir;
        Some(Emission {
            d,
            le: light.emitted_towards(wl, e.uv, n, d),
            pdf_dir: (1.0 - SHARE) * own + SHARE * p_guide,
            ..e
        })
    }

    /// The slot a light vertex at `p` leaving in direction `d` records
    /// into while the guide learns.
    pub(super) fn emission_slot(&self, light: &Light, p: Vec3, d: Vec3) -> Option<u32> {
        let learning = self.guiding.as_ref().is_some_and(|g| g.learning);
        if !learning || !guided(light) {
            return None;
        }
        Some(self.field()?.at(p, side(EMITTING)).slot(d))
    }
}

/// Whether light paths leaving `light` are guided: lights whose emission
/// is drawn by direction from a point (not at infinity, not directional).
fn guided(light: &Light) -> bool {
    !(light.is_infinite() || light.is_delta_direction())
}
