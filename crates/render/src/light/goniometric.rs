//! A goniometric point light: a luminaire measured as luminous intensity
//! I(γ, C) in candela (type C photometry, as IES LM-63 and EULUMDAT files
//! give it) times a relative spectral distribution.
//!
//! In the light's frame the photometric nadir (γ = 0) is local +z, the
//! C = 0° half-plane contains +x and C = 90° contains +y (issue 24's
//! convention: aimed like Mitsuba's spot light, along +z).
//!
//! The file's table is resampled once onto a regular grid (the caller's
//! smooth interpolation evaluated at every node); between nodes the grid
//! is read bilinearly. Directions for light paths are drawn cell by cell
//! in proportion to the mean of the cell's corners times its solid angle,
//! uniformly in (C, cos γ) within a cell, so the density per solid angle
//! is constant over a cell.

use std::f32::consts::PI;
use std::sync::Arc;

use scotopia_color::{SampledSpectrum, SampledWavelengths, Spectrum};

use super::simple::point_sample;
use super::{spectral_power, LightSample, Power};
use crate::math::{Frame, Vec3};
use crate::sampling::distribution::Distribution2D;

/// Luminous intensity on a regular (γ, C) grid and the distribution that
/// samples directions by it; shared by every light made from one file.
#[derive(Debug, Clone, PartialEq)]
pub struct IntensityGrid {
    /// Rows of γ = i · π / rows, i = 0..=rows; each row `columns` values at
    /// C = j · 2π / columns (periodic). One column: rotationally symmetric.
    values: Vec<f32>,
    rows: usize,
    columns: usize,
    distribution: Distribution2D,
    /// ∫ I dΩ of the bilinear grid, lm (with I in cd).
    flux: f64,
}

impl IntensityGrid {
    /// The grid of `rows` γ steps over [0°, 180°] and `columns` C steps
    /// over [0°, 360°), from `intensity(γ_deg, c_deg)` (cd, ≥ 0).
    /// `None` when the intensity is zero everywhere or not finite.
    pub fn new(rows: usize, columns: usize, intensity: impl Fn(f32, f32) -> f32) -> Option<Self> {
        let (rows, columns) = (rows.max(1), columns.max(1));
        let mut values = Vec::with_capacity((rows + 1) * columns);
        for i in 0..=rows {
            let gamma = 180.0 * i as f32 / rows as f32;
            for j in 0..columns {
                let v = intensity(gamma, 360.0 * j as f32 / columns as f32);
                if !v.is_finite() {
                    return None;
                }
                values.push(v.max(0.0));
            }
        }
        let at = |i: usize, j: usize| values[i * columns + j % columns];
        let dc = 2.0 * PI / columns as f32;
        let mut cells = Vec::with_capacity(rows * columns);
        let mut flux = 0.0f64;
        for i in 0..rows {
            let solid = dc * band(i, rows);
            for j in 0..columns {
                let mean = 0.25 * (at(i, j) + at(i, j + 1) + at(i + 1, j) + at(i + 1, j + 1));
                cells.push(mean * solid);
                flux += (mean * solid) as f64;
            }
        }
        (flux > 0.0).then(|| Self {
            distribution: Distribution2D::new(&cells, columns),
            values,
            rows,
            columns,
            flux,
        })
    }

    /// ∫ I dΩ over the sphere, lm.
    pub fn flux(&self) -> f64 {
        self.flux
    }

    /// (γ_lo, γ_hi): the intensity is zero at every γ outside them. Read
    /// from the grid's rows: bilinear reading is zero between two rows of
    /// zeros, so the lit band runs from the row before the first lit row to
    /// the row after the last (the light hierarchy's cone of directions).
    pub fn lit_gamma(&self) -> (f32, f32) {
        let lit = |i: &usize| {
            self.values[i * self.columns..(i + 1) * self.columns]
                .iter()
                .any(|&v| v > 0.0)
        };
        let first = (0..=self.rows).find(lit).unwrap_or(0);
        let last = (0..=self.rows).rev().find(lit).unwrap_or(self.rows);
        let step = PI / self.rows as f32;
        (
            first.saturating_sub(1) as f32 * step,
            ((last + 1).min(self.rows) as f32 * step).min(PI),
        )
    }

    /// I in local direction `w` (unit), cd.
    pub fn intensity(&self, w: Vec3) -> f32 {
        let (gamma, c) = angles(w);
        let y = gamma / PI * self.rows as f32;
        let i = (y as usize).min(self.rows - 1);
        let fy = (y - i as f32).clamp(0.0, 1.0);
        let x = c / (2.0 * PI) * self.columns as f32;
        let j = (x as usize).min(self.columns - 1);
        let fx = (x - j as f32).clamp(0.0, 1.0);
        let at = |i: usize, j: usize| self.values[i * self.columns + j % self.columns];
        let row = |i: usize| at(i, j) + fx * (at(i, j + 1) - at(i, j));
        row(i) + fy * (row(i + 1) - row(i))
    }

    /// A local direction drawn by the grid and its density per solid angle.
    pub fn sample(&self, u: [f32; 2]) -> Option<(Vec3, f32)> {
        let ([x, y], pdf_uv) = self.distribution.sample(u)?;
        let rows = self.rows as f32;
        let i = ((y * rows) as usize).min(self.rows - 1);
        let f = (y * rows - i as f32).clamp(0.0, 1.0);
        let (c0, c1) = (edge_cos(i, self.rows), edge_cos(i + 1, self.rows));
        let cos = c0 + f * (c1 - c0);
        let sin = (1.0 - cos * cos).max(0.0).sqrt();
        let phi = 2.0 * PI * x;
        let w = Vec3::new(sin * phi.cos(), sin * phi.sin(), cos);
        let pdf = self.cell_density(i, pdf_uv);
        (pdf > 0.0).then_some((w, pdf))
    }

    /// Density per solid angle of [`IntensityGrid::sample`] drawing local
    /// direction `w`.
    pub fn pdf(&self, w: Vec3) -> f32 {
        let (gamma, c) = angles(w);
        let y = (gamma / PI).clamp(0.0, 1.0 - f32::EPSILON);
        let i = ((y * self.rows as f32) as usize).min(self.rows - 1);
        let x = (c / (2.0 * PI)).clamp(0.0, 1.0 - f32::EPSILON);
        self.cell_density(i, self.distribution.pdf([x, y]))
    }

    /// A cell's density per solid angle from its density per unit (x, y):
    /// the cell holds pdf_uv / (rows · columns) of the probability over
    /// (2π / columns) · (cos γᵢ − cos γᵢ₊₁) steradians.
    fn cell_density(&self, row: usize, pdf_uv: f32) -> f32 {
        let solid = band(row, self.rows) * 2.0 * PI;
        if solid <= 0.0 {
            return 0.0;
        }
        pdf_uv / (self.rows as f32 * solid)
    }
}

/// cos γ at the i-th of `rows` equal γ steps over [0, π].
fn edge_cos(i: usize, rows: usize) -> f32 {
    (PI * i as f32 / rows as f32).cos()
}

/// cos γᵢ − cos γᵢ₊₁: the band's solid angle per radian of C.
fn band(i: usize, rows: usize) -> f32 {
    (edge_cos(i, rows) - edge_cos(i + 1, rows)).max(0.0)
}

/// (γ, C) of local direction `w`: γ from +z, C from +x towards +y, in
/// [0, π] × [0, 2π).
fn angles(w: Vec3) -> (f32, f32) {
    let gamma = w.z.clamp(-1.0, 1.0).acos();
    let mut c = w.y.atan2(w.x);
    if c < 0.0 {
        c += 2.0 * PI;
    }
    (gamma, c.min(2.0 * PI * (1.0 - f32::EPSILON)))
}

/// A luminaire at `position`: I(γ, C, λ) = grid(γ, C) · spectrum(λ), with
/// the spectrum scaled so that 683 ∫ S ȳ dλ is the lamp's multiplier (1:
/// the grid's candela are the rendered luminous intensity).
#[derive(Debug, Clone, PartialEq)]
pub struct GoniometricLight {
    pub position: Vec3,
    /// n: the nadir (γ = 0); s: C = 0°; t: C = 90°.
    pub frame: Frame,
    pub spectrum: Spectrum,
    pub grid: Arc<IntensityGrid>,
}

impl GoniometricLight {
    /// Spectral intensity in world direction `d` (unit), W·sr⁻¹·nm⁻¹.
    pub fn intensity_towards<const K: usize>(
        &self,
        wl: &SampledWavelengths<K>,
        d: Vec3,
    ) -> SampledSpectrum<K> {
        let i = self.grid.intensity(self.frame.to_local(d));
        if i <= 0.0 {
            return SampledSpectrum::splat(0.0);
        }
        self.spectrum.sample(wl) * i
    }

    pub fn sample_li<const K: usize>(
        &self,
        wl: &SampledWavelengths<K>,
        p: Vec3,
    ) -> Option<LightSample<K>> {
        point_sample(self.position, p, |d| self.intensity_towards(wl, d))
    }

    /// A world direction for a light path and its density per solid angle.
    pub fn sample_direction(&self, u: [f32; 2]) -> Option<(Vec3, f32)> {
        let (w, pdf) = self.grid.sample(u)?;
        Some((self.frame.to_world(w), pdf))
    }

    pub fn pdf_direction(&self, d: Vec3) -> f32 {
        self.grid.pdf(self.frame.to_local(d))
    }

    /// Φ = ∫ I dΩ · (∫ S dλ, 683 ∫ S ȳ dλ).
    pub fn power(&self) -> Power {
        spectral_power(&self.spectrum).scaled(self.grid.flux())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn seq(n: usize) -> impl Iterator<Item = [f32; 2]> {
        // A rank-1 lattice in [0, 1)²: even coverage for integrals.
        let g = 0.618_034f32;
        (0..n).map(move |k| [(k as f32 + 0.5) / n as f32, (k as f32 * g).fract()])
    }

    #[test]
    fn an_isotropic_grid_holds_four_pi_lumens_per_candela() {
        let g = IntensityGrid::new(180, 1, |_, _| 2.0).unwrap();
        assert!((g.flux() / (8.0 * std::f64::consts::PI) - 1.0).abs() < 1e-5);
        assert!((g.intensity(Vec3::new(0.3, -0.5, 0.81).normalize()) - 2.0).abs() < 1e-6);
    }

    #[test]
    fn sampled_directions_integrate_the_intensity() {
        // E[I(ω)/p(ω)] = ∫ I dΩ, and the sampler's pdf is pdf(ω).
        let g = IntensityGrid::new(90, 48, |gamma, c| {
            let down = gamma.to_radians().cos().max(0.0);
            down * (1.0 + 0.5 * c.to_radians().cos())
        })
        .unwrap();
        let n = 200_000;
        let mut sum = 0.0f64;
        for u in seq(n) {
            let (w, pdf) = g.sample(u).unwrap();
            // (At the poles every column meets: C is undefined there.)
            let pole = w.z.abs() > 1.0 - 1e-6;
            assert!(
                pole || (g.pdf(w) / pdf - 1.0).abs() < 1e-3,
                "{w:?} {pdf} {}",
                g.pdf(w)
            );
            sum += (g.intensity(w) / pdf) as f64;
        }
        let est = sum / n as f64;
        // ∫ cos γ (1 + ½ cos C) over the lower hemisphere = π.
        assert!(
            (g.flux() / std::f64::consts::PI - 1.0).abs() < 2e-3,
            "{}",
            g.flux()
        );
        assert!((est / g.flux() - 1.0).abs() < 5e-3, "{est} vs {}", g.flux());
    }

    #[test]
    fn the_frame_aims_the_nadir_and_the_c_planes() {
        // Brighter towards C = 90° (+y) than C = 270°.
        let g = Arc::new(
            IntensityGrid::new(36, 36, |gamma, c| {
                (1.0 + c.to_radians().sin()) * (gamma < 90.0) as u8 as f32
            })
            .unwrap(),
        );
        let light = GoniometricLight {
            position: Vec3::ZERO,
            frame: Frame::from_normal(Vec3::new(0.0, 0.0, 1.0)),
            spectrum: Spectrum::Constant(1.0),
            grid: g,
        };
        let local_y = light.frame.t;
        let toward = |d: Vec3| light.grid.intensity(light.frame.to_local(d.normalize()));
        assert!(toward(local_y + light.frame.n) > 1.5);
        assert!(toward(-local_y + light.frame.n) < 0.5);
        assert_eq!(toward(-light.frame.n), 0.0);
    }
}
