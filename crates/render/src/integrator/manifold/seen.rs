//! The caustic seen from the camera: light tracing for the path tracer.
//!
//! Where the camera sees the caustic directly, the estimator of `mod.rs`
//! ran at every first hit, for every kind: a third of the render's time on
//! `glass-and-metals.xml`. Its paths' density falls to nothing at the
//! caustic's folds (dω/dA large), where BSDF sampling through the ball
//! takes their weight and each find carries the lamp's radiance: the
//! brightest pixels left. Light tracing draws those points as often as
//! the caustic is bright. So the light subpath each camera path draws
//! (`connect`: one in twenty) is drawn when the path starts, and the point
//! v it lands on is joined to the camera (Veach 1997 §10.2's t = 1; the
//! camera's importance as in `camera/importance.rs`): a splat on the
//! pixel that sees v. The camera's ray then plays the part of the bounce
//! that reaches a joined vertex: at a first hit, the density per area is
//! the camera's, p_cam(ω) |cos_v| / d², and the estimator there runs at
//! `SHARES_JOINED`, weighed against this strategy as against a join.

use scotopia_color::photometry::estimate_xyzv;
use scotopia_color::SampledWavelengths;

use super::connect::{Caustic, LightVertex};
use crate::camera::Projection;
use crate::integrator::bdpt::Splat;
use crate::integrator::path::PathState;
use crate::integrator::Renderer;
use crate::math::{Ray, Vec3};
use crate::sampling::splitmix::SplitMix;

impl Renderer<'_> {
    /// Draws the light subpath of a camera path about to start in clear
    /// air (where balls are joined), and its splat where the camera sees
    /// where it lands; the rays that took. Every camera path in clear air
    /// comes here first, so each draws one with the same probability.
    pub(in crate::integrator) fn draw_caustic<const K: usize>(
        &self,
        path: &mut PathState<K>,
    ) -> u32 {
        let mut traced = 0;
        if !self.lenses.joined() {
            return traced;
        }
        path.caustic = match self.draw_light_vertex(&mut path.rng, &mut traced) {
            Some(lv) => {
                let wl = path.wl;
                path.seen = self.seen(&lv, &wl, &mut path.rng, &mut traced);
                Caustic::At(lv)
            }
            None => Caustic::Lost,
        };
        traced
    }

    /// The light of `lv` at the camera: where on the film and how much,
    /// weighed against the camera path's strategies at its first hit.
    fn seen<const K: usize>(
        &self,
        lv: &LightVertex,
        wl: &SampledWavelengths<K>,
        rng: &mut SplitMix,
        traced: &mut u32,
    ) -> Option<Splat<K>> {
        if !self.within(1 + lv.kind.segments()) || !self.sees_points() {
            return None;
        }
        let camera = &self.scene.camera;
        let conn = camera.connect(lv.v.p, [rng.next_f32(), rng.next_f32()])?;
        let to = conn.lens - lv.v.p;
        let dist2 = to.length_squared();
        let dir = to / dist2.sqrt();
        let cos_v = lv.v.ng.dot(dir).abs();
        let a = camera.pdf_direction(conn.lens, -dir) * cos_v / dist2;
        let light = self.light_vertex_sends(wl, lv, -dir, a) * (cos_v * conn.importance);
        if light.is_zero() || !light.max_value().is_finite() {
            return None;
        }
        if !self.clear_between((lv.v.p, lv.v.ng), conn.lens, traced) {
            return None;
        }
        let xyzv = estimate_xyzv(&light, wl);
        xyzv.iter().all(|v| v.is_finite()).then_some(Splat {
            raster: conn.raster,
            xyzv,
            radiance: light,
            wl: *wl,
        })
    }

    /// The density per area at `p` (geometric normal `ng`) of the camera
    /// ray `ray` that reached it, as the light subpaths' splats weigh it.
    pub(in crate::integrator) fn camera_density(&self, ray: &Ray, p: Vec3, ng: Vec3) -> f32 {
        if !self.sees_points() {
            return 0.0;
        }
        let to = p - ray.o;
        let dist2 = to.length_squared();
        let a = self.scene.camera.pdf_direction(ray.o, ray.d) * ng.dot(ray.d).abs() / dist2;
        if a.is_finite() {
            a
        } else {
            0.0
        }
    }

    /// Whether a point can be joined to the camera: through a lens, not
    /// along an orthographic camera's parallel rays, which no light path
    /// reaches (there the first hits keep the estimator's full shares).
    fn sees_points(&self) -> bool {
        self.scene.camera.projection != Projection::Orthographic
    }
}
