//! The strategies (s, t): joining the first s vertices of the light
//! subpath to the first t of the camera subpath, each contribution with
//! its MIS weight. s = 0: the camera path found a light; s = 1: a light
//! point sampled afresh for the camera vertex (next-event estimation);
//! t = 1: the light vertex seen through a lens point, splatted where it
//! lands on the film (light tracing).

use scotopia_color::{SampledSpectrum, SampledWavelengths};

use super::clusters::Lanes;
use super::mis::{self, Connection};
use super::vertex::{Kind, Vertex};
use crate::bsdf::{Bsdf, Transport};
use crate::integrator::direct::{Crossing, DirectSample};
use crate::integrator::light_choice::ClusterChoice;
use crate::integrator::Renderer;
use crate::light::Light;
use crate::math::{offset_ray_origin, Ray, Vec3};
use crate::sampling::sobol::Sampler;
use crate::sampling::splitmix::SplitMix;
use crate::texture::TexPoint;

/// Relative margin a connection ray stops short of its far end.
const CONNECT_EPSILON: f32 = 1e-4;

/// What one sample's strategies share.
pub(super) struct Subpaths<'p, const K: usize> {
    pub light: &'p [Vertex<K>],
    pub camera: &'p [Vertex<K>],
    /// The camera cluster, on which every contribution is evaluated.
    pub wl: &'p SampledWavelengths<K>,
    pub lanes: &'p Lanes<K>,
    pub choice: &'p ClusterChoice,
    /// Evaluate one strategy alone, unweighted.
    pub unweighted: bool,
    /// Next-event estimation (s = 1) chooses its light at the camera
    /// vertex by the light hierarchy (`LightChoice::by_point`), not by the
    /// cluster as the light subpaths do (the weights' `share`, `mis::weight`).
    pub by_point: bool,
}

/// What one strategy adds: light on the camera cluster's members, and
/// where on the film it lands for light tracing (t = 1; `None`: the
/// sample's own pixel).
pub(super) struct Contribution<const K: usize> {
    pub l: SampledSpectrum<K>,
    pub raster: Option<[f32; 2]>,
}

/// What a sample's subpaths and connections draw numbers from and count
/// their rays in, and whether they are traced through media (`media.rs`).
pub(super) struct Draw<'s> {
    pub sampler: &'s mut Sampler,
    /// Numbers for the media's estimates.
    pub rng: &'s mut SplitMix,
    pub rays: &'s mut u64,
    pub media: bool,
}

/// The elastic part of a fluorescent BSDF (ρ), 1 for the others.
pub(super) fn elastic<const K: usize>(
    bsdf: &Bsdf,
    wl: &SampledWavelengths<K>,
    uv: TexPoint,
) -> SampledSpectrum<K> {
    bsdf.fluorescent()
        .map_or(SampledSpectrum::splat(1.0), |f| f.reflectance.eval(wl, uv))
}

impl Renderer<'_> {
    /// The BSDF at a surface vertex.
    pub(super) fn bsdf_at<const K: usize>(&self, v: &Vertex<K>) -> &Bsdf {
        let scene = self.scene;
        &scene.materials[scene.shape_material[v.index as usize] as usize]
    }

    /// What passes along connection `ray`, which starts in `medium`
    /// (`Renderer::transmittance`).
    fn connection<const K: usize>(
        &self,
        ray: Ray,
        medium: Option<u32>,
        wl: &SampledWavelengths<K>,
        draw: &mut Draw<'_>,
    ) -> SampledSpectrum<K> {
        let crossing = if draw.media {
            Crossing::Media {
                medium,
                rng: &mut *draw.rng,
            }
        } else {
            Crossing::Clear
        };
        self.transmittance(ray, crossing, wl, draw.rays)
    }

    /// What passes between vertex `a` and point `b` (normal `nb`; zero:
    /// no surface), each offset off its surface towards the other: the
    /// transmittance through media and null surfaces (`media`), starting
    /// in the medium on the segment's side of `a`; without media 1 or 0.
    fn between<const K: usize>(
        &self,
        a: &Vertex<K>,
        b: Vec3,
        nb: Vec3,
        wl: &SampledWavelengths<K>,
        draw: &mut Draw<'_>,
    ) -> SampledSpectrum<K> {
        let off = |p: Vec3, n: Vec3, towards: Vec3| {
            if n == Vec3::ZERO {
                p
            } else {
                let side = if (towards - p).dot(n) >= 0.0 { n } else { -n };
                offset_ray_origin(p, side, self.scene.geometry.offset_unit())
            }
        };
        let o = off(a.p, a.ng, b);
        let e = off(b, nb, a.p);
        let d = e - o;
        let dist = d.length();
        if dist.is_nan() || dist <= 0.0 {
            return SampledSpectrum::splat(0.0);
        }
        let mut ray = Ray::new(o, d / dist);
        ray.t_max = dist * (1.0 - CONNECT_EPSILON);
        self.connection(ray, self.medium_towards(a, ray.d), wl, draw)
    }

    /// The lights' choice-weighted density of starting a light path at
    /// vertex `v` (a light vertex, an emitter hit, or the lights at
    /// infinity in direction `v.wi`).
    pub(super) fn origin_density<const K: usize>(
        &self,
        choice: impl Fn(usize) -> f32,
        v: &Vertex<K>,
    ) -> f32 {
        let extent = self.extent();
        match v.kind {
            Kind::Infinite => self
                .infinite_lights()
                .map(|(i, l)| choice(i) * l.pdf_le(&extent, v.p, Vec3::ZERO, -v.wi).dir)
                .sum(),
            Kind::Light => {
                let i = v.index as usize;
                choice(i) * self.scene.lights[i].pdf_le(&extent, v.p, v.ng, -v.wi).pos
            }
            Kind::Surface => match self.scene.shape_light[v.index as usize] {
                Some(i) => {
                    let l = &self.scene.lights[i as usize];
                    choice(i as usize) * l.pdf_le(&extent, v.p, v.ng, v.ng).pos
                }
                None => 0.0,
            },
            Kind::Camera | Kind::Medium => 0.0,
        }
    }

    /// The density with which next-event estimation at `x` would start a
    /// path at light vertex `v`: the light hierarchy's choice at `x` times
    /// the light's own density of `v`.
    fn nee_origin<const K: usize>(&self, x: &Vertex<K>, v: &Vertex<K>) -> f32 {
        let n = x.on_surface().then_some(x.ng);
        self.origin_density(|i| self.lights.probability(x.p, n, i), v)
    }

    /// The light with the emission at vertex `v`, if one.
    fn light_of<const K: usize>(&self, v: &Vertex<K>) -> Option<&Light> {
        match v.kind {
            Kind::Light => self.scene.lights.get(v.index as usize),
            Kind::Surface => self.scene.shape_light[v.index as usize]
                .and_then(|i| self.scene.lights.get(i as usize)),
            _ => None,
        }
    }

    /// Density per unit area at `next` of the light at `v` emitting
    /// towards it.
    fn emission_density<const K: usize>(&self, v: &Vertex<K>, next: &Vertex<K>) -> f32 {
        let extent = self.extent();
        if v.kind == Kind::Infinite {
            // The light travels along −wi; its disk's density on the line
            // through `next`.
            let disk = extent.disk_pdf(-v.wi, next.p);
            let mut at = *v;
            at.at_infinity = true;
            return at.convert(disk, next);
        }
        let Some(light) = self.light_of(v) else {
            return 0.0;
        };
        let d = (next.p - v.p).normalize();
        let pdf = light.pdf_le(&extent, next.p, v.ng, d);
        if v.at_infinity {
            return v.convert(pdf.pos, next);
        }
        v.convert(self.emission_pdf(light, v.p, d, pdf.dir), next)
    }

    /// Radiance (or intensity) the light at `v` emits in direction `d`.
    fn emitted<const K: usize>(
        &self,
        v: &Vertex<K>,
        wl: &SampledWavelengths<K>,
        d: Vec3,
    ) -> SampledSpectrum<K> {
        if v.kind == Kind::Infinite {
            return self
                .infinite_lights()
                .map(|(_, l)| l.radiance_at_infinity(wl, v.wi))
                .fold(SampledSpectrum::splat(0.0), |a, b| a + b);
        }
        match self.light_of(v) {
            Some(l) => l.emitted_towards(wl, v.tex.uv, v.ng, d),
            None => SampledSpectrum::splat(0.0),
        }
    }

    /// Contribution of strategy (s, t) on the camera cluster's members,
    /// MIS-weighted, and where on the film it lands when t = 1.
    pub(super) fn strategy<const K: usize>(
        &self,
        sub: &Subpaths<K>,
        s: usize,
        t: usize,
        draw: &mut Draw<'_>,
    ) -> Option<Contribution<K>> {
        let (light, camera, wl, lanes) = (sub.light, sub.camera, sub.wl, sub.lanes);
        let mut c = Connection::default();
        // A path of two vertices (an emitter seen from the lens) has no
        // next-event estimation: s = 1 is then light tracing's (1, 1).
        let by_point = sub.by_point && s + t > 2;
        // The light subpaths' origin density of the path's light over
        // next-event estimation's (1 where both choose alike; for s ≥ 2
        // found only once the contribution is known not to be zero).
        let mut share = 1.0f32;
        if let Some(y0) = light.first() {
            c.light_at_infinity = y0.at_infinity;
            c.delta_light = match y0.kind {
                Kind::Light => {
                    let l = &self.scene.lights[y0.index as usize];
                    l.is_delta_position() || l.is_delta_direction()
                }
                _ => false,
            };
        }
        // Per member: the light subpath's factor (throughput, reradiation)
        // and the least s of the strategies that can build its path.
        let mut min_s = [0usize; K];
        let mut l: SampledSpectrum<K>;
        let mut raster = None;
        let initial_only = |min_s: &mut [usize; K]| {
            SampledSpectrum::from_fn(|j| {
                min_s[j] = 0;
                if lanes.start[j] == 0 {
                    1.0
                } else {
                    0.0
                }
            })
        };

        if s == 0 {
            // The camera subpath reached a light.
            let z = &camera[t - 1];
            let le = self.emitted(z, wl, z.wi);
            if le.is_zero() {
                return None;
            }
            l = z.beta * le * initial_only(&mut min_s);
            let by_cluster = self.origin_density(|i| sub.choice.probability(i), z);
            c.camera_last_rev = by_cluster;
            if by_point {
                // s = 1 would have chosen this light at camera[t − 2].
                let x = &camera[t - 2];
                c.camera_last_rev = self.nee_origin(x, z);
                share = by_cluster / c.camera_last_rev;
            }
            c.camera_prev_rev = self.emission_density(z, &camera[t - 2]);
            c.delta_light = false;
            c.light_at_infinity = z.kind == Kind::Infinite;
        } else if t == 1 {
            // Light tracing: the light vertex seen through the lens.
            let y = &light[s - 1];
            let [u0, u1] = draw.sampler.get_2d();
            if y.at_infinity || (s > 1 && !self.connectible(y)) {
                return None;
            }
            let conn = self.scene.camera.connect(y.p, [u0, u1])?;
            let d = conn.lens - y.p;
            let dist2 = d.length_squared();
            let dir = d / dist2.sqrt();
            let f = if s == 1 {
                self.emitted(y, wl, dir) * (y.beta.0[0] * y.cos(dir)) * initial_only(&mut min_s)
            } else {
                let (f_dir, rho) = self.scatter_f(y, wl, dir, Transport::Importance);
                f_dir * self.light_factor(y, s - 1, lanes, &rho, &mut min_s)
            };
            if f.is_zero() {
                return None;
            }
            let tr = self.between(y, conn.lens, Vec3::ZERO, wl, draw);
            if tr.is_zero() {
                return None;
            }
            l = f * tr * conn.importance;
            raster = Some(conn.raster);
            let pdf_cam = self.scene.camera.pdf_direction(conn.lens, -dir);
            c.light_last_rev = pdf_cam * y.cos(dir) / dist2;
            if s >= 2 {
                let pdf = self.scatter_pdf(y, wl, dir, y.wi);
                c.light_prev_rev = y.convert(pdf, &light[s - 2]);
            }
        } else if s == 1 {
            // Next-event estimation: a light point sampled for z.
            let z = &camera[t - 1];
            let [u_choice, u_select, u0, u1] = draw.sampler.get_4d();
            if !self.connectible(z) {
                return None;
            }
            // No surface at a medium vertex: the ray leaves along the
            // light's direction.
            let n = z.on_surface().then_some(z.ng);
            let (i, q) = if by_point {
                self.lights.sample(z.p, n, u_choice)?
            } else {
                sub.choice.sample(u_choice)?
            };
            let lt = &self.scene.lights[i];
            let d = self.sample_direct(i, q, wl, z.p, n, [u_select, u0, u1])?;
            let (f, rho) = self.scatter_f(z, wl, d.ls.wi, Transport::Radiance);
            let f = f * rho;
            if f.is_zero() {
                return None;
            }
            let ray = d.ray(self.scene.geometry.offset_unit());
            let DirectSample { ls, pdf, .. } = d;
            let tr = self.connection(ray, self.medium_towards(z, ls.wi), wl, draw);
            if tr.is_zero() {
                return None;
            }
            l = z.beta * f * tr * ls.radiance * (1.0 / pdf) * initial_only(&mut min_s);
            // The sampled light point, as a vertex.
            let at_infinity = !ls.distance.is_finite();
            let mut y0 = Vertex::new(
                if lt.is_infinite() {
                    Kind::Infinite
                } else {
                    Kind::Light
                },
                if at_infinity {
                    z.p + ls.wi * (2.0 * self.bounds.radius)
                } else {
                    z.p + ls.wi * ls.distance
                },
                SampledSpectrum::splat(1.0),
            );
            y0.index = i as u32;
            y0.ng = ls.n;
            y0.at_infinity = at_infinity;
            y0.wi = ls.wi;
            let by_cluster = self.origin_density(|j| sub.choice.probability(j), &y0);
            if by_point {
                let nee = self.nee_origin(z, &y0);
                c.light_origin = Some(nee);
                share = by_cluster / nee;
            } else {
                c.light_origin = Some(by_cluster);
            }
            c.delta_light = ls.delta;
            c.light_at_infinity = at_infinity;
            let pdf_towards = if ls.delta {
                0.0
            } else {
                self.scatter_pdf(z, wl, z.wi, ls.wi)
            };
            c.light_last_rev = z.convert(pdf_towards, &y0);
            c.camera_last_rev = self.emission_density(&y0, z);
            c.camera_prev_rev = z.convert(self.scatter_pdf(z, wl, ls.wi, z.wi), &camera[t - 2]);
        } else {
            // Two scattering vertices (surfaces or media) joined.
            let (y, z) = (&light[s - 1], &camera[t - 1]);
            if !self.connectible(y) || !self.connectible(z) {
                return None;
            }
            let d = z.p - y.p;
            let dist2 = d.length_squared();
            if dist2.is_nan() || dist2 <= 0.0 {
                return None;
            }
            let dir = d / dist2.sqrt();
            let (f_y, rho) = self.scatter_f(y, wl, dir, Transport::Importance);
            let (f_z, rho_z) = self.scatter_f(z, wl, -dir, Transport::Radiance);
            let f = f_y * f_z * rho_z * self.light_factor(y, s - 1, lanes, &rho, &mut min_s);
            if f.is_zero() {
                return None;
            }
            let tr = self.between(y, z.p, z.ng, wl, draw);
            if tr.is_zero() {
                return None;
            }
            l = f * tr * z.beta * (1.0 / dist2);
            c.light_last_rev = z.convert(self.scatter_pdf(z, wl, z.wi, -dir), y);
            c.light_prev_rev = y.convert(self.scatter_pdf(y, wl, dir, y.wi), &light[s - 2]);
            c.camera_last_rev = y.convert(self.scatter_pdf(y, wl, y.wi, dir), z);
            c.camera_prev_rev = z.convert(self.scatter_pdf(z, wl, -dir, z.wi), &camera[t - 2]);
        }
        // Both subpaths collapsed to the first member: the factor K that
        // stands for the others counts once.
        let light_collapsed = s >= 1 && !(s == 1 && t >= 2) && light[s - 1].collapsed;
        if K > 1 && light_collapsed && camera[t - 1].collapsed {
            l /= K as f32;
        }
        if l.is_zero() {
            return None;
        }
        if !sub.unweighted {
            if by_point && s >= 2 {
                // s = 1 would have chosen this light at light[1].
                share = light[0].pdf_fwd / self.nee_origin(&light[1], &light[0]);
            }
            // One weight per distinct least s (one, without fluorescence).
            let mut cache: Option<(usize, f32)> = None;
            for (v, &least) in l.0.iter_mut().zip(&min_s) {
                if *v == 0.0 {
                    continue;
                }
                let w = match cache {
                    Some((cached, w)) if cached == least => w,
                    _ => {
                        let w = mis::weight(light, camera, s, t, &c, least, share);
                        cache = Some((least, w));
                        w
                    }
                };
                *v *= w;
            }
        }
        Some(Contribution { l, raster })
    }

    /// Per camera member, light vertex `i`'s throughput for the member's
    /// run, times the BSDF's spectral part there: ρ (`rho`, 1 for
    /// non-fluorescent BSDFs) for light reflected at the member's
    /// wavelength, or the reradiation factor where the run starts at `i`.
    /// Records each member's least s.
    fn light_factor<const K: usize>(
        &self,
        v: &Vertex<K>,
        i: usize,
        lanes: &Lanes<K>,
        rho: &SampledSpectrum<K>,
        min_s: &mut [usize; K],
    ) -> SampledSpectrum<K> {
        SampledSpectrum::from_fn(|j| {
            let k = lanes.member[j] as usize;
            let a = lanes.start[j] as usize;
            min_s[j] = if a > 0 { a + 1 } else { 0 };
            match lanes.at(j, v, i) {
                Some(false) => v.beta.0[k] * rho.0[j],
                Some(true) => v.beta.0[k] * v.shift.0[k],
                None => 0.0,
            }
        })
    }
}
