//! The model's constants, every one overridable, and the display's
//! scale for a scene's adaptation luminance.

use super::adaptation::Pooling;
use super::gain::GainFunction;

/// What the eye adapts to in the model's gain control.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum GainAdaptation {
    /// Per pixel, from the light around it ([`Pooling`]).
    Local,
    /// One photopic luminance (cd/m²) for the whole image; cone and rod
    /// adaptation follow from the image's mean chromaticity and S/P ratio.
    Global(f64),
}

/// Every constant of the model, overridable.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MultiscaleParams {
    /// Visual angle of one pixel, degrees: the pooling field is in
    /// degrees.
    pub degrees_per_pixel: f64,
    /// How the eye pools light for its local adaptation.
    pub pooling: Pooling,
    /// The image's log-average luminance when the caller has it already
    /// (`None`: computed).
    pub log_average: Option<f64>,
    pub cones: GainFunction,
    pub rods: GainFunction,
    /// The display's peak luminance, cd/m².
    pub display_peak: f64,
    /// The luminance the viewer of the display is adapted to, cd/m²
    /// (`None`: half the peak).
    pub display_adaptation: Option<f64>,
    pub adaptation: GainAdaptation,
    /// The highest display level, as a fraction of the peak, the scene's
    /// adaptation luminance is shown at (see `display_scale`).
    pub mean_ceiling: f64,
}

impl Default for MultiscaleParams {
    fn default() -> Self {
        Self {
            degrees_per_pixel: 40.0 / 1024.0,
            pooling: Pooling::default(),
            log_average: None,
            cones: GainFunction::CONES,
            rods: GainFunction::RODS,
            display_peak: 100.0,
            display_adaptation: None,
            adaptation: GainAdaptation::Local,
            mean_ceiling: 0.25,
        }
    }
}

impl MultiscaleParams {
    /// The luminance the viewer of the display is adapted to, cd/m².
    pub fn display_adaptation(&self) -> f64 {
        self.display_adaptation.unwrap_or(self.display_peak / 2.0)
    }

    /// The factor the display image is scaled by for a scene adapted to
    /// `la` cd/m²: the brightness match shows `la` at
    /// m = la·G(la)/G(La_display); with the ceiling c = `mean_ceiling` ×
    /// peak the factor is (1 + (m/c)⁴)^(−1/4), so m·factor rises with m,
    /// stays below c, and is within 1 % of m up to m = c/2. A dusk scene
    /// (m ≈ 0.16 of the peak) moves by 4 %; daylight scenes, which the
    /// plain match put at 60–140 % of the peak, sit near a quarter of it.
    /// (scotopia's choice: the display cannot match daylight's brightness,
    /// so it keeps the contrasts instead.)
    pub fn display_scale(&self, la: f64) -> f64 {
        let cones = self.cones;
        let m =
            la * cones.gain(la as f32) as f64 / cones.gain(self.display_adaptation() as f32) as f64;
        let c = self.mean_ceiling * self.display_peak;
        if !(m > 0.0 && m.is_finite() && c > 0.0) {
            return 1.0;
        }
        (1.0 + (m / c).powi(4)).powf(-0.25)
    }
}
