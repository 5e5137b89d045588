//! Which wavelengths the camera subpath carries (the light subpath's
//! light is chosen for its cluster by `integrator::light_choice`).
//!
//! **Fluorescence (the rule the seed design proposes).** Wavelengths only
//! change on the light subpath: at a fluorescent vertex each member is
//! reflected or re-emitted at a new wavelength drawn ∝ F(λi → λo). The
//! wavelength each member has along one stretch of the path is a *run*
//! (started by the light or by a re-emission). The camera subpath draws
//! its K wavelengths from the n runs, stratified (member j takes run
//! ⌊(j + u)·n/K⌋, then the cluster is rotated by a uniform offset), and
//! sees fluorescent surfaces by their elastic part alone. A camera member
//! on run r (of light member k, started at vertex a) connects only to the
//! light vertices where member k carries that run — the others are
//! stripped from its cluster — so every connection is at one wavelength.
//!
//! Estimator: each run is chosen K/n times on average, so weighing member
//! j by n/K (its density in the film estimate is p(λ_k)·K/n, λ_k the
//! light member's first wavelength, whose density the light throughput
//! does not include) makes the sum over camera members an unbiased
//! estimate of the sum over runs, which is the K light members' plain
//! bidirectional estimates. Without fluorescence n = K and member j is
//! light member j: the plain estimator. A path whose wavelength changes at
//! vertex a can only be built by strategies whose light subpath holds
//! vertex a (s > a); its MIS weight counts only those (`mis`).

use scotopia_color::SampledWavelengths;

use super::vertex::Vertex;

/// Which light member and run each camera member follows.
#[derive(Debug, Clone, Copy)]
pub(super) struct Lanes<const K: usize> {
    pub member: [u8; K],
    /// The vertex where the run starts (0: the light).
    pub start: [u8; K],
}

impl<const K: usize> Lanes<K> {
    /// Whether camera member `j` connects to light vertex `i`, and if so
    /// whether across a re-emission at `i` (`Some(true)`) or elastically.
    #[inline]
    pub fn at(&self, j: usize, v: &Vertex<K>, i: usize) -> Option<bool> {
        let (k, a) = (self.member[j] as usize, self.start[j]);
        if v.run_in[k] == a {
            Some(false)
        } else if v.run_out[k] == a && a as usize == i && a > 0 {
            Some(true)
        } else {
            None
        }
    }
}

/// Draws the camera cluster from the runs along `light` (whose members
/// started at `first`): returns the cluster (with the densities the film
/// estimate divides by), the lanes, and whether any member was re-emitted.
pub(super) fn camera_cluster<const K: usize>(
    first: &SampledWavelengths<K>,
    light: &[Vertex<K>],
    u: f32,
    u_rotate: f32,
) -> (SampledWavelengths<K>, Lanes<K>) {
    // Count the runs: one per member, plus one per re-emission.
    let mut n = K;
    for (i, v) in light.iter().enumerate() {
        n += v
            .run_out
            .iter()
            .filter(|&&a| a as usize == i && i > 0)
            .count();
    }
    if n == K {
        let lanes = Lanes {
            member: std::array::from_fn(|k| k as u8),
            start: [0; K],
        };
        return (*first, lanes);
    }
    // The e-th run, in order: member by member, light first, then each
    // re-emission along the path.
    let run = |mut e: usize| -> (u8, u8) {
        for k in 0..K {
            if e == 0 {
                return (k as u8, 0);
            }
            e -= 1;
            for (i, v) in light.iter().enumerate().skip(1) {
                if v.run_out[k] as usize == i {
                    if e == 0 {
                        return (k as u8, i as u8);
                    }
                    e -= 1;
                }
            }
        }
        (0, 0)
    };
    let mut lambda = [0.0f32; K];
    let mut pdf = [0.0f32; K];
    let mut member = [0u8; K];
    let mut start = [0u8; K];
    for j in 0..K {
        let e = (((j as f32 + u) * n as f32 / K as f32) as usize).min(n - 1);
        let (k, a) = run(e);
        member[j] = k;
        start[j] = a;
        lambda[j] = if a == 0 {
            first.lambda(k as usize)
        } else {
            light[a as usize].lambda_out[k as usize]
        };
        pdf[j] = first.pdf(k as usize) * K as f32 / n as f32;
    }
    // A uniform rotation makes the member a dispersive event keeps
    // uniform over the cluster.
    let r = ((u_rotate * K as f32) as usize).min(K - 1);
    lambda.rotate_left(r);
    pdf.rotate_left(r);
    member.rotate_left(r);
    start.rotate_left(r);
    (
        SampledWavelengths::new(lambda, pdf),
        Lanes { member, start },
    )
}
