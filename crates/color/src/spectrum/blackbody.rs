//! Planck's law in absolute spectral radiance.

/// Planck constant, J·s (SI 2019, exact).
pub const PLANCK_H: f64 = 6.626_070_15e-34;
/// Speed of light in vacuum, m/s (exact).
pub const LIGHT_C: f64 = 299_792_458.0;
/// Boltzmann constant, J/K (SI 2019, exact).
pub const BOLTZMANN_K: f64 = 1.380_649e-23;

/// Spectral radiance of a black body at `kelvin`, in W·sr⁻¹·m⁻²·nm⁻¹:
/// L(λ, T) = 2hc² / λ⁵ / (exp(hc / λkT) − 1) (Planck 1901), per nm.
#[inline]
pub fn planck(lambda_nm: f64, kelvin: f64) -> f64 {
    let lambda = lambda_nm * 1e-9;
    let exponent = PLANCK_H * LIGHT_C / (lambda * BOLTZMANN_K * kelvin);
    // exp_m1 keeps precision at long wavelengths / high temperatures;
    // above 0.5 the plain exp loses nothing and costs a third as much.
    let denominator = if exponent > 0.5 {
        exponent.exp() - 1.0
    } else {
        exponent.exp_m1()
    };
    let per_metre = 2.0 * PLANCK_H * LIGHT_C * LIGHT_C / lambda.powi(5) / denominator;
    per_metre * 1e-9
}

/// A black-body emitter: Planck radiance at a temperature, times a scale.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Blackbody {
    pub kelvin: f32,
    pub scale: f32,
}

/// 2hc² in W·sr⁻¹·m⁻²·nm⁻¹·nm⁵ (λ in nm): 2·PLANCK_H·LIGHT_C²·10³⁶.
const C1_NM: f32 = (2.0 * PLANCK_H * LIGHT_C * LIGHT_C * 1e36) as f32;
/// hc/k in nm·K.
const C2_NM: f32 = (PLANCK_H * LIGHT_C / BOLTZMANN_K * 1e9) as f32;

impl Blackbody {
    /// `planck` in f32, as a path evaluates it at every bounce: one `expf`
    /// and f32 divisions instead of f64 `exp`, `powi` and divisions.
    /// Relative error below 10⁻⁵ wherever the value is a normal f32 (a
    /// test holds it to `planck`); it underflows to 0 where exp overflows.
    #[inline]
    pub fn eval(&self, lambda: f32) -> f32 {
        let r = 1.0 / lambda;
        let x = C2_NM / self.kelvin * r;
        let denominator = if x > 0.5 { x.exp() - 1.0 } else { x.exp_m1() };
        // C1/λ⁵ first (≤ 10⁹): the product λ⁵·(eˣ − 1) would overflow.
        let r2 = r * r;
        self.scale * C1_NM * (r2 * r2 * r) / denominator
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn single_precision_matches_planck() {
        for kelvin in [500.0f32, 1000.0, 1800.0, 2700.0, 6500.0, 20000.0, 1e6] {
            let b = Blackbody { kelvin, scale: 3.0 };
            for l in (3600..=8300).map(|i| i as f32 * 0.1) {
                let exact = 3.0 * planck(l as f64, kelvin as f64);
                let got = b.eval(l) as f64;
                if exact < 1e-30 {
                    assert!(got < 1e-28, "{kelvin} K, {l} nm: {got}");
                    continue;
                }
                assert!(
                    (got / exact - 1.0).abs() < 1e-5,
                    "{kelvin} K, {l} nm: {got} vs {exact}"
                );
            }
        }
    }

    #[test]
    fn wien_peak_and_stefan_boltzmann() {
        // Wien's displacement law: peak at b / T with b = 2.897771955e-3 m·K (CODATA 2018).
        let t = 5000.0;
        let peak = (2000..20000)
            .map(|i| i as f64 * 0.1)
            .max_by(|&a, &b| planck(a, t).total_cmp(&planck(b, t)))
            .unwrap();
        assert!((peak - 2.897_771_955e-3 / t * 1e9).abs() < 0.2, "{peak}");
        // ∫ L dλ = σT⁴/π with σ = 5.670374419e-8 W·m⁻²·K⁻⁴ (CODATA 2018).
        let integral: f64 = (1..200_000).map(|i| planck(i as f64 * 0.5, t) * 0.5).sum();
        let expected = 5.670_374_419e-8 * t.powi(4) / std::f64::consts::PI;
        assert!(
            (integral / expected - 1.0).abs() < 1e-4,
            "{integral} vs {expected}"
        );
    }
}
