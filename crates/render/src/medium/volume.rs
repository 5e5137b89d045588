//! The fields a heterogeneous medium reads (Mitsuba 3's volumes): a
//! `gridvolume` over a voxel grid or a `constvolume`'s constant spectrum.
//!
//! A grid spans the unit cube of its own space, which `to_world` places in
//! the scene (or, with `use_grid_bbox`, the box its file records, placed
//! by `to_world`). One channel is grey. Three channels are RGB, which
//! Mitsuba's spectral variants upsample when the grid is loaded: each
//! cell's colour c becomes s · S(c / s) with s = 2·max(c) and S the Jakob &
//! Hanika (2019) sigmoid spectrum of the halved colour; a trilinear lookup
//! blends the eight cells' unit spectra and, apart, their scales, and
//! multiplies the two (Mitsuba 3's `gridvolume`, `interpolate_spectral`).

use rayon::prelude::*;
use scotopia_color::spectrum::{normalised_lambda, sigmoid};
use scotopia_color::upsample::jakob2019_texel;
use scotopia_color::{RgbSpace, SampledSpectrum, SampledWavelengths, Spectrum, SpectrumKind};

use super::Grid;
use crate::math::{Transform, Vec3};

/// How values are reconstructed between cell centres (`filter_type`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Filter {
    Trilinear,
    Nearest,
}

/// A `gridvolume`.
#[derive(Debug, Clone, PartialEq)]
pub struct GridVolume {
    grid: Grid,
    /// For an RGB grid: each cell's sigmoid coefficients and scale.
    sigmoids: Option<Vec<([f32; 3], f32)>>,
    pub filter: Filter,
    /// World to the grid's unit cube.
    to_local: Transform,
    /// Largest value at any wavelength and place (the grey maximum, or the
    /// largest scale of an RGB grid: a sigmoid is at most 1).
    max: f32,
}

impl GridVolume {
    /// A grid of 1 or 3 channels (3: RGB, upsampled) placed by `to_world`:
    /// its unit cube, or with `use_grid_bbox` the grid's own box. Errors
    /// say what cannot be used.
    pub fn new(
        grid: Grid,
        filter: Filter,
        to_world: Transform,
        use_grid_bbox: bool,
    ) -> Result<Self, String> {
        let mut to_local = to_world.inverse();
        if use_grid_bbox {
            let b = grid.bounds;
            let e = b.max - b.min;
            let unit = Transform::scale(Vec3::new(1.0 / e.x, 1.0 / e.y, 1.0 / e.z))
                .filter(|_| e.x > 0.0 && e.y > 0.0 && e.z > 0.0)
                .ok_or_else(|| {
                    format!(
                        "use_grid_bbox needs a box of positive extent, the file's is ({}, {}, {}) – ({}, {}, {})",
                        b.min.x, b.min.y, b.min.z, b.max.x, b.max.y, b.max.z
                    )
                })?;
            to_local = unit
                .then_after(&Transform::translate(-b.min))
                .then_after(&to_local);
        }
        let (sigmoids, max) = match grid.channels() {
            1 => (None, grid.max(0)),
            3 => {
                let [nx, ny, nz] = grid.resolution();
                let cells: Vec<([f32; 3], f32)> = (0..nx * ny * nz)
                    .into_par_iter()
                    .map(|i| {
                        let rgb = [grid.value(i, 0), grid.value(i, 1), grid.value(i, 2)];
                        jakob2019_texel(rgb, RgbSpace::Srgb, SpectrumKind::Unbounded)
                    })
                    .collect::<Result<_, _>>()
                    .map_err(|e| e.to_string())?;
                let max = cells.iter().map(|c| c.1).fold(0.0f32, f32::max);
                (Some(cells), max)
            }
            n => {
                return Err(format!(
                    "a grid of {n} channels is not a spectrum (1: grey, 3: RGB)"
                ))
            }
        };
        Ok(Self {
            grid,
            sigmoids,
            filter,
            to_local,
            max,
        })
    }

    pub fn grid(&self) -> &Grid {
        &self.grid
    }

    pub fn is_rgb(&self) -> bool {
        self.sigmoids.is_some()
    }

    /// The largest value at any wavelength.
    pub fn max(&self) -> f32 {
        self.max
    }

    pub fn to_local(&self) -> &Transform {
        &self.to_local
    }

    /// A bound on cell `cell`'s value at every wavelength.
    pub(super) fn cell_top(&self, cell: usize) -> f32 {
        match &self.sigmoids {
            Some(s) => s[cell].1,
            None => self.grid.value(cell, 0),
        }
    }

    /// The value at `p` in the grid's unit cube for the normalised
    /// wavelengths `t` (`normalised_lambda`).
    #[inline]
    pub fn eval_local<const K: usize>(&self, p: Vec3, t: &[f32; K]) -> [f32; K] {
        let unit = |c: &([f32; 3], f32), t: f32| {
            let k = &c.0;
            sigmoid((k[0] * t + k[1]) * t + k[2])
        };
        match (self.filter, &self.sigmoids) {
            (Filter::Nearest, None) => [self.grid.value(self.grid.nearest(p), 0); K],
            (Filter::Nearest, Some(s)) => {
                let c = &s[self.grid.nearest(p)];
                t.map(|t| c.1 * unit(c, t))
            }
            (Filter::Trilinear, None) => [self.grid.lookup(p, 0); K],
            (Filter::Trilinear, Some(s)) => {
                let corners = self.grid.corners(p);
                let scale: f32 = corners.iter().map(|&(i, w)| w * s[i].1).sum();
                t.map(|t| {
                    scale
                        * corners
                            .iter()
                            .map(|&(i, w)| w * unit(&s[i], t))
                            .sum::<f32>()
                })
            }
        }
    }
}

/// A medium's σ_t or albedo: a constant spectrum (a plain spectrum or a
/// `constvolume`) or a grid.
#[derive(Debug, Clone, PartialEq)]
pub enum Field {
    /// The value everywhere; `to_local` (world to the constvolume's unit
    /// cube) bounds a medium whose σ_t it is, as in Mitsuba, where every
    /// volume spans its `to_world`'s unit cube.
    Constant {
        value: Spectrum,
        to_local: Transform,
    },
    Grid(GridVolume),
}

impl Field {
    /// A constant spanning the unit cube (Mitsuba's default `to_world`).
    pub fn constant(value: Spectrum) -> Self {
        Field::Constant {
            value,
            to_local: Transform::IDENTITY,
        }
    }

    /// World to the field's unit cube.
    pub fn to_local(&self) -> &Transform {
        match self {
            Field::Constant { to_local, .. } => to_local,
            Field::Grid(g) => g.to_local(),
        }
    }

    /// The value at world point `p`.
    pub fn eval<const K: usize>(&self, p: Vec3, wl: &SampledWavelengths<K>) -> SampledSpectrum<K> {
        match self {
            Field::Constant { value, .. } => value.sample(wl),
            Field::Grid(g) => {
                let t = wl.lambdas().map(normalised_lambda);
                SampledSpectrum(g.eval_local(g.to_local().point(p), &t))
            }
        }
    }
}
