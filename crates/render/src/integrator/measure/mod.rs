//! Illuminance at virtual receivers, by the path tracer's own transport.
//!
//! A receiver is a point and the normal of the hemisphere it measures. It
//! is treated as a white Lambertian surface (reflectance 1) that a camera
//! ray has just reached from above: the path tracer's vertex step
//! ([`Renderer::scatter`]) does next-event estimation there (so point and
//! goniometric lights count) and continues by BSDF sampling with MIS, and
//! the path goes on as any camera path. Such a surface reflects
//! L = E/π in every direction, so E = π L: every light path the camera
//! would see is measured, with no separate estimator.
//!
//! Photopic illuminance E = π Y (lx, Y with K_m = 683 lm/W) and scotopic
//! illuminance E′ = π V′ (K′_m = 1700 lm/W), and the five α-opic
//! equivalent daylight (D65) illuminances of CIE S 026
//! (`scotopia_color::alpha_opic`), from the same paths' spectra, each with
//! its standard error over the samples. The receiver does not block light: nothing is added
//! to the scene; its ray origin is offset along its normal as a surface
//! point's would be, so a receiver on a floor measures the floor's
//! illuminance.
//!
//! With an observer ([`Setup::observer`]), also the luminance of what
//! the eye sees at each receiver's point (the road's, for EN 13201-3's
//! luminance method): a camera path along the ray from the eye to the
//! point, Y in cd/m². With [`Setup::direct`], light straight from the
//! emitters alone, as the standards' methods count it: receivers' paths of
//! one segment, the eye's of two (to the point, and to a light).

mod at_eye;
mod road_grid;

pub use at_eye::{lights_at_eye, AtEye};
pub use road_grid::{GridPoint, Road, RoadError, EYE_HEIGHT, OBSERVER_DISTANCE};

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

use rayon::prelude::*;
use scotopia_color::alpha_opic;
use scotopia_color::photometry::estimate_xyzv;
use scotopia_color::{SampledWavelengths, Spectrum};

use super::path::{CameraSample, PathState, ScatterPoint};
use super::renderer::SampleStart;
use super::select::{Integrator, Receivers};
use super::{ClusterSize, RenderError, RenderOptions, Renderer};
use crate::bsdf::{Bsdf, Diffuse, ShadingPoint};
use crate::math::{Frame, Ray, Vec3};
use crate::sampling::sobol::Sampler;
use crate::scene::Scene;
use crate::texture::Texture;

/// A point and the unit normal of the hemisphere it receives light from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Receiver {
    pub p: Vec3,
    pub n: Vec3,
}

/// What receivers measure: the illuminance of the plane of their normal,
/// or the mean illuminance over the curved surface of an infinitesimal
/// cylinder or half-cylinder along `up` (EN 12464-1's cylindrical
/// illuminance E_z, EN 13201-2's semi-cylindrical E_sc, for seeing
/// faces). With θ a direction's angle from `up`, E_z = (1/π)∫ L sin θ dω;
/// for a half-cylinder facing the receiver's normal (its part across
/// `up`), with φ a direction's azimuth from the facing, E_sc = (1/π)∫ L
/// sin θ (1 + cos φ) dω. Both are πL in a uniform field. Each is the mean
/// over the surface's normals of their planes' illuminance, so each
/// sample measures the plane of a normal drawn uniformly around the
/// cylinder (over the half-cylinder's half-turn): unbiased, by the
/// planes' own estimator.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum ReceiverShape {
    /// The plane of the receiver's normal.
    #[default]
    Plane,
    /// A cylinder along `up`; the receiver's normal is not used.
    Cylinder { up: Vec3 },
    /// A half-cylinder along `up` facing the receiver's normal.
    SemiCylinder { up: Vec3 },
}

impl ReceiverShape {
    /// The shape `plane`, `cylindrical` or `semicylindrical` names, the
    /// cylinders along `up`.
    pub fn from_name(name: &str, up: Vec3) -> Option<Self> {
        match name {
            "plane" => Some(Self::Plane),
            "cylindrical" => Some(Self::Cylinder { up }),
            "semicylindrical" => Some(Self::SemiCylinder { up }),
            _ => None,
        }
    }

    /// The same shape with its axis at unit length; an error for an axis
    /// that is not finite or is zero.
    fn with_unit_axis(self) -> Result<Self, RenderError> {
        let unit = |up: Vec3| {
            let finite = up.x.is_finite() && up.y.is_finite() && up.z.is_finite();
            if finite && up.abs().max_component() > 0.0 {
                Ok(unit_normal(up))
            } else {
                Err(RenderError::Axis)
            }
        };
        Ok(match self {
            Self::Plane => self,
            Self::Cylinder { up } => Self::Cylinder { up: unit(up)? },
            Self::SemiCylinder { up } => Self::SemiCylinder { up: unit(up)? },
        })
    }

    /// The normal of the plane one sample measures, from `u` in [0, 1),
    /// for a receiver of unit normal `n`; `None` where a half-cylinder's
    /// normal lies along its axis.
    fn normal(self, n: Vec3, u: f32) -> Option<Vec3> {
        use std::f32::consts::PI;
        let (up, facing, turn) = match self {
            Self::Plane => return Some(n),
            Self::Cylinder { up } => (up, Frame::from_normal(up).s, 2.0 * PI),
            Self::SemiCylinder { up } => {
                let across = n - up * n.dot(up);
                (across.length() > 1e-4).then_some(())?;
                (up, across.normalize(), PI)
            }
        };
        let side = up.cross(facing);
        let a = (u - 0.5) * turn;
        Some(facing * a.cos() + side * a.sin())
    }
}

/// What one receiver measured.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Measured {
    /// Photopic illuminance, lx, and its standard error.
    pub e: f64,
    pub e_se: f64,
    /// Scotopic illuminance (K′_m = 1700 lm/W), scotopic lx, and its
    /// standard error.
    pub es: f64,
    pub es_se: f64,
    /// The α-opic equivalent daylight (D65) illuminances, lx, in the order
    /// of `scotopia_color::alpha_opic::NAMES` (sc, mc, lc, rh, mel), and
    /// their standard errors.
    pub edi: [f64; 5],
    pub edi_se: [f64; 5],
    /// Samples that went into it.
    pub samples: u32,
    /// The luminance seen from the observer at the point, cd/m², and its
    /// standard error; NaN without an observer.
    pub lobs: f64,
    pub lobs_se: f64,
    /// The scotopic luminance seen there (K′_m = 1700 lm/W); NaN without
    /// an observer.
    pub lobs_scotopic: f64,
}

/// What `measure` measures: receivers of `shape`, and with an `observer`
/// the luminance it sees at each receiver's point; `direct`: light
/// straight from the emitters alone.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Setup {
    pub shape: ReceiverShape,
    pub observer: Option<Vec3>,
    pub direct: bool,
    /// With an observer, measure only what it sees: the receivers'
    /// illuminance is left out (its fields zero), for callers that want
    /// the luminance alone (`scotopia road`, one observer after another).
    pub seen_only: bool,
}

impl Measured {
    /// The S/P ratio E′/E (0 in the dark).
    pub fn sp(&self) -> f64 {
        if self.e > 0.0 {
            self.es / self.e
        } else {
            0.0
        }
    }
}

/// Illuminance at every receiver with `options.spp` samples each (the
/// scene's when `None`), the seed, wavelength strategy and cluster size of
/// `options`; always the path tracer. `progress(done, total)` counts
/// receivers. Cancelled measurements return what they have (receivers
/// not reached have no samples). A receiver whose point or normal is not
/// finite, or whose normal is zero, is an error naming its index.
pub fn measure(
    scene: &Scene,
    receivers: &[Receiver],
    options: &RenderOptions,
    cancel: &AtomicBool,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<Vec<Measured>, RenderError> {
    measure_with(
        scene,
        receivers,
        ReceiverShape::Plane,
        options,
        cancel,
        progress,
    )
}

/// [`measure`] with receivers of `shape`: planes, cylinders or
/// half-cylinders. A half-cylinder whose normal lies along its axis, or an
/// axis that is not finite or is zero, is an error.
pub fn measure_with(
    scene: &Scene,
    receivers: &[Receiver],
    shape: ReceiverShape,
    options: &RenderOptions,
    cancel: &AtomicBool,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<Vec<Measured>, RenderError> {
    let setup = Setup {
        shape,
        ..Setup::default()
    };
    measure_setup(scene, receivers, setup, options, cancel, progress)
}

/// [`measure_with`] of a whole [`Setup`]: with an observer, the luminance
/// it sees at each point too; an observer that is not a finite point is
/// an error.
pub fn measure_setup(
    scene: &Scene,
    receivers: &[Receiver],
    setup: Setup,
    options: &RenderOptions,
    cancel: &AtomicBool,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<Vec<Measured>, RenderError> {
    if setup
        .observer
        .is_some_and(|o| !(o.x.is_finite() && o.y.is_finite() && o.z.is_finite()))
    {
        return Err(RenderError::Observer);
    }
    let job = (
        receivers,
        Setup {
            shape: setup.shape.with_unit_axis()?,
            ..setup
        },
    );
    match options.cluster {
        ClusterSize::K1 => measure_k::<1>(scene, job, options, cancel, progress),
        ClusterSize::K2 => measure_k::<2>(scene, job, options, cancel, progress),
        ClusterSize::K4 => measure_k::<4>(scene, job, options, cancel, progress),
        ClusterSize::K8 => measure_k::<8>(scene, job, options, cancel, progress),
        ClusterSize::K16 => measure_k::<16>(scene, job, options, cancel, progress),
    }
}

fn measure_k<const K: usize>(
    scene: &Scene,
    (receivers, setup): (&[Receiver], Setup),
    options: &RenderOptions,
    cancel: &AtomicBool,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<Vec<Measured>, RenderError> {
    let spp = options.spp.unwrap_or(scene.samples_per_pixel);
    if spp == 0 {
        return Err(RenderError::Spp);
    }
    let finite = |v: Vec3| v.x.is_finite() && v.y.is_finite() && v.z.is_finite();
    if let Some(i) = receivers
        .iter()
        .position(|r| !finite(r.p) || !finite(r.n) || r.n.abs().max_component() == 0.0)
    {
        return Err(RenderError::Receiver(i));
    }
    if let Some(i) = receivers
        .iter()
        .position(|r| setup.shape.normal(unit_normal(r.n), 0.5).is_none())
    {
        return Err(RenderError::Facing(i));
    }
    let shape = setup.shape;
    // Direct light: a receiver's path of one segment (to an emitter), the
    // eye's of two (to the point, then to an emitter).
    let mut renderer = Renderer::receivers(scene, options.strategy);
    if setup.direct {
        renderer.max_depth = 1;
    }
    let eye = setup.observer.map(|o| {
        let mut eye = Renderer::receivers(scene, options.strategy);
        if setup.direct {
            eye.max_depth = 2;
        }
        (eye, o)
    });
    let Integrator::Illuminance(state) = &renderer.integrator else {
        unreachable!("Renderer::receivers runs the illuminance integrator")
    };
    let done = AtomicUsize::new(0);
    Ok(receivers
        .par_iter()
        .enumerate()
        .map(|(k, r)| {
            if cancel.load(Ordering::Relaxed) {
                return Measured::default();
            }
            let mut m = if setup.seen_only && eye.is_some() {
                Measured::default()
            } else {
                renderer.receive::<K>(
                    state,
                    (r, shape),
                    Sampler::new(options.seed),
                    k as u32,
                    spp,
                    cancel,
                )
            };
            [m.lobs, m.lobs_se, m.lobs_scotopic] = match &eye {
                Some((eye, o)) => eye.observe::<K>(
                    state,
                    (*o, r.p),
                    Sampler::new(options.seed),
                    k as u32,
                    spp,
                    cancel,
                ),
                None => [f64::NAN; 3],
            };
            progress(done.fetch_add(1, Ordering::Relaxed) + 1, receivers.len());
            m
        })
        .collect())
}

/// `n` (finite, not zero) at unit length: scaled by its largest component
/// first, so that a normal of any finite size works (3e38 in each
/// component has a length beyond f32, and would normalise to 0: 0 lx; a
/// subnormal one, 1e-40, would give NaN).
/// The mean of `n` samples whose sum is `sum` and sum of squares `sum2`,
/// and its standard error (from the unbiased sample variance).
pub(super) fn mean_se(sum: f64, sum2: f64, n: u32) -> (f64, f64) {
    let n = f64::from(n.max(1));
    let mean = sum / n;
    let var = (sum2 / n - mean * mean).max(0.0) * n / (n - 1.0).max(1.0);
    (mean, (var / n).sqrt())
}

pub fn unit_normal(n: Vec3) -> Vec3 {
    let m = n.abs().max_component();
    // Divided component by component: `Vec3 / f32` multiplies by 1/m,
    // which is ∞ for a subnormal m (1e-40).
    Vec3::new(n.x / m, n.y / m, n.z / m).normalize()
}

impl Renderer<'_> {
    /// One camera sample of the illuminance at the first surface `pixel`
    /// sees ([`super::Quantity::Illuminance`]), as a [`CameraSample`]
    /// whose X, Y, Z, V′ are illuminances.
    pub(super) fn sample_illuminance<const K: usize>(
        &self,
        receivers: &Receivers,
        sampler: &mut Sampler,
        pixel: [u32; 2],
        index: u32,
        rays: &mut u64,
    ) -> Option<CameraSample<K>> {
        let camera = self.start_path::<K>(sampler, pixel, index);
        *rays += 1;
        let Some(hit) = self.scene.geometry.intersect(&camera.ray) else {
            return Self::finish(&camera);
        };
        let surface = self.scene.geometry.surface(&hit, &camera.ray);
        let ng = surface.n_geometric;
        let n = if ng.dot(camera.ray.d) <= 0.0 { ng } else { -ng };
        let mut path = self.receiver_path(
            receivers,
            sampler,
            &Receiver { p: surface.p, n },
            camera.wl,
            rays,
        );
        path.l *= std::f32::consts::PI;
        let mut sample = Self::finish(&path)?;
        if receivers.melanopic {
            let mel = alpha_opic::estimate(&path.l, &path.wl)[4];
            sample.xyzv[3] = (f64::from(mel) / alpha_opic::d65_efficacy()[4]) as f32;
        }
        Some(sample)
    }

    /// One sample of an irradiancemeter (`Scene::meter`): the illuminance
    /// at a point of its shape chosen uniformly by area (the lens sample
    /// places it, the spare one chooses a mesh's triangle), measured over
    /// the hemisphere of the shape's normal there, as Mitsuba's
    /// `irradiancemeter` does with cosine-distributed rays.
    pub(super) fn sample_meter<const K: usize>(
        &self,
        receivers: &Receivers,
        sampler: &mut Sampler,
        pixel: [u32; 2],
        index: u32,
        rays: &mut u64,
    ) -> Option<CameraSample<K>> {
        let meter = self.scene.meter.as_ref()?;
        sampler.start(pixel, index);
        let sets = sampler.get_two_4d();
        let SampleStart {
            lens, wl, spare, ..
        } = self.start_sample_with::<K>(pixel, sets);
        let s = meter.sample(&self.scene.geometry.shapes, spare, lens)?;
        let mut path =
            self.receiver_path(receivers, sampler, &Receiver { p: s.p, n: s.n }, wl, rays);
        path.l *= std::f32::consts::PI;
        Self::finish(&path)
    }

    /// One path from a white receiver at `at.p` facing `at.n` (unit), as
    /// if a camera ray had just arrived there from straight above: its `l`
    /// is the receiver's radiance L = E/π.
    fn receiver_path<const K: usize>(
        &self,
        receivers: &Receivers,
        sampler: &mut Sampler,
        &Receiver { p, n }: &Receiver,
        wl: SampledWavelengths<K>,
        rays: &mut u64,
    ) -> PathState<K> {
        let frame = Frame::from_normal(n);
        let at = ShadingPoint::at([0.0f32; 2], n, n, frame.s, frame.t).1;
        let mut path = PathState::<K>::at_receiver(p, n, wl);
        // Receivers sit in the sensor's medium (Mitsuba's irradiancemeter
        // takes its sensor's).
        path.medium = self.scene.camera_medium;
        path.rng = sampler.stream();
        let u = sampler.get_two_4d();
        let point = ScatterPoint {
            p,
            ng: n,
            frame,
            at,
        };
        let white = &receivers.white;
        match &receivers.media {
            None => {
                let b = self.scatter::<K, false>(&mut path, u, &point, white);
                if self.settle::<K, false>(&mut path, b, rays) {
                    self.trace(sampler, &mut path, rays);
                }
            }
            Some(media) => {
                let b = self.scatter::<K, true>(&mut path, u, &point, white);
                if self.settle::<K, true>(&mut path, b, rays) {
                    self.trace_media(media, sampler, &mut path, rays);
                }
            }
        }
        path
    }

    /// The luminance (cd/m²) an eye at `eye` sees at `p`, its standard
    /// error and the scotopic luminance, from `spp` camera paths along the ray between them (samples
    /// of row 1 of receiver `index`'s column, apart from its
    /// illuminance's).
    fn observe<const K: usize>(
        &self,
        receivers: &Receivers,
        (eye, p): (Vec3, Vec3),
        mut sampler: Sampler,
        index: u32,
        spp: u32,
        cancel: &AtomicBool,
    ) -> [f64; 3] {
        let to = p - eye;
        let dist = to.length();
        if !(dist > 0.0 && dist.is_finite()) {
            return [f64::NAN; 3];
        }
        // Just past the point, so that the surface it lies on is hit.
        let ray = Ray {
            o: eye,
            d: to / dist,
            t_max: dist * (1.0 + 1e-3) + 1e-3,
        };
        let (mut sum, mut sum2, mut scotopic, mut n) = (0.0f64, 0.0f64, 0.0f64, 0u32);
        for i in 0..spp {
            if i % 64 == 63 && cancel.load(Ordering::Relaxed) {
                break;
            }
            sampler.start([index, 1], i);
            let sets = sampler.get_two_4d();
            let wl = self.start_sample_with::<K>([index, 1], sets).wl;
            let mut path = PathState::new(ray, wl, 1);
            path.medium = self.scene.camera_medium;
            path.rng = sampler.stream();
            match &receivers.media {
                None => self.trace(&mut sampler, &mut path, &mut 0),
                Some(media) => self.trace_media(media, &mut sampler, &mut path, &mut 0),
            }
            let [_, y, _, v] = estimate_xyzv(&path.l, &path.wl).map(f64::from);
            if y.is_finite() && v.is_finite() {
                sum += y;
                sum2 += y * y;
                scotopic += v;
                n += 1;
            }
        }
        let (mean, se) = mean_se(sum, sum2, n);
        [mean, se, scotopic / f64::from(n.max(1))]
    }

    /// `spp` samples of receiver number `index` (its place in the sampler's
    /// pixel grid: row 0, column `index`), of `shape`.
    fn receive<const K: usize>(
        &self,
        receivers: &Receivers,
        (r, shape): (&Receiver, ReceiverShape),
        mut sampler: Sampler,
        index: u32,
        spp: u32,
        cancel: &AtomicBool,
    ) -> Measured {
        let n = unit_normal(r.n);
        // E, E′ and the five α-opic EDIs.
        let (mut sum, mut sum2) = ([0.0f64; 7], [0.0f64; 7]);
        let k_d65 = alpha_opic::d65_efficacy();
        let mut samples = 0u32;
        for i in 0..spp {
            if i % 64 == 63 && cancel.load(Ordering::Relaxed) {
                break;
            }
            sampler.start([index, 0], i);
            let sets = sampler.get_two_4d();
            let start = self.start_sample_with::<K>([index, 0], sets);
            // The lens sample turns a cylinder's plane (checked to exist).
            let Some(n) = shape.normal(n, start.lens[0]) else {
                continue;
            };
            let (wl, at) = (start.wl, Receiver { p: r.p, n });
            let path = self.receiver_path(receivers, &mut sampler, &at, wl, &mut 0);
            let [_, y, _, v] = estimate_xyzv(&path.l, &path.wl);
            let a = alpha_opic::estimate(&path.l, &path.wl);
            let pi = std::f64::consts::PI;
            let x: [f64; 7] = std::array::from_fn(|i| match i {
                0 => pi * f64::from(y),
                1 => pi * f64::from(v),
                _ => pi * f64::from(a[i - 2]) / k_d65[i - 2],
            });
            if !x.iter().all(|v| v.is_finite()) {
                continue;
            }
            samples += 1;
            for i in 0..7 {
                sum[i] += x[i];
                sum2[i] += x[i] * x[i];
            }
        }
        let stat = |s: f64, s2: f64| mean_se(s, s2, samples);
        let (e, e_se) = stat(sum[0], sum2[0]);
        let (es, es_se) = stat(sum[1], sum2[1]);
        let edi = std::array::from_fn(|i| stat(sum[i + 2], sum2[i + 2]));
        Measured {
            e,
            e_se,
            es,
            es_se,
            edi: edi.map(|s| s.0),
            edi_se: edi.map(|s| s.1),
            samples,
            lobs: f64::NAN,
            lobs_se: f64::NAN,
            lobs_scotopic: f64::NAN,
        }
    }
}

impl<const K: usize> PathState<K> {
    /// A path that has just reached receiver `p` along −`n` (one segment
    /// done, as a camera ray's first hit).
    fn at_receiver(p: Vec3, n: Vec3, wl: SampledWavelengths<K>) -> Self {
        // The receiver is the instrument, not a scattering vertex:
        // max_depth counts segments from it, as from Mitsuba's
        // irradiancemeter (1: light straight from emitters).
        Self::new(Ray::new(p + n, -n), wl, 0)
    }
}

/// The receivers' surface: white Lambertian, reflectance 1 at every
/// wavelength (L = E/π).
pub(super) fn white() -> Bsdf {
    Bsdf::Diffuse(Diffuse {
        reflectance: Texture::Constant(Spectrum::Constant(1.0)),
    })
}

#[cfg(test)]
mod tests {
    use super::{unit_normal, Vec3};

    #[test]
    fn a_normal_of_any_finite_size_normalises() {
        // 1e-40 is subnormal; 3e38 (×√3) overflows a plain length.
        for k in [1e-40f32, 1e-30, 1.0, 1e30, 3e38] {
            let n = unit_normal(Vec3::new(k, k, k));
            assert!((n.length() - 1.0).abs() < 1e-6, "{k}: {n:?}");
            assert!((n.x - 1.0 / 3f32.sqrt()).abs() < 1e-6, "{k}: {n:?}");
        }
    }
}
