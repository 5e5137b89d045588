//! The multiscale model's gain control (Pattanaik, Ferwerda, Fairchild &
//! Greenberg 1998; docs/vision.md §3): the photoreceptors' gain as a
//! function of local adaptation.

/// A gain-control function of the adapting luminance I (cd/m² for cones,
/// scotopic cd/m² for rods):
///
///   G(I) = S(I) / (k · (I + σ)ⁿ),  S(I) = c / (I² + c) (rods) or 1 (cones).
///
/// Pattanaik et al. 1998 fit these to threshold-versus-intensity data so
/// that a band signal times G is in units of threshold: cones k = 0.555,
/// σ = 1, n = 0.85; rods k = 0.908, σ = 0.001, n = 0.85, with the
/// saturation factor c = 10 that switches rods off in daylight.
///
/// Not yet checked against the paper (issue 37, part 4): no copy of its
/// text beyond the abstract, and no implementation of this 1998 model, was
/// found (pfstmo's `pattanaik00` is the different 2000 time-dependent
/// model), so every value below is as scotopia's authors recall it. The
/// units of I are the question to settle first: the paper's rod signal is
/// its fit R = −0.702X + 1.039Y + 0.433Z, which is V′ divided by 2.92 for
/// D65 ([`scotopia_color::photometry::ROD_FIT_SCALE`]) and by 3.3 for
/// illuminant A, while scotopia passes V′ itself; if the rod constants were
/// fitted to R, rods here saturate about three times too early
/// (docs/vision.md §3).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GainFunction {
    pub k: f32,
    pub sigma: f32,
    pub n: f32,
    /// The rods' saturation constant c; `None` for cones.
    pub saturation: Option<f32>,
}

impl GainFunction {
    /// G_cone(I) = 1 / (0.555 · (I + 1)^0.85).
    pub const CONES: Self = Self {
        // Pattanaik et al. 1998, cone gain control, scale k (recalled, unchecked).
        k: 0.555,
        // Pattanaik et al. 1998, cone gain control, offset σ (recalled, unchecked).
        sigma: 1.0,
        // Pattanaik et al. 1998, cone gain control, exponent n (recalled, unchecked).
        n: 0.85,
        saturation: None,
    };
    /// G_rod(I) = 10 / (I² + 10) · 1 / (0.908 · (I + 0.001)^0.85).
    pub const RODS: Self = Self {
        // Pattanaik et al. 1998, rod gain control, scale k (recalled, unchecked).
        k: 0.908,
        // Pattanaik et al. 1998, rod gain control, offset σ (recalled, unchecked).
        sigma: 0.001,
        // Pattanaik et al. 1998, rod gain control, exponent n (recalled, unchecked).
        n: 0.85,
        // Pattanaik et al. 1998, rod saturation c in c / (I² + c) (recalled, unchecked).
        saturation: Some(10.0),
    };

    #[inline]
    pub fn gain(&self, i: f32) -> f32 {
        let i = i.max(0.0);
        let g = 1.0 / (self.k * (i + self.sigma).powf(self.n));
        match self.saturation {
            Some(c) => g * c / (i * i + c),
            None => g,
        }
    }

    /// [`GainFunction::gain`] with the power through `wide_math` (f64
    /// polynomials, the same to an f32 ulp), so a loop of gains
    /// vectorises.
    #[inline(always)]
    pub fn gain_wide(&self, i: f32) -> f32 {
        let i = i.max(0.0);
        let g = 1.0 / (self.k * crate::wide_math::powf(i + self.sigma, self.n));
        // Both sides computed and one chosen (a select, not a branch).
        let c = self.saturation.unwrap_or(0.0);
        let saturated = g * c / (i * i + c);
        if self.saturation.is_some() {
            saturated
        } else {
            g
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gains_are_one_near_one_candela_and_fall_with_adaptation() {
        // Both fits pass close to G(1) = 1: cones 1/(0.555·2^0.85),
        // rods (10/11)/(0.908·1.001^0.85).
        assert!((GainFunction::CONES.gain(1.0) - 1.0).abs() < 0.01);
        assert!((GainFunction::RODS.gain(1.0) - 1.0).abs() < 0.01);
        for g in [GainFunction::CONES, GainFunction::RODS] {
            let mut last = f32::INFINITY;
            for e in -4..5 {
                let v = g.gain(10f32.powi(e));
                assert!(v < last, "gain must fall as adaptation rises");
                last = v;
            }
        }
        // Rods saturate: at 100 scotopic cd/m² their gain is a thousandth
        // of the cones' at the same level.
        assert!(GainFunction::RODS.gain(100.0) < 1e-3 * GainFunction::CONES.gain(100.0));
    }
}
