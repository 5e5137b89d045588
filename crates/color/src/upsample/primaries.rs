//! The naive baseline: RGB weights three fixed, non-overlapping boxes of the
//! spectrum — blue on 360–490 nm, green on 490–580 nm, red on 580–830 nm —
//! whose sum is 1, so greys are exact and nothing else is. Kept only to show
//! what the better methods gain.

use crate::spectrum::Tabulated;
use crate::{LAMBDA_MAX, LAMBDA_MIN};

/// Box edges, nm: blue | green at 490, green | red at 580.
const EDGES: [f32; 2] = [490.0, 580.0];
/// Width of the linear ramp between boxes (narrow: a near-step).
const RAMP: f32 = 0.5;

/// The box spectrum of a reflectance `rgb`.
pub fn reflectance(rgb: [f32; 3]) -> Tabulated {
    let [r, g, b] = rgb;
    let (e0, e1) = (EDGES[0], EDGES[1]);
    let lambda = vec![
        LAMBDA_MIN,
        e0 - RAMP,
        e0 + RAMP,
        e1 - RAMP,
        e1 + RAMP,
        LAMBDA_MAX,
    ];
    let value = vec![b, b, g, g, r, r];
    // The wavelengths are fixed and increasing.
    Tabulated::new(lambda, value).expect("fixed box edges")
}
