//! Mitsuba 3's `bitmap` texture. Each texel's RGB becomes a Jakob & Hanika
//! 2019 sigmoid spectrum when the image is loaded, so a lookup costs a few
//! multiplications per wavelength. Bilinear filtering blends the four
//! texels' *spectra* (Mitsuba blends their sigmoid coefficients, which is
//! not linear in reflectance); v = 0 is the image's top row, as in Mitsuba.

use std::sync::Arc;

use rayon::prelude::*;
use scotopia_color::spectrum::{normalised_lambda, sigmoid};
use scotopia_color::upsample::jakob2019_texel;
use scotopia_color::Tabulated;
use scotopia_color::{ColorError, RgbSpace, SampledSpectrum, SampledWavelengths, SpectrumKind};

use super::UvTransform;

/// How texels are reconstructed between their centres.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Filter {
    Nearest,
    Bilinear,
}

/// What lies outside [0, 1)².
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Wrap {
    Repeat,
    Mirror,
    Clamp,
}

impl Wrap {
    /// Texel index `i` folded into 0..n.
    #[inline]
    pub(super) fn index(self, i: i64, n: usize) -> usize {
        let n = n as i64;
        (match self {
            Wrap::Repeat => i.rem_euclid(n),
            Wrap::Clamp => i.clamp(0, n - 1),
            Wrap::Mirror => {
                let m = i.rem_euclid(2 * n);
                if m >= n {
                    2 * n - 1 - m
                } else {
                    m
                }
            }
        }) as usize
    }
}

/// One texel: `scale · S(c₀t² + c₁t + c₂)` (also a mesh attribute's
/// colour per vertex or face).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Texel {
    coeffs: [f32; 3],
    scale: f32,
}

impl Texel {
    /// The sigmoid of linear sRGB `rgb` upsampled for use as `kind` (the
    /// illuminant itself is applied by the caller).
    pub(super) fn new(
        rgb: [f32; 3],
        space: RgbSpace,
        kind: SpectrumKind,
    ) -> Result<Self, ColorError> {
        jakob2019_texel(rgb, space, kind).map(|(coeffs, scale)| Texel { coeffs, scale })
    }

    /// The value at normalised wavelength `t` (see `normalised_lambda`).
    #[inline]
    pub(super) fn at(&self, t: f32) -> f32 {
        let c = &self.coeffs;
        self.scale * sigmoid((c[0] * t + c[1]) * t + c[2])
    }
}

#[derive(Debug, Clone, PartialEq)]
pub struct Bitmap {
    width: usize,
    height: usize,
    /// Row-major, top row first.
    texels: Vec<Texel>,
    /// The colour space's white for emission textures.
    illuminant: Option<Arc<Tabulated>>,
    mean: f32,
    pub filter: Filter,
    pub wrap: Wrap,
    pub to_uv: UvTransform,
}

impl Bitmap {
    /// Upsamples linear `rgb` (row-major, top row first) in `space` for use
    /// as `kind`. Reflectances are clamped to [0, 1].
    pub fn from_rgb(
        width: usize,
        height: usize,
        rgb: &[[f32; 3]],
        space: RgbSpace,
        kind: SpectrumKind,
    ) -> Result<Self, ColorError> {
        if width == 0 || height == 0 || rgb.len() != width * height {
            return Err(ColorError::OutOfRange(format!(
                "a {width}×{height} bitmap needs {} texels, got {}",
                width * height,
                rgb.len()
            )));
        }
        let texels = rgb
            .par_iter()
            .map(|&c| Texel::new(c, space, kind))
            .collect::<Result<Vec<_>, _>>()?;
        let clamp = |v: f32| {
            let v = if v.is_finite() { v.max(0.0) } else { 0.0 };
            if kind == SpectrumKind::Reflectance {
                v.min(1.0)
            } else {
                v
            }
        };
        let sum: f64 = rgb
            .iter()
            .map(|c| c.iter().map(|&v| clamp(v) as f64).sum::<f64>() / 3.0)
            .sum();
        Ok(Self {
            width,
            height,
            texels,
            illuminant: (kind == SpectrumKind::Illuminant)
                .then(|| space.def().illuminant_normalised.clone()),
            mean: (sum / rgb.len() as f64) as f32,
            filter: Filter::Bilinear,
            wrap: Wrap::Repeat,
            to_uv: UvTransform::default(),
        })
    }

    pub fn width(&self) -> usize {
        self.width
    }

    pub fn height(&self) -> usize {
        self.height
    }

    /// Mean of the texels' RGB components (≈ the mean spectral value).
    pub fn mean(&self) -> f32 {
        self.mean
    }

    /// The largest value any texel takes at each of `lambdas`.
    pub fn max_over_texels(&self, lambdas: &[f32]) -> Vec<f32> {
        lambdas
            .par_iter()
            .map(|&l| {
                let t = normalised_lambda(l);
                let white = self.illuminant.as_ref().map_or(1.0, |ill| ill.eval(l));
                self.texels
                    .iter()
                    .map(|texel| white * texel.at(t))
                    .fold(0.0, f32::max)
            })
            .collect()
    }

    /// Texel (x, y)'s spectrum on `wl`, given the wavelengths' normalised
    /// positions `t` and the illuminant's values there.
    #[inline]
    pub(crate) fn texel<const K: usize>(
        &self,
        x: usize,
        y: usize,
        t: &[f32; K],
        white: &[f32; K],
    ) -> SampledSpectrum<K> {
        let texel = &self.texels[y * self.width + x];
        SampledSpectrum::from_fn(|i| white[i] * texel.at(t[i]))
    }

    /// The illuminant (or 1) and normalised wavelength per sample of `wl`.
    #[inline]
    pub(crate) fn prepare<const K: usize>(
        &self,
        wl: &SampledWavelengths<K>,
    ) -> ([f32; K], [f32; K]) {
        let t = wl.lambdas().map(normalised_lambda);
        let white = match &self.illuminant {
            Some(ill) => wl.lambdas().map(|l| ill.eval(l)),
            None => [1.0; K],
        };
        (t, white)
    }

    /// Texel (x, y)'s spectrum on `wl`, unfiltered (for environment maps).
    pub fn texel_value<const K: usize>(
        &self,
        x: usize,
        y: usize,
        wl: &SampledWavelengths<K>,
    ) -> SampledSpectrum<K> {
        let (t, white) = self.prepare(wl);
        self.texel(x.min(self.width - 1), y.min(self.height - 1), &t, &white)
    }

    /// The blend of texels (xs[i], ys[j]) with weights `a` along x and y,
    /// texel by texel in spectrum.
    pub fn bilinear<const K: usize>(
        &self,
        wl: &SampledWavelengths<K>,
        xs: [usize; 2],
        ys: [usize; 2],
        [ax, ay]: [f32; 2],
    ) -> SampledSpectrum<K> {
        let (t, white) = self.prepare(wl);
        let row = |y| {
            self.texel(xs[0], y, &t, &white) * (1.0 - ax) + self.texel(xs[1], y, &t, &white) * ax
        };
        row(ys[0]) * (1.0 - ay) + row(ys[1]) * ay
    }

    /// Like `bilinear`, but blending the texels' unit spectra (scale 1) and
    /// their scales separately and multiplying the two blends: Mitsuba 3's
    /// environment map (envmap.cpp, spectral variants) interpolates this
    /// way, which differs from the blend of the texels' spectra where
    /// neighbouring texels differ in brightness (museum.exr's mean xy moves
    /// by (0.0008, 0.0007)). Exact at texel centres.
    pub fn bilinear_scale_split<const K: usize>(
        &self,
        wl: &SampledWavelengths<K>,
        xs: [usize; 2],
        ys: [usize; 2],
        [ax, ay]: [f32; 2],
    ) -> SampledSpectrum<K> {
        let (t, white) = self.prepare(wl);
        let mut unit = SampledSpectrum::splat(0.0);
        let mut scale = 0.0;
        for (y, wy) in [(ys[0], 1.0 - ay), (ys[1], ay)] {
            for (x, wx) in [(xs[0], 1.0 - ax), (xs[1], ax)] {
                let Texel {
                    coeffs: c,
                    scale: s,
                } = self.texels[y * self.width + x];
                let w = wx * wy;
                unit += SampledSpectrum::from_fn(|i| {
                    w * white[i] * sigmoid((c[0] * t[i] + c[1]) * t[i] + c[2])
                });
                scale += w * s;
            }
        }
        unit * scale
    }

    /// The filtered value at texture coordinates `uv`.
    pub fn eval<const K: usize>(
        &self,
        wl: &SampledWavelengths<K>,
        uv: [f32; 2],
    ) -> SampledSpectrum<K> {
        let [u, v] = self.to_uv.apply(uv);
        let (w, h) = (self.width, self.height);
        match self.filter {
            Filter::Nearest => {
                let x = self.wrap.index((u * w as f32).floor() as i64, w);
                let y = self.wrap.index((v * h as f32).floor() as i64, h);
                self.texel_value(x, y, wl)
            }
            Filter::Bilinear => {
                // Texel centres sit at half-integers.
                let (px, py) = (u * w as f32 - 0.5, v * h as f32 - 0.5);
                let (fx, fy) = (px.floor(), py.floor());
                let (x0, y0) = (fx as i64, fy as i64);
                let xs = [self.wrap.index(x0, w), self.wrap.index(x0 + 1, w)];
                let ys = [self.wrap.index(y0, h), self.wrap.index(y0 + 1, h)];
                self.bilinear(wl, xs, ys, [px - fx, py - fy])
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use scotopia_color::{rgb_to_spectrum, UpsampleMethod};

    fn wl() -> SampledWavelengths<4> {
        SampledWavelengths::new([450.0, 520.0, 600.0, 680.0], [1.0; 4])
    }

    fn two_by_two() -> Bitmap {
        let rgb = [
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
            [0.5, 0.5, 0.5],
        ];
        Bitmap::from_rgb(2, 2, &rgb, RgbSpace::Srgb, SpectrumKind::Reflectance).unwrap()
    }

    fn reference(rgb: [f32; 3]) -> SampledSpectrum<4> {
        rgb_to_spectrum(
            rgb,
            RgbSpace::Srgb,
            UpsampleMethod::Jakob2019,
            SpectrumKind::Reflectance,
        )
        .unwrap()
        .sample(&wl())
    }

    fn close(a: SampledSpectrum<4>, b: SampledSpectrum<4>) {
        for i in 0..4 {
            assert!((a[i] - b[i]).abs() < 1e-5, "{a:?} vs {b:?}");
        }
    }

    #[test]
    fn texel_centres_return_their_own_spectrum() {
        let b = two_by_two();
        // Top-left texel centre is (0.25, 0.25); v grows downwards.
        close(b.eval(&wl(), [0.25, 0.25]), reference([1.0, 0.0, 0.0]));
        close(b.eval(&wl(), [0.75, 0.25]), reference([0.0, 1.0, 0.0]));
        close(b.eval(&wl(), [0.25, 0.75]), reference([0.0, 0.0, 1.0]));
        // Repeat: one period away is the same.
        close(b.eval(&wl(), [1.25, -0.75]), reference([1.0, 0.0, 0.0]));
    }

    #[test]
    fn bilinear_blends_spectra_linearly() {
        let b = two_by_two();
        let mid = b.eval(&wl(), [0.5, 0.25]);
        let want = (reference([1.0, 0.0, 0.0]) + reference([0.0, 1.0, 0.0])) * 0.5;
        close(mid, want);
    }

    /// Between a bright white texel and a dim blue one, Mitsuba's envmap
    /// blend is (blend of unit spectra) × (blend of scales), not the blend
    /// of the spectra: the blue weighs far more than its radiance.
    #[test]
    fn the_scale_split_blend_multiplies_the_blends() {
        let (a, b) = ([4.0, 4.0, 4.0], [0.02, 0.05, 0.2]);
        let bm = Bitmap::from_rgb(2, 1, &[a, b], RgbSpace::Srgb, SpectrumKind::Unbounded).unwrap();
        let unit = |rgb: [f32; 3]| {
            let s = 2.0 * rgb.iter().copied().fold(0.0, f32::max);
            (reference(rgb.map(|v| v / s)), s)
        };
        let ((ua, sa), (ub, sb)) = (unit(a), unit(b));
        for t in [0.0, 0.3, 0.5, 1.0] {
            let got = bm.bilinear_scale_split(&wl(), [0, 1], [0, 0], [t, 0.0]);
            let want = (ua * (1.0 - t) + ub * t) * (sa * (1.0 - t) + sb * t);
            for i in 0..4 {
                assert!(
                    (got[i] - want[i]).abs() < 1e-5 * want[i].max(1.0),
                    "t {t}: {got:?} vs {want:?}"
                );
            }
        }
        // At the midpoint the blue texel's share is about half, not 1/40.
        let mid = bm.bilinear_scale_split(&wl(), [0, 1], [0, 0], [0.5, 0.0]);
        let plain = bm.bilinear(&wl(), [0, 1], [0, 0], [0.5, 0.0]);
        assert!(
            mid[0] / mid[3] > 1.5 * plain[0] / plain[3],
            "{mid:?} vs {plain:?}"
        );
    }

    #[test]
    fn wrap_modes_fold_indices() {
        assert_eq!(Wrap::Repeat.index(-1, 4), 3);
        assert_eq!(Wrap::Clamp.index(-1, 4), 0);
        assert_eq!(Wrap::Clamp.index(9, 4), 3);
        assert_eq!(Wrap::Mirror.index(-1, 4), 0);
        assert_eq!(Wrap::Mirror.index(4, 4), 3);
        assert_eq!(Wrap::Mirror.index(8, 4), 0);
        assert_eq!(
            Wrap::Repeat.index(i64::MIN, 3),
            i64::MIN.rem_euclid(3) as usize
        );
    }

    #[test]
    fn nearest_and_mean() {
        let mut b = two_by_two();
        b.filter = Filter::Nearest;
        close(b.eval(&wl(), [0.99, 0.01]), reference([0.0, 1.0, 0.0]));
        assert!((b.mean() - (1.0 + 1.0 + 1.0 + 1.5) / 12.0).abs() < 1e-6);
        assert!(Bitmap::from_rgb(
            2,
            2,
            &[[0.0; 3]; 3],
            RgbSpace::Srgb,
            SpectrumKind::Reflectance
        )
        .is_err());
    }

    #[test]
    fn the_maximum_over_texels_is_the_brightest_texel_per_wavelength() {
        let b = two_by_two();
        let lambdas = [450.0, 520.0, 600.0, 680.0];
        let max = b.max_over_texels(&lambdas);
        let texels = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [0.5; 3]];
        for (i, m) in max.iter().enumerate() {
            let want = texels.iter().map(|&c| reference(c)[i]).fold(0.0, f32::max);
            assert!((m - want).abs() < 1e-5, "{lambdas:?}: {max:?}");
        }
        // Blue wins at 450 nm, red at 680 nm: different texels.
        assert!((max[0] - reference([0.0, 0.0, 1.0])[0]).abs() < 1e-5);
        assert!((max[3] - reference([1.0, 0.0, 0.0])[3]).abs() < 1e-5);
    }

    #[test]
    fn emission_texels_carry_the_illuminant() {
        let rgb = [[2.0, 2.0, 2.0]];
        let b = Bitmap::from_rgb(1, 1, &rgb, RgbSpace::Srgb, SpectrumKind::Illuminant).unwrap();
        let want = rgb_to_spectrum(
            rgb[0],
            RgbSpace::Srgb,
            UpsampleMethod::Jakob2019,
            SpectrumKind::Illuminant,
        )
        .unwrap()
        .sample(&wl());
        close(b.eval(&wl(), [0.3, 0.8]) * 0.1, want * 0.1);
    }
}
