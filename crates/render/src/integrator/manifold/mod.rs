//! Manifold next-event estimation through glass balls (Hanika, Droske &
//! Fascione 2015): light that reaches a diffuse point only through a
//! smooth dielectric ball — the caustic under it, and that caustic seen in
//! a mirror, a metal or the ball itself — found by next-event estimation
//! rather than by a BSDF-sampled path that happens to refract onto a lamp.
//!
//! At a vertex `x` the path tracer picks a lamp as for next-event
//! estimation, a point `y` uniformly on its area, and then every path
//! x → ball → ball → y (`ball.rs`, solved exactly). Each path's density
//! in the solid angle at `x` is p_A(y) · dA_y/dω, and it is weighed by
//! the power heuristic against the same path drawn by BSDF sampling at
//! `x` and the dielectric's choices to refract twice. That path is
//! recognised when it reaches the lamp (`Passage`) and weighed in turn; a
//! path the ball's search would miss keeps its whole weight, so the sum is
//! unbiased whatever the search finds.
//!
//! Which balls: top-level spheres of a smooth `dielectric` whose index and
//! transmittance do not vary (a dispersive ball splits the cluster, which
//! the path tracer reaches by sampling), that emit nothing, in a scene
//! without media. Only area lights are reached this way. The bidirectional
//! tracer does not use it.

mod ball;
mod connect;
mod seen;
mod sweep;

use ball::{Ball, Kind, Paths, Refracted};
pub(super) use connect::{area_density, Caustic};

use scotopia_color::{SampledSpectrum, SampledWavelengths};

use super::direct::{power_heuristic, spawn};
use super::path::ScatterPoint;
use super::Renderer;
use crate::accel::Aabb;
use crate::bsdf::{fresnel_dielectric, Bsdf, Transport};
use crate::geometry::{Hit, Shape, Sphere};
use crate::guiding::DTree;
use crate::light::Light;
use crate::math::{Transform, Vec3};
use crate::sampling::distribution::Distribution1D;
use crate::scene::Scene;
use crate::texture::TexPoint;

/// The probability the estimator runs for each kind of path
/// (`Kind::SEARCHED`'s order).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Shares(pub [f32; Kind::SEARCHED.len()]);

impl Shares {
    /// Whether it runs at all.
    pub fn any(&self) -> bool {
        self.0.iter().any(|&s| s > 0.0)
    }

    /// These shares at a vertex from which a path may have `room` more
    /// segments: none for the kinds whose paths would be longer, so that
    /// the estimator finds a path exactly where BSDF sampling can.
    pub fn fitting(self, room: i32) -> Shares {
        let mut fit = self;
        for (share, kind) in fit.0.iter_mut().zip(Kind::SEARCHED) {
            if kind.segments() > room {
                *share = 0.0;
            }
        }
        fit
    }

    /// Whether it runs for some kinds only by chance.
    pub fn by_chance(&self) -> bool {
        self.0.iter().any(|&s| s > 0.0 && s < 1.0)
    }

    fn of(&self, kind: Kind) -> f32 {
        Kind::SEARCHED
            .iter()
            .position(|&k| k == kind)
            .map_or(0.0, |i| self.0[i])
    }
}

/// The probability the estimator runs for each kind of path, at every
/// vertex where it runs. The choice is drawn from the path's own stream
/// and the estimator's density in MIS is scaled by it, which keeps the
/// sum unbiased (one-sample MIS, Veach 1997 §9.2.4). Measured on
/// `glass-and-metals.xml` (docs/caustics.md, paired renders of the same
/// seeds, so that only the estimator's share of the noise differs):
///
/// - light through the ball, straight or with one reflection inside:
///   always. It is the caustic.
/// - reflected off the ball: a tenth of the time. A convex mirror spreads
///   that light thin, so it is faint, and the search and two shadow rays
///   cost as much as for the caustic: run always it took a fifth of the
///   render's time for no change in relMSE (0.0771 against 0.0772 over 40
///   seeds at 32 spp; it once ran always where the vertex is seen
///   sharply, a quarter of the time elsewhere).
/// - two and three reflections inside: a twentieth of the time. Their
///   light is fainter still (F², F³); what they are wanted for is MIS. A
///   BSDF-sampled path of these kinds is chosen with the dielectric's
///   probability F² or F³ and then carries the lamp's whole radiance, a
///   firefly, unless weighed against an estimator that runs there; at a
///   twentieth the estimator's density still outweighs BSDF sampling's by
///   far where those fireflies are.
pub(super) const SHARES: Shares = Shares([0.1, 1.0, 1.0, 0.05, 0.05]);

/// The estimator's shares at a vertex that a light subpath through a ball
/// can be joined to (`connect`: reached by a bounce that is not a delta
/// from a surface): a tenth of [`SHARES`]. There the join finds the
/// caustic's light that the estimator would, and weighs BSDF sampling's
/// paths through the ball as the estimator did; the estimator is still
/// wanted a little, for MIS (never run there, one seed's relMSE was 62).
/// Measured on `glass-and-metals.xml`, 48 paired seeds at 32 spp: relMSE
/// 0.0559 against 0.0561 for the full shares, and 0.607 s per image
/// against 0.716 (relMSE × s 0.0336 against 0.0401); a twentieth and a
/// fifth of them measured 0.0331 and 0.0343.
pub(super) const SHARES_JOINED: Shares = Shares([0.01, 0.1, 0.1, 0.005, 0.005]);

/// The segments of the shortest path by way of a ball from a vertex to the
/// next (a reflection off it: [`Kind::segments`]).
pub(super) const SHORTEST: i32 = 2;

/// The estimator's shares at a vertex reached with density `joined` per
/// area (`Passage::joined`; 0 where no light subpath could be joined to
/// it).
pub(super) fn shares_at(joined: f32) -> Shares {
    if joined > 0.0 {
        SHARES_JOINED
    } else {
        SHARES
    }
}

/// A ball light is found through: its shape (the scene's number; in the
/// instance `instance` when it belongs to a shape group), its material
/// and where it is.
#[derive(Debug, Clone)]
struct Lens {
    shape: u32,
    instance: Option<u32>,
    material: u32,
    ball: Ball,
    /// Whether no other surface reaches inside the ball, so that a path's
    /// chords inside it need no shadow rays.
    hollow: bool,
}

/// The scene's glass balls.
#[derive(Debug, Clone, Default)]
pub struct Lenses {
    list: Vec<Lens>,
    /// The lamps light subpaths through the balls start from, by their
    /// radiant power (`connect`): area lights only.
    pick: Option<Distribution1D>,
}

impl Lenses {
    /// The balls of `scene` light is found through (the module's list),
    /// top-level or placed by an instance whose transform keeps a ball a
    /// ball (turns, a uniform scale and a shift).
    pub fn of(scene: &Scene) -> Self {
        if !scene.media.is_empty() {
            return Self::default();
        }
        let geometry = &scene.geometry;
        let mut list: Vec<Lens> = geometry
            .shapes
            .iter()
            .enumerate()
            .filter_map(|(i, shape)| {
                let (material, eta, s) = lens_material(scene, i as u32, shape)?;
                Some(Lens {
                    shape: i as u32,
                    instance: None,
                    material,
                    ball: Ball::new(s.center, s.radius, eta),
                    hollow: false,
                })
            })
            .collect();
        for (j, instance) in geometry.instances().iter().enumerate() {
            let group = instance.group();
            let Some(scale) = similarity(instance.world_from_object()) else {
                continue;
            };
            for (k, shape) in group.shapes().iter().enumerate() {
                let i = group.first_shape() + k as u32;
                let Some((material, eta, s)) = lens_material(scene, i, shape) else {
                    continue;
                };
                let center = instance.world_from_object().point(s.center);
                list.push(Lens {
                    shape: i,
                    instance: Some(j as u32),
                    material,
                    ball: Ball::new(center, s.radius * scale, eta),
                    hollow: false,
                });
            }
        }
        let hollow = hollows(scene, &list);
        for (lens, hollow) in list.iter_mut().zip(hollow) {
            lens.hollow = hollow;
        }
        let power = |l: &Light| match l {
            Light::Area(a) => a.power().watts as f32,
            _ => 0.0,
        };
        let weights: Vec<f32> = scene.lights.iter().map(power).collect();
        let lit = !list.is_empty() && weights.iter().any(|&w| w > 0.0 && w.is_finite());
        let pick = lit.then(|| Distribution1D::new(weights));
        Self { list, pick }
    }

    /// Whether camera paths join light subpaths through the balls.
    pub fn joined(&self) -> bool {
        self.pick.is_some()
    }

    pub fn is_empty(&self) -> bool {
        self.list.is_empty()
    }

    /// The lens of a shape a ray hit, by its index in the list.
    fn at(&self, hit: &Hit) -> Option<u16> {
        let same = |l: &Lens| l.shape == hit.shape && l.instance == hit.instance;
        let i = self.list.iter().position(same)?;
        Some(i as u16)
    }
}

/// The material of shape `i`, its index ratio and the sphere, if the shape
/// is a ball light is found through (the module's list).
fn lens_material<'s>(scene: &Scene, i: u32, shape: &'s Shape) -> Option<(u32, f32, &'s Sphere)> {
    let Shape::Sphere(s) = shape else {
        return None;
    };
    let material = *scene.shape_material.get(i as usize)?;
    let Some(Bsdf::Dielectric(d)) = scene.materials.get(material as usize) else {
        return None;
    };
    let eta = d.ior.eta(&SampledWavelengths::<1>::new([550.0], [1.0]))[0];
    let plain = !d.ior.dispersive()
        && !d.specular_transmittance.is_varying()
        && !d.specular_reflectance.is_varying();
    let dark = scene
        .shape_light
        .get(i as usize)
        .is_none_or(|l| l.is_none());
    (plain && dark && !s.flip && eta.is_finite() && eta > 1.0).then_some((material, eta, s))
}

/// For each lens, whether nothing but the lens itself reaches inside its
/// ball: no primitive's box of another top-level shape, and no
/// instance's box (an instanced lens's own instance included:
/// conservative). A box that only touches the ball (the floor a ball
/// rests on) cannot block a chord inside it. One pass over the boxes,
/// each built once.
fn hollows(scene: &Scene, lenses: &[Lens]) -> Vec<bool> {
    let geometry = &scene.geometry;
    let mut hollow = vec![true; lenses.len()];
    let mut mark = |b: Aabb, own: Option<u32>| {
        for (h, lens) in hollow.iter_mut().zip(lenses) {
            let itself = lens.instance.is_none() && own == Some(lens.shape);
            *h &= itself || !reaches_inside(&lens.ball, b);
        }
    };
    for (i, shape) in geometry.shapes.iter().enumerate() {
        for k in 0..shape.primitive_count() {
            mark(shape.bounds(k), Some(i as u32));
        }
    }
    for instance in geometry.instances() {
        mark(instance.bounds(), None);
    }
    hollow
}

/// Whether the box `b` reaches inside `ball`, beyond touching it.
fn reaches_inside(ball: &Ball, b: Aabb) -> bool {
    let nearest = ball.center.max(b.min).min(b.max);
    (nearest - ball.center).length() < ball.radius * (1.0 - 1e-3)
}

/// The scale of a transform that keeps balls balls (orthogonal axes of
/// one length, not mirrored), or `None`.
fn similarity(t: &Transform) -> Option<f32> {
    let [x, y, z] = [
        Vec3::new(1.0, 0.0, 0.0),
        Vec3::new(0.0, 1.0, 0.0),
        Vec3::new(0.0, 0.0, 1.0),
    ]
    .map(|e| t.vector(e));
    let s = x.length();
    let tol = 1e-5 * s;
    let square = (y.length() - s).abs() <= tol && (z.length() - s).abs() <= tol;
    let orthogonal =
        x.dot(y).abs() <= tol * s && y.dot(z).abs() <= tol * s && z.dot(x).abs() <= tol * s;
    let turned = x.cross(y).dot(z) > 0.0;
    (s > 0.0 && square && orthogonal && turned).then_some(s)
}

/// How far a path has followed a passage by way of a lens since it last
/// scattered where the estimator runs.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
enum Stage {
    #[default]
    None,
    /// It left `x` by sampling a lobe that is not a delta.
    Left,
    /// It refracted into lens `lens` and was reflected inside this many
    /// times.
    In(u8),
    /// It left the lens: a path of this kind.
    Out(Kind),
}

/// What the path tracer keeps of a BSDF-sampled path's way through a lens,
/// to weigh it against the estimator when it reaches a lamp.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Passage {
    stage: Stage,
    lens: u16,
    /// The vertex it left, its geometric normal and direction, and the
    /// density of the whole passage: the direction's at `x` times the
    /// dielectric's choices to refract.
    x: Vec3,
    n: Vec3,
    dir: Vec3,
    pdf: f32,
    /// The probability the estimator ran at `x`, by kind.
    shares: Shares,
    /// The density per area at `x` of the bounce that reached it, where a
    /// light subpath could be joined from there (`connect`); else 0.
    joined: f32,
}

impl Passage {
    /// The path left `x` (normal `n`) along `dir`, drawn with density
    /// `pdf`, where the estimator runs with probabilities `shares` and
    /// light subpaths are joined with density `joined` per area at `x`.
    pub(super) fn left(
        (x, n): (Vec3, Vec3),
        dir: Vec3,
        pdf: f32,
        (shares, joined): (Shares, f32),
    ) -> Self {
        Self {
            stage: Stage::Left,
            lens: 0,
            x,
            n,
            dir,
            pdf,
            shares,
            joined,
        }
    }
}

/// The fraction of light a smooth interface of relative index `eta`
/// reflects at incidence cosine `cos` (the side by its sign).
fn reflected(cos: f32, eta: f32) -> f32 {
    fresnel_dielectric(cos, eta).0
}

/// What a path of `kind` keeps of the light at its interfaces, each of
/// which reflects `f`: F per reflection, 1 − F per transmission. It is
/// also the probability that the dielectric's sampling chose that way.
fn fresnel(kind: Kind, f: f32) -> f32 {
    let (r, t) = kind.events();
    f.powi(r as i32) * (1.0 - f).powi(t as i32)
}

impl Renderer<'_> {
    /// Light of lamp `choice` (chosen with its probability as for
    /// next-event estimation at `point`; `u`: a point on it) that reaches
    /// `point` by way of each glass ball, weighed against BSDF sampling,
    /// and tested for occlusion, for the kinds whose share of `shares`
    /// exceeds `u`; `throughput` is the path's weight before this vertex,
    /// `joined` the density per area here of the bounce that reached it
    /// where a light subpath could be joined from there (`connect`).
    /// Counts the rays it traces in `traced`.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn through_lenses<const K: usize>(
        &self,
        now: &SampledWavelengths<K>,
        throughput: &SampledSpectrum<K>,
        point: &ScatterPoint,
        (bsdf, guide, wi): (&Bsdf, Option<&DTree>, Vec3),
        ((light, p_choice), (shares, u)): ((usize, f32), (Shares, f32)),
        ([u_select, u0, u1], joined): ([f32; 3], f32),
        traced: &mut u32,
    ) -> SampledSpectrum<K> {
        let mut sum = SampledSpectrum::splat(0.0);
        let Light::Area(area) = &self.scene.lights[light] else {
            return sum;
        };
        let shapes = &self.scene.geometry.shapes;
        let Some(y) = shapes[area.shape as usize].sample_area(area.triangles(), u_select, [u0, u1])
        else {
            return sum;
        };
        let p_light = p_choice / area.area();
        let ScatterPoint {
            p: x,
            ng,
            frame,
            at,
        } = *point;
        for (li, lens) in self.lenses.list.iter().enumerate() {
            let Some(search) = lens.ball.search(x, y.p) else {
                continue;
            };
            for (kind, share) in Kind::SEARCHED.into_iter().zip(shares.0) {
                if u >= share {
                    continue;
                }
                let found = search.paths(kind);
                if found.iter().next().is_none() {
                    continue;
                }
                let p_area = share * p_light;
                let tint = self.lens_tint(lens, kind, now);
                for path in found.iter() {
                    let wo = frame.to_local(path.dir);
                    let f = bsdf.eval(now, at, wi, wo, Transport::Radiance);
                    let le = area.radiance(now, y.uv, y.n, -path.out);
                    if f.is_zero() || le.is_zero() {
                        continue;
                    }
                    // Densities per steradian at x of reaching y this way:
                    // by the light's point, and by the BSDF's direction and
                    // the dielectric's choices.
                    let spread = path.spread * path.out.dot(y.n).abs();
                    let fr = fresnel(kind, reflected(path.cos_in, lens.ball.eta));
                    let p_bsdf = bsdf.pdf_at(now, at, wi, wo);
                    let p_bsdf = self.bounce_pdf(guide, bsdf, x, path.dir, p_bsdf) * fr;
                    let at_y = (y.p, y.n, path.out);
                    let run = (light, li as u16, fr);
                    let p_join = self.join_density(joined, run, (ng, path.dir), at_y);
                    let w = power_heuristic(p_area / spread, p_bsdf.hypot(p_join));
                    let light = *throughput * f * le * tint * (fr * w * spread / p_area);
                    if light.is_zero()
                        || !self.passage_clear((x, ng), lens, kind, path, y.p, traced)
                    {
                        continue;
                    }
                    sum += light;
                }
            }
        }
        sum
    }

    /// The lens's specular reflectance and transmittance, once for each
    /// interface of a path of `kind`.
    fn lens_tint<const K: usize>(
        &self,
        lens: &Lens,
        kind: Kind,
        now: &SampledWavelengths<K>,
    ) -> SampledSpectrum<K> {
        let Bsdf::Dielectric(d) = &self.scene.materials[lens.material as usize] else {
            return SampledSpectrum::splat(0.0);
        };
        let (r, t) = kind.events();
        let reflectance = d.specular_reflectance.eval(now, TexPoint::default());
        let transmittance = d.specular_transmittance.eval(now, TexPoint::default());
        let mut tint = SampledSpectrum::splat(1.0);
        for _ in 0..r {
            tint *= reflectance;
        }
        for _ in 0..t {
            tint *= transmittance;
        }
        tint
    }

    /// Whether nothing blocks `path`'s segments from `x` (normal `ng`)
    /// by way of `lens` to `y` (inside it only where it is not hollow).
    #[allow(clippy::too_many_arguments)]
    fn passage_clear(
        &self,
        (x, ng): (Vec3, Vec3),
        lens: &Lens,
        kind: Kind,
        path: &Refracted,
        y: Vec3,
        traced: &mut u32,
    ) -> bool {
        let clear = |from: Vec3, n: Vec3, to: Vec3, traced: &mut u32| {
            self.clear_between((from, n), to, traced)
        };
        let normal = |p: Vec3| p - lens.ball.center;
        let (a, m, b) = (path.entry, path.mid, path.exit);
        let inside = match kind {
            _ if lens.hollow => true,
            Kind::Reflected => true,
            Kind::Through(0) => clear(a, normal(a), b, traced),
            Kind::Through(k) => {
                let turn = chord_turn(lens.ball.center, a, m);
                let mut p = a;
                let mut open = true;
                for i in 0..=k {
                    let next = if i == k { b } else { turn(p) };
                    open = open && clear(p, normal(p), next, traced);
                    p = next;
                }
                open
            }
        };
        clear(x, ng, a, traced) && inside && clear(b, normal(b), y, traced)
    }

    /// Whether nothing blocks the segment from `from` (on a surface of
    /// normal `n`) to `to`; counts its ray in `traced`.
    fn clear_between(&self, (from, n): (Vec3, Vec3), to: Vec3, traced: &mut u32) -> bool {
        let unit = self.scene.geometry.offset_unit();
        let mut ray = spawn(from, n, (to - from).normalize(), unit);
        let left = (to - ray.o).length();
        ray.d = (to - ray.o) / left;
        ray.t_max = left * (1.0 - 1e-4);
        *traced += 1;
        !self.scene.geometry.occluded(&ray)
    }

    /// Follows a path's passage by way of a lens at a delta bounce on
    /// `hit` (at `p`), from `wo` (towards where it came from) to `d`.
    pub(super) fn follow_passage(
        &self,
        passage: &mut Passage,
        hit: &Hit,
        p: Vec3,
        wo: Vec3,
        d: Vec3,
    ) {
        let lens = self.lenses.at(hit);
        let Some(i) = lens.filter(|&i| passage.stage == Stage::Left || i == passage.lens) else {
            passage.stage = Stage::None;
            return;
        };
        let ball = &self.lenses.list[i as usize].ball;
        let n = p - ball.center;
        let (outside, leaves) = (wo.dot(n) > 0.0, d.dot(n) > 0.0);
        let f = reflected(wo.dot(n.normalize()), ball.eta);
        let (stage, chose) = match (passage.stage, outside, leaves) {
            (Stage::Left, true, true) => (Stage::Out(Kind::Reflected), f),
            (Stage::Left, true, false) => (Stage::In(0), 1.0 - f),
            (Stage::In(k), false, false) => (Stage::In(k.saturating_add(1)), f),
            (Stage::In(k), false, true) => (Stage::Out(Kind::Through(k)), 1.0 - f),
            _ => (Stage::None, 1.0),
        };
        passage.stage = stage;
        passage.lens = i;
        passage.pdf *= chose;
    }

    /// The MIS weight of a BSDF-sampled path that reached area light
    /// `light` at `y` (normal `n`, arriving along `out`) along its
    /// `passage`: 1 unless the estimator at its last vertex finds the same
    /// path or a light subpath could have been joined to that vertex.
    pub(super) fn passage_weight(
        &self,
        passage: &Passage,
        light: usize,
        (y, n, out): (Vec3, Vec3, Vec3),
    ) -> f32 {
        let Stage::Out(kind) = passage.stage else {
            return 1.0;
        };
        let Light::Area(area) = &self.scene.lights[light] else {
            return 1.0;
        };
        if !Kind::SEARCHED.contains(&kind) {
            return 1.0;
        }
        let ball = &self.lenses.list[passage.lens as usize].ball;
        let found = ball.paths(kind, passage.x, y);
        let (p_est, cos_in, out) = match nearest(&found, passage.dir) {
            Some(path) => {
                let p_choice = self.lights.probability(passage.x, Some(passage.n), light);
                let p_area = passage.shares.of(kind) * p_choice / area.area();
                let spread = path.spread * path.out.dot(n).abs();
                (p_area / spread, path.cos_in, path.out)
            }
            // A path traced in f32 can land a hair beyond the caustic's
            // fold, where the search finds no root: the estimator cannot
            // draw it, but a light subpath, traced too, can.
            None => match ball.entry_cos(passage.x, passage.dir) {
                Some(cos_in) => (0.0, cos_in, out),
                None => return 1.0,
            },
        };
        let fr = fresnel(kind, reflected(cos_in, ball.eta));
        let run = (light, passage.lens, fr);
        let at_x = (passage.n, passage.dir);
        let p_join = self.join_density(passage.joined, run, at_x, (y, n, out));
        power_heuristic(passage.pdf, p_est.hypot(p_join))
    }

    /// The density per area at `p` (geometric normal `ng`) of a path that
    /// reached it along `passage` by way of a ball, from a vertex that
    /// joins light subpaths there by way of the ball (`connect::THROUGH`):
    /// the passage's density times the leg's dω/dA; 0 for any other.
    pub(super) fn joined_through(&self, passage: &Passage, p: Vec3, ng: Vec3) -> f32 {
        let Stage::Out(kind) = passage.stage else {
            return 0.0;
        };
        if !connect::THROUGH.contains(&kind) {
            return 0.0;
        }
        let ball = &self.lenses.list[passage.lens as usize].ball;
        let Some(leg) = along(ball, kind, (passage.x, p), passage.dir) else {
            return 0.0;
        };
        let a = passage.pdf * leg.spread * ng.dot(leg.out).abs();
        if a.is_finite() {
            a
        } else {
            0.0
        }
    }
}

/// The path of `found` that is the one leaving along `dir`, if any: the
/// nearest, when it is near enough. A path traced in f32 lands a hair off
/// the exact one, which the caustic's focusing magnifies.
fn nearest(found: &Paths, dir: Vec3) -> Option<&Refracted> {
    let off = |p: &Refracted| p.dir.cross(dir).length_squared();
    let best = found.iter().min_by(|a, b| off(a).total_cmp(&off(b)));
    best.filter(|p| off(p) < SAME * SAME && p.dir.dot(dir) > 0.0)
}

/// The path of `kind` from `x` by way of `ball` to `y` that leaves `x`
/// along `dir` (a path traced, not searched for), if the search's root
/// there is it.
fn along(ball: &Ball, kind: Kind, (x, y): (Vec3, Vec3), dir: Vec3) -> Option<Refracted> {
    let leg = ball.search(x, y)?.path_along(kind, dir)?;
    (leg.dir.dot(dir) > 1.0 - 0.5 * SAME * SAME).then_some(leg)
}

/// The turn about the ball's centre `c` that takes a path's entry `a` to
/// its first reflection inside `m`, in the path's plane. Each chord
/// inside turns by the same angle, so the reflections inside are the
/// entry turned once, twice, …, and the exit is the last. Along a
/// diameter the turn is by π, about no axis in particular.
fn chord_turn(c: Vec3, a: Vec3, m: Vec3) -> impl Fn(Vec3) -> Vec3 {
    let (from, to) = (a - c, m - c);
    let normal = from.cross(to);
    let axis = match normal.length_squared() > 0.0 {
        true => normal.normalize(),
        false => Vec3::ZERO,
    };
    let cos = from.normalize().dot(to.normalize());
    let sin = normal.length() / (from.length() * to.length());
    move |p: Vec3| {
        let v = p - c;
        c + v * cos + axis.cross(v) * sin
    }
}

/// How close (radians) the nearest path found must be to a sampled one to
/// be it: far above the error of tracing in f32, which the caustic's
/// focusing magnifies (at 2e-4 a share of the caustic's sampled paths
/// went unrecognised and were counted twice: 8 % too bright, 40 % in its
/// pixels), and below the angle between distinct paths but where two
/// merge at the caustic's edge.
const SAME: f32 = 2e-2;

#[cfg(test)]
mod tests {
    use super::*;

    /// At a vertex with room for n more segments the estimator runs only
    /// for the kinds whose paths to the lamp have at most n: a reflection
    /// off the ball 2 (vertex, ball, lamp), through it 3 and one more per
    /// reflection inside.
    #[test]
    fn the_estimator_runs_for_the_paths_that_fit_the_depth() {
        let all = SHARES;
        assert_eq!(all.fitting(1), Shares::default());
        assert_eq!(all.fitting(2), Shares([0.1, 0.0, 0.0, 0.0, 0.0]));
        assert_eq!(all.fitting(3), Shares([0.1, 1.0, 0.0, 0.0, 0.0]));
        assert_eq!(all.fitting(5), Shares([0.1, 1.0, 1.0, 0.05, 0.0]));
        assert_eq!(all.fitting(6), all);
        assert_eq!(all.fitting(i32::MAX), all);
        assert!(!all.fitting(SHORTEST - 1).any() && all.fitting(SHORTEST).any());
    }

    /// Turning the entry by the first chord's angle, once per chord, lands
    /// on the exit the search traced, for every kind through the ball.
    #[test]
    fn the_chords_inside_are_the_entry_turned() {
        let ball = Ball::new(Vec3::new(0.0, 0.25, 0.0), 0.25, 1.5);
        let (x, y) = (Vec3::new(0.6, 0.05, 0.3), Vec3::new(-0.3, 1.6, -0.3));
        let mut checked = 0;
        for k in 1..=3u8 {
            for (dx, dz) in [(0.0, 0.0), (0.4, -0.2), (-0.5, 0.1), (0.2, 0.6)] {
                let y = y + Vec3::new(dx, 0.0, dz);
                for p in ball.paths(Kind::Through(k), x, y).iter() {
                    let turn = chord_turn(ball.center, p.entry, p.mid);
                    let mut q = p.entry;
                    for _ in 0..=k {
                        q = turn(q);
                    }
                    assert!(
                        (q - p.exit).length() < 1e-4,
                        "{k}: {q:?} against {:?}",
                        p.exit
                    );
                    checked += 1;
                }
            }
        }
        assert!(checked >= 6, "only {checked} paths");
    }

    /// The floor a ball rests on touches it and leaves it hollow; a box
    /// inside it, or one that cuts into it, does not.
    #[test]
    fn only_boxes_that_reach_inside_a_ball_fill_it() {
        let ball = Ball::new(Vec3::new(0.0, 0.25, 0.0), 0.25, 1.5);
        let b = |lo: [f32; 3], hi: [f32; 3]| Aabb {
            min: Vec3::new(lo[0], lo[1], lo[2]),
            max: Vec3::new(hi[0], hi[1], hi[2]),
        };
        let floor = b([-2.0, 0.0, -2.0], [2.0, 0.0, 2.0]);
        let wall = b([-2.0, 0.0, -1.2], [2.0, 2.0, -1.2]);
        let inside = b([-0.01, 0.24, -0.01], [0.01, 0.26, 0.01]);
        let cutting = b([0.2, 0.2, -0.1], [0.6, 0.3, 0.1]);
        assert!(!reaches_inside(&ball, floor) && !reaches_inside(&ball, wall));
        assert!(reaches_inside(&ball, inside));
        assert!(reaches_inside(&ball, cutting));
    }
}
