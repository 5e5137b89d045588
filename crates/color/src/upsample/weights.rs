//! The discrete colorimetry of reflectance round trips: XYZ of a reflectance
//! under a colour space's white illuminant, normalised so that the perfect
//! reflector has Y = 1. The Jakob–Hanika fitter and the round-trip
//! measurements share it, so both optimise and measure the same thing.

use std::sync::OnceLock;

use crate::cie;
use crate::space::RgbSpace;
use crate::spectrum::Spectrum;
use crate::{LAMBDA_MAX, LAMBDA_MIN};

/// Weights wᵢ = I(λᵢ)·{x̄, ȳ, z̄}(λᵢ) / Σ I ȳ at λᵢ = 360, 361, …, 830 nm,
/// so XYZ = Σᵢ wᵢ R(λᵢ) (the CIE 1 nm summation).
pub struct ReflectanceWeights {
    pub lambda: Vec<f32>,
    pub w: Vec<[f64; 3]>,
}

impl ReflectanceWeights {
    /// The weights for `space`'s white illuminant, built once per space.
    pub fn of(space: RgbSpace) -> &'static ReflectanceWeights {
        static W: OnceLock<Vec<ReflectanceWeights>> = OnceLock::new();
        let all = W.get_or_init(|| {
            RgbSpace::ALL
                .iter()
                .map(|&s| Self::build(&s.def().illuminant))
                .collect()
        });
        &all[space as usize]
    }

    fn build(illuminant: &Spectrum) -> Self {
        let lambda: Vec<f32> = (LAMBDA_MIN as u32..=LAMBDA_MAX as u32)
            .map(|l| l as f32)
            .collect();
        let raw: Vec<[f64; 3]> = lambda
            .iter()
            .map(|&l| {
                let i = illuminant.eval(l) as f64;
                cie::xyz_bar(l).map(|c| c as f64 * i)
            })
            .collect();
        let norm: f64 = raw.iter().map(|w| w[1]).sum();
        let w = raw.iter().map(|w| w.map(|v| v / norm)).collect();
        Self { lambda, w }
    }

    /// Relative XYZ of the reflectance `r` (Y = 1 for the perfect reflector).
    pub fn xyz(&self, mut r: impl FnMut(f32) -> f32) -> [f64; 3] {
        let mut xyz = [0.0f64; 3];
        for (l, w) in self.lambda.iter().zip(&self.w) {
            let v = r(*l) as f64;
            xyz[0] += w[0] * v;
            xyz[1] += w[1] * v;
            xyz[2] += w[2] * v;
        }
        xyz
    }
}
