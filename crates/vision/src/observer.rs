//! The observer whose eye the pipeline models: age and eye pigmentation,
//! the two parameters of CIE 146:2002's glare spread function (and age the
//! lens's optical density, Pokorny, Smith & Lutze 1987).

/// An observer's eye.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Observer {
    /// Age in years. CIE 146:2002's glare spread function holds for adult
    /// eyes; its young reference observer is 25 (the default here).
    pub age: f64,
    /// Eye pigmentation factor p of CIE 146:2002: 0 very dark eyes, 0.5
    /// brown (the standard's usual value and the default here), 1 light
    /// blue-green (pale eyes scatter more light through the eye wall).
    pub pigmentation: f64,
}

impl Default for Observer {
    fn default() -> Self {
        Self {
            age: Self::DEFAULT_AGE,
            pigmentation: Self::DEFAULT_PIGMENTATION,
        }
    }
}

/// Why an observer's value was refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ObserverError {
    #[error("age {0}: use years from {min} to {max}", min = Observer::AGES.0, max = Observer::AGES.1)]
    Age(f64),
    #[error("pigmentation {0}: use a factor from 0 (dark eyes) to 1 (light blue eyes)")]
    Pigmentation(f64),
}

impl Observer {
    pub const DEFAULT_AGE: f64 = 25.0;
    pub const DEFAULT_PIGMENTATION: f64 = 0.5;
    /// The ages accepted: the lens density model of Pokorny et al. 1987
    /// was fitted from 20 to 80 years and CIE 146's equation to adults;
    /// scotopia accepts 1 to 100 and extrapolates outside the data.
    pub const AGES: (f64, f64) = (1.0, 100.0);

    /// What this observer's lens passes of each channel (X, Y, Z, V′)
    /// relative to the default observer's, for a flat spectrum (Pokorny,
    /// Smith & Lutze 1987's optical density as CIE 170-1:2006 adopts it;
    /// `scotopia_color::cie::lens`). The CIE 1931 and 1951 observers are
    /// taken as the default observer's eye, so 25 years changes nothing;
    /// an older lens absorbs more, most of all at short wavelengths (70
    /// years: Y 0.79, Z 0.44, V′ 0.61 of the default's).
    pub fn lens_factors(&self) -> [f64; 4] {
        let own = scotopia_color::cie::lens_channel_factors(self.age);
        let reference = scotopia_color::cie::lens_channel_factors(Self::DEFAULT_AGE);
        std::array::from_fn(|c| own[c] / reference[c])
    }

    /// An observer, checked.
    pub fn new(age: f64, pigmentation: f64) -> Result<Self, ObserverError> {
        if !(Self::AGES.0..=Self::AGES.1).contains(&age) {
            return Err(ObserverError::Age(age));
        }
        if !(0.0..=1.0).contains(&pigmentation) {
            return Err(ObserverError::Pigmentation(pigmentation));
        }
        Ok(Self { age, pigmentation })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_out_of_range_are_refused() {
        assert!(Observer::new(25.0, 0.5).is_ok());
        assert_eq!(Observer::new(0.0, 0.5), Err(ObserverError::Age(0.0)));
        assert!(Observer::new(f64::NAN, 0.5).is_err());
        assert!(Observer::new(70.0, 1.5).is_err());
        assert!(Observer::new(70.0, f64::NAN).is_err());
        assert_eq!(Observer::default(), Observer::new(25.0, 0.5).unwrap());
    }

    #[test]
    fn an_older_lens_passes_less_and_least_of_blue() {
        assert_eq!(Observer::default().lens_factors(), [1.0; 4]);
        let f = Observer::new(70.0, 0.5).unwrap().lens_factors();
        assert!(f[1] < 0.85 && f[1] > 0.7, "{f:?}");
        assert!(f[2] < 0.6 * f[1], "{f:?}");
        assert!(f[3] < f[1] && f[3] > f[2], "{f:?}");
    }
}
