//! The caustic as a light: lamp light traced through a glass ball onto a
//! surface, and joined from there to the camera path's diffuse vertices.
//!
//! The estimator of `mod.rs` finds the caustic where the camera path
//! scatters in it. A wall or a shadow lit by the caustic (the path
//! u → v → ball → lamp, with v in the caustic) it finds only when u's
//! bounce happens to land in the small bright spot: a firefly. Light
//! tracing finds that spot where the caustic is bright, so each camera
//! path draws one light subpath, y → ball → … → v: a lamp by its power,
//! a point y on it, a direction uniform in the cone the ball subtends
//! from y, and at each interface reflection or refraction by the Fresnel
//! fraction F. Every diffuse vertex u of the camera path is joined to v
//! (Veach 1997 ch. 10's connections, with the ball's chords a specular
//! chain): straight, by a shadow ray, and by way of a ball (`THROUGH`),
//! the caustic seen through it. One camera path in twenty draws a
//! subpath (`JOIN_SHARE`).
//!
//! Three strategies then draw the path u → v → ball → y: the bounce at u
//! and the estimator at v (which runs less often where joins run:
//! `SHARES_JOINED`), the bounces at u and at v, and this one. Their
//! densities, per area at v and per solid angle of the chain at v:
//!
//! - the estimator: A · P_nee(lamp) σ_kind / (A_lamp · dω_v/dA_y);
//! - BSDF sampling: A · p_v(ω_v) · F-choices;
//! - this: P(lamp) p_dir(ω_y) F-choices · |cos_v| / (A_lamp |cos_y|),
//!   the chain's étendue (cos dA dω, both ends in air) taking the
//!   density at y to v's measure;
//!
//! where A = p_u(u → v) |cos_v′| / d² is the bounce at u's density per
//! area at v (by way of a ball, p_u times the Fresnel choices times the
//! leg's dω_u/dA_v). All three are weighed by the power heuristic.

use scotopia_color::{SampledSpectrum, SampledWavelengths};

use super::ball::Kind;
use super::{along, fresnel, reflected, Lens, SHARES_JOINED};
use crate::bsdf::{Bsdf, Transport};
use crate::guiding::DTree;
use crate::integrator::direct::{power_heuristic, spawn};
use crate::integrator::path::{PathState, ScatterPoint};
use crate::integrator::Renderer;
use crate::light::Light;
use crate::math::{Frame, Vec3};
use crate::sampling::splitmix::SplitMix;
use crate::sampling::warp::{square_to_uniform_cone, uniform_cone_pdf};

/// The most reflections inside a ball a light subpath follows: those of
/// the kinds the estimator searches.
const MOST_INSIDE: u8 = 3;

/// The kinds of path by way of a ball that a vertex is joined to a light
/// subpath by, besides straight: the caustic seen through the ball, or
/// reflected off its underside, from a diffuse point. Those were the
/// brightest fireflies left once the walls were joined (logged: floor →
/// off the ball → floor in the caustic → estimator; and one reflection
/// inside).
pub(super) const THROUGH: [Kind; 3] = [Kind::Reflected, Kind::Through(0), Kind::Through(1)];

/// The share of camera paths that draw a light subpath; the others join
/// none, and the strategy's density carries the share (one-sample MIS, as
/// the estimator's `SHARES`). Measured on `glass-and-metals.xml`, 16
/// paired seeds at 32 spp (docs/caustics.md): the relMSE of Y is 0.0653
/// drawn for every path, 0.0661 for one in 20 and 0.0669 for one in 50,
/// against 0.0772 without; the seconds per image 0.99, 0.72 and 0.71,
/// against 0.68. The walls need few subpaths: each lands where the
/// caustic is bright. With the joins by way of the ball and
/// `SHARES_JOINED`, over 48 seeds, relMSE × s was 0.0268 for one in 20,
/// 0.0273 for one in 33, 0.0278 for one in 10 and 0.0306 for one in 5.
const JOIN_SHARE: f32 = 0.05;

/// Where a light subpath through a ball lands, and what joining it needs.
#[derive(Clone, Copy)]
pub struct LightVertex {
    pub(super) light: u32,
    pub(super) lens: u16,
    pub(super) kind: Kind,
    /// The lamp's normal and texture coordinates where the light leaves
    /// it, and the direction it leaves along.
    y: (Vec3, [f32; 2]),
    leaves: Vec3,
    /// Where it lands, and the material there.
    pub(super) v: ScatterPoint,
    material: u32,
    /// The unit direction from `v` back towards the ball.
    back: Vec3,
    /// The light the chain keeps (and the probability it was chosen so).
    fr: f32,
    /// This strategy's density (`join_pdf`), and the estimator's at `v`
    /// per steradian (its share included; 0 where its search misses this
    /// path). The subpath's weight but its spectra is fr / p_join:
    /// |cos y| / (p_y p_dir |cos v|).
    p_join: f32,
    p_nee: f32,
}

/// A camera path's light subpath, drawn when the path starts
/// (`seen::draw_caustic`).
#[derive(Clone, Copy, Default)]
pub enum Caustic {
    /// Not joined: no balls, or not a camera path in clear air.
    #[default]
    Off,
    /// Drawn, and lost (it missed the ball, or landed nowhere to join).
    Lost,
    At(LightVertex),
}

impl Caustic {
    pub fn is_on(&self) -> bool {
        !matches!(self, Caustic::Off)
    }
}

/// The cone of directions from `p` that meet `lens`'s ball: its axis and
/// 1 − cos of its half-angle (as sin²/(1 + cos), exact for small cones).
fn seen(lens: &Lens, p: Vec3) -> Option<(Vec3, f32)> {
    let d = lens.ball.center - p;
    let dc = (d.length_squared() as f64).sqrt();
    let r = lens.ball.radius as f64;
    if dc.is_nan() || dc <= r * (1.0 + 1e-4) {
        return None;
    }
    let sin2 = (r / dc) * (r / dc);
    let one_minus = sin2 / (1.0 + (1.0 - sin2).sqrt());
    Some((d / dc as f32, one_minus as f32))
}

impl Renderer<'_> {
    /// A light subpath: lamp, ball, the surface it lands on.
    pub(super) fn draw_light_vertex(
        &self,
        rng: &mut SplitMix,
        traced: &mut u32,
    ) -> Option<LightVertex> {
        let scene = self.scene;
        let pick = self.lenses.pick.as_ref()?;
        let u_pick = rng.next_f32();
        if u_pick >= JOIN_SHARE {
            return None;
        }
        let (light, _, _) = pick.sample_discrete(u_pick / JOIN_SHARE)?;
        let Light::Area(area) = &scene.lights[light] else {
            return None;
        };
        let [u0, u1, u2] = [rng.next_f32(), rng.next_f32(), rng.next_f32()];
        let shape = &scene.geometry.shapes[area.shape as usize];
        let y = shape.sample_area(area.triangles(), u0, [u1, u2])?;
        let lenses = &self.lenses.list;
        let li = ((rng.next_f32() * lenses.len() as f32) as usize).min(lenses.len() - 1);
        let lens = &lenses[li];
        let (axis, one_minus) = seen(lens, y.p)?;
        let u = [rng.next_f32(), rng.next_f32()];
        let dir = Frame::from_normal(axis).to_world(square_to_uniform_cone(u, one_minus));
        let unit = scene.geometry.offset_unit();
        let ray = spawn(y.p, y.n, dir, unit);
        *traced += 1;
        let hit = scene.geometry.intersect(&ray)?;
        if self.lenses.at(&hit) != Some(li as u16) {
            return None;
        }
        let entry = ray.o + ray.d * hit.t;
        let (kind, exit, out, f) = self.cross_ball(lens, entry, dir, rng, traced)?;
        let ray = spawn(exit, exit - lens.ball.center, out, unit);
        *traced += 1;
        let hit = scene.geometry.intersect(&ray)?;
        let material = scene.shape_material[hit.shape as usize];
        let bsdf = &scene.materials[material as usize];
        if self.lenses.at(&hit).is_some() || bsdf.is_delta() || bsdf.fluorescent().is_some() {
            return None;
        }
        let v = ScatterPoint::of(&scene.geometry.surface(&hit, &ray), &hit);
        let ng = v.ng;
        let cos_v = ng.dot(out).abs();
        let fr = fresnel(kind, f);
        let p_join = self.join_pdf((light, li as u16, fr), cos_v, (y.p, y.n, -dir));
        if !(p_join > 0.0 && (fr / p_join).is_finite()) {
            return None;
        }
        // The estimator at v (whose shares are those of a vertex joined to)
        // finds this path where its search does: the root of the search's
        // g at this path, refined from near it.
        let share = SHARES_JOINED.of(kind);
        let found = (share > 0.0).then(|| along(&lens.ball, kind, (v.p, y.p), -out));
        let p_nee = found.flatten().map_or(0.0, |path| {
            let p_choice = self.lights.probability(v.p, Some(ng), light);
            let spread = path.spread * path.out.dot(y.n).abs();
            share * p_choice / area.area() / spread
        });
        Some(LightVertex {
            light: light as u32,
            lens: li as u16,
            kind,
            y: (y.n, y.uv),
            leaves: dir,
            v,
            material,
            back: -out,
            fr,
            p_join,
            p_nee,
        })
    }

    /// Light entering `lens` at `a` along `d`: reflected off it, or
    /// refracted in, reflected inside, refracted out, each by its Fresnel
    /// probability. Its kind, where and along what it leaves, and F (the
    /// same at every interface of a ball). `None` past [`MOST_INSIDE`]
    /// reflections inside, or where something inside the ball blocks it.
    fn cross_ball(
        &self,
        lens: &Lens,
        a: Vec3,
        d: Vec3,
        rng: &mut SplitMix,
        traced: &mut u32,
    ) -> Option<(Kind, Vec3, Vec3, f32)> {
        let (c, eta) = (lens.ball.center, lens.ball.eta);
        let n = (a - c).normalize();
        let cos_i = -d.dot(n);
        if cos_i.is_nan() || cos_i <= 0.0 {
            return None;
        }
        let f = reflected(cos_i, eta);
        if rng.next_f32() < f {
            return Some((Kind::Reflected, a, d + n * (2.0 * cos_i), f));
        }
        // Snell's law in: d/η + (cos θ/η − cos θ_t) n.
        let inv = 1.0 / eta;
        let cos_t = (1.0 - inv * inv * (1.0 - cos_i * cos_i)).max(0.0).sqrt();
        let mut inside = (d * inv + n * (inv * cos_i - cos_t)).normalize();
        let mut p = a;
        let mut k = 0u8;
        loop {
            let q = p + inside * (-2.0 * (p - c).dot(inside));
            if !lens.hollow && !self.clear_between((p, p - c), q, traced) {
                return None;
            }
            let nq = (q - c).normalize();
            if rng.next_f32() >= f {
                // Snell's law out, back to the angle of incidence.
                let cos = inside.dot(nq);
                let out = (inside * eta + nq * (cos_i - eta * cos)).normalize();
                return Some((Kind::Through(k), q, out, f));
            }
            k += 1;
            if k > MOST_INSIDE {
                return None;
            }
            inside = inside - nq * (2.0 * inside.dot(nq));
            p = q;
        }
    }

    /// The light of the path's light subpath (`Caustic`) that reaches
    /// the path's vertex `point` of `bsdf` (where it draws bounces from
    /// `guide`; `wi` towards where it came from): straight, and by way of
    /// each ball for the kinds of [`THROUGH`]. Each is weighed against the
    /// estimator and BSDF sampling at the subpath's vertex, and tested for
    /// occlusion; counts the rays it traces in `traced`.
    pub(in crate::integrator) fn join_caustic<const K: usize>(
        &self,
        path: &mut PathState<K>,
        point: &ScatterPoint,
        at_u: (&Bsdf, Option<&DTree>, Vec3),
        traced: &mut u32,
    ) -> SampledSpectrum<K> {
        let mut sum = SampledSpectrum::splat(0.0);
        let Caustic::At(lv) = path.caustic else {
            return sum;
        };
        let to = lv.v.p - point.p;
        let dist2 = to.length_squared();
        // Each join makes a path of the depth the camera path's would
        // reach that way, and is made only where that is within the
        // depth: there, and only there, the other strategies find it too.
        let chain = lv.kind.segments();
        if dist2.is_finite() && dist2 > 0.0 && self.within(path.depth + 1 + chain) {
            let dir = to / dist2.sqrt();
            let per_area = lv.v.ng.dot(dir).abs() / dist2;
            let leg = (dir, dir, per_area, SampledSpectrum::splat(1.0));
            let light = self.join_leg(path, point, at_u, &lv, leg);
            if !light.is_zero() && self.clear_between((point.p, point.ng), lv.v.p, traced) {
                sum += light;
            }
        }
        for (li, lens) in self.lenses.list.iter().enumerate() {
            let Some(search) = lens.ball.search(point.p, lv.v.p) else {
                continue;
            };
            for kind in THROUGH {
                if !self.within(path.depth + kind.segments() + chain) {
                    continue;
                }
                let tint = self.lens_tint(lens, kind, &path.now);
                for leg in search.paths(kind).iter() {
                    let fr = fresnel(kind, reflected(leg.cos_in, lens.ball.eta));
                    let per_area = fr * leg.spread * lv.v.ng.dot(leg.out).abs();
                    let run = (leg.dir, leg.out, per_area, tint);
                    let light = self.join_leg(path, point, at_u, &lv, run);
                    let at = (point.p, point.ng);
                    if !light.is_zero()
                        && self.passage_clear(at, &self.lenses.list[li], kind, leg, lv.v.p, traced)
                    {
                        sum += light;
                    }
                }
            }
        }
        sum
    }

    /// The light of `lv` reaching `point` along a leg that leaves it along
    /// `dir` and reaches the light vertex along `arrive`, whose density
    /// per area there per unit density of `dir` (dω/dA, times the
    /// dielectric's choices on the way) is `per_area` and which keeps
    /// `tint` of the light; weighed, not tested for occlusion.
    fn join_leg<const K: usize>(
        &self,
        path: &PathState<K>,
        point: &ScatterPoint,
        (bsdf, guide, wi): (&Bsdf, Option<&DTree>, Vec3),
        lv: &LightVertex,
        (dir, arrive, per_area, tint): (Vec3, Vec3, f32, SampledSpectrum<K>),
    ) -> SampledSpectrum<K> {
        let now = &path.now;
        let wo = point.frame.to_local(dir);
        let f_u = bsdf.eval(now, point.at, wi, wo, Transport::Radiance);
        if f_u.is_zero() || !per_area.is_finite() || per_area <= 0.0 {
            return SampledSpectrum::splat(0.0);
        }
        let p_u = bsdf.pdf_at(now, point.at, wi, wo);
        let a = self.bounce_pdf(guide, bsdf, point.p, dir, p_u) * per_area;
        let light = self.light_vertex_sends(now, lv, arrive, a);
        path.beta * f_u * tint * light * per_area
    }

    /// The light of `lv` that its vertex v sends back along `arrive` (the
    /// direction a leg from another vertex reaches v along), per unit of
    /// the leg's geometry there; weighed against the estimator and BSDF
    /// sampling at v, given `a`, the density per area at v of the other
    /// end's bounce (or the camera's ray) that would reach v along the leg.
    pub(super) fn light_vertex_sends<const K: usize>(
        &self,
        now: &SampledWavelengths<K>,
        lv: &LightVertex,
        arrive: Vec3,
        a: f32,
    ) -> SampledSpectrum<K> {
        let zero = SampledSpectrum::splat(0.0);
        let scene = self.scene;
        let bsdf_v = &scene.materials[lv.material as usize];
        let (wi_v, wo_v) = (lv.v.frame.to_local(-arrive), lv.v.frame.to_local(lv.back));
        let f_v = bsdf_v.eval(now, lv.v.at, wi_v, wo_v, Transport::Radiance);
        let Light::Area(area) = &scene.lights[lv.light as usize] else {
            return zero;
        };
        let (n_y, uv_y) = lv.y;
        let le = area.radiance(now, uv_y, n_y, lv.leaves);
        if f_v.is_zero() || le.is_zero() {
            return zero;
        }
        let lens = &self.lenses.list[lv.lens as usize];
        let tint = self.lens_tint(lens, lv.kind, now);
        // The other two strategies' densities, per area at v.
        let ng_v = lv.v.ng;
        let facing = if ng_v.dot(arrive) > 0.0 { -ng_v } else { ng_v };
        let guide_v = self.surface_guide(self.spot(lv.v.p, Some(facing)), bsdf_v);
        let p_v = bsdf_v.pdf_at(now, lv.v.at, wi_v, wo_v);
        let p_bsdf = self.bounce_pdf(guide_v, bsdf_v, lv.v.p, lv.back, p_v) * lv.fr;
        let w = power_heuristic(lv.p_join, a * lv.p_nee.hypot(p_bsdf));
        f_v * le * tint * (lv.fr / lv.p_join * w)
    }

    /// This strategy's density of a path the estimator or BSDF sampling
    /// found at `x` (geometric normal `n`) by way of lens `lens` to lamp
    /// `light` at `y` (normal `n_y`), leaving `x` along `dir` and
    /// reaching `y` along `out`, keeping `fr` of the light; per steradian
    /// at `x`, given `a`, the density per area at `x` of the bounce that
    /// reached it (0 where no vertex before could join it).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn join_density(
        &self,
        a: f32,
        run: (usize, u16, f32),
        (n, dir): (Vec3, Vec3),
        at_y: (Vec3, Vec3, Vec3),
    ) -> f32 {
        if a <= 0.0 {
            return 0.0;
        }
        let p = self.join_pdf(run, n.dot(dir).abs(), at_y) / a;
        if p.is_finite() {
            p
        } else {
            0.0
        }
    }

    /// The density of drawing a light subpath from lamp `light` at `y`
    /// (normal `n_y`) by way of lens `lens` along a chain that reaches `y`
    /// along `out`, keeps `fr` of the light and meets its other end at
    /// cosine `cos_x`: per area there and per steradian of the chain. The
    /// one evaluation both the draw and the other strategies' weights use.
    fn join_pdf(
        &self,
        (light, lens, fr): (usize, u16, f32),
        cos_x: f32,
        (y, n_y, out): (Vec3, Vec3, Vec3),
    ) -> f32 {
        let Some(pick) = self.lenses.pick.as_ref() else {
            return 0.0;
        };
        let Light::Area(area) = &self.scene.lights[light] else {
            return 0.0;
        };
        let Some((_, one_minus)) = seen(&self.lenses.list[lens as usize], y) else {
            return 0.0;
        };
        let p_y = JOIN_SHARE * pick.probability(light) / area.area();
        let p_dir = uniform_cone_pdf(one_minus) / self.lenses.list.len() as f32;
        p_y * p_dir * fr * cos_x / out.dot(n_y).abs()
    }
}

/// The densities a vertex's bounce gives the next one per area, for
/// joining: `pdf` per steradian at `from` towards `p` (geometric normal
/// `ng`); 0 where `joins` is false.
pub(in crate::integrator) fn area_density(
    joins: bool,
    pdf: f32,
    from: Vec3,
    p: Vec3,
    ng: Vec3,
) -> f32 {
    if !joins {
        return 0.0;
    }
    let to = p - from;
    let d2 = to.length_squared();
    let a = pdf * ng.dot(to).abs() / (d2 * d2.sqrt());
    if a.is_finite() {
        a
    } else {
        0.0
    }
}
