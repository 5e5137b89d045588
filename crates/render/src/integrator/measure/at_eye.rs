//! Each luminaire's illuminance at an eye, for the threshold increment
//! (EN 13201-3, CIE 140): E_k on the plane at the eye facing along the
//! line of sight, and the direction it comes from, by the renderer's own
//! light sampling with a shadow ray through the scene's geometry, so that
//! what shields a lamp from the eye counts. Lights at infinity and
//! directional lights are no luminaires and are left out; media are not
//! crossed (their attenuation is not counted).

use scotopia_color::photometry::estimate_xyzv;

use crate::integrator::{ClusterSize, RenderError, RenderOptions, Renderer};
use crate::light::Light;
use crate::math::{Ray, Vec3};
use crate::sampling::sobol::Sampler;
use crate::scene::Scene;

/// One luminaire as an eye sees it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AtEye {
    /// The light's index in the scene.
    pub light: usize,
    /// Unit direction from the eye towards it (the mean over its samples,
    /// weighted by their light).
    pub direction: Vec3,
    /// Its illuminance on the plane at the eye facing the line of sight
    /// (lx), and the standard error of that.
    pub e: f64,
    pub e_se: f64,
}

/// Every luminaire's illuminance at `eye` on the plane facing `look`
/// (unit), with `options.spp` samples each (the scene's when `None`), the
/// options' seed, wavelengths and cluster size.
/// Luminaires that give nothing (behind the plane, hidden) are left out.
pub fn lights_at_eye(
    scene: &Scene,
    eye: Vec3,
    look: Vec3,
    options: &RenderOptions,
) -> Result<Vec<AtEye>, RenderError> {
    let finite = |v: Vec3| v.x.is_finite() && v.y.is_finite() && v.z.is_finite();
    if !finite(eye) || !finite(look) || look.length_squared() == 0.0 {
        return Err(RenderError::Observer);
    }
    let look = look.normalize();
    let spp = options.spp.unwrap_or(scene.samples_per_pixel).max(1);
    Ok(match options.cluster {
        ClusterSize::K1 => at_eye::<1>(scene, (eye, look), spp, options),
        ClusterSize::K2 => at_eye::<2>(scene, (eye, look), spp, options),
        ClusterSize::K4 => at_eye::<4>(scene, (eye, look), spp, options),
        ClusterSize::K8 => at_eye::<8>(scene, (eye, look), spp, options),
        ClusterSize::K16 => at_eye::<16>(scene, (eye, look), spp, options),
    })
}

fn at_eye<const K: usize>(
    scene: &Scene,
    (eye, look): (Vec3, Vec3),
    spp: u32,
    options: &RenderOptions,
) -> Vec<AtEye> {
    let r = Renderer::receivers(scene, options.strategy);
    let extent = r.extent();
    let mut sampler = Sampler::new(options.seed);
    let mut out = Vec::new();
    for (i, light) in scene.lights.iter().enumerate() {
        if light.is_infinite() || matches!(light, Light::Directional(_)) {
            continue;
        }
        // Point-like lights too: each sample's few wavelengths estimate
        // the spectrum's luminance with noise.
        let n = spp;
        let (mut sum, mut sum2, mut towards) = (0.0f64, 0.0f64, Vec3::ZERO);
        for s in 0..n {
            sampler.start([i as u32, 2], s);
            let sets = sampler.get_two_4d();
            let start = r.start_sample_with::<K>([i as u32, 2], sets);
            let [u0, u1, u2, _] = sets[1];
            let e = light
                .sample_li(&extent, &start.wl, eye, u0, [u1, u2])
                .filter(|ls| ls.pdf > 0.0 && ls.wi.dot(look) > 0.0)
                .filter(|ls| {
                    let to = if ls.distance.is_finite() {
                        ls.distance * (1.0 - 1e-4)
                    } else {
                        f32::INFINITY
                    };
                    !scene.geometry.occluded(&Ray {
                        o: eye,
                        d: ls.wi,
                        t_max: to,
                    })
                })
                .map_or(0.0, |ls| {
                    let y = f64::from(estimate_xyzv(&ls.radiance, &start.wl)[1]);
                    let e = y * f64::from(ls.wi.dot(look)) / f64::from(ls.pdf);
                    towards += ls.wi * e as f32;
                    e
                });
            if e.is_finite() {
                sum += e;
                sum2 += e * e;
            }
        }
        let (mean, se) = super::mean_se(sum, sum2, n);
        if mean <= 0.0 || towards.length_squared() == 0.0 {
            continue;
        }
        out.push(AtEye {
            light: i,
            direction: towards.normalize(),
            e: mean,
            e_se: se,
        });
    }
    out
}
