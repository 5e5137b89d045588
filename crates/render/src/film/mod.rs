//! The film: per pixel, the running filter-weighted sums of the X, Y, Z,
//! V′ estimates of the camera samples that reach it (absolute: Y in cd/m²,
//! V′ in scotopic cd/m²), the sum of their weights, and how many samples
//! were its own (see `filter`: a sample lands in one pixel and is
//! splatted into those its filter reaches).

mod checkpoint;
mod filter;
mod spectral;

use scotopia_color::{SampledSpectrum, SampledWavelengths};

pub use checkpoint::{fingerprint, Checkpoint, SampleCounts, Source};
pub use filter::{Filter, FilterSampler};
pub use spectral::Bands;

/// Accumulated estimates of one pixel.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct PixelSum {
    /// Σ f·L over the camera samples that reach the pixel (and the
    /// light-tracing splats).
    pub xyzv: [f64; 4],
    /// Σ f over the camera samples that reach it: the pixel is
    /// `xyzv / weight`. With the box filter, the sample count.
    pub weight: f64,
    /// Camera samples that landed in this pixel.
    pub samples: u32,
}

impl PixelSum {
    /// Adds a camera sample that reaches this pixel with filter weight `f`
    /// (it need not be this pixel's: `samples` is counted apart).
    #[inline]
    pub fn add_weighted(&mut self, xyzv: [f32; 4], f: f32) {
        // Written lane by lane so that it compiles to one conversion and
        // one add of four f64 (the splat's inner loop, `integrator::pass`).
        let [a, b, c, d] = xyzv;
        self.xyzv[0] += f64::from(a * f);
        self.xyzv[1] += f64::from(b * f);
        self.xyzv[2] += f64::from(c * f);
        self.xyzv[3] += f64::from(d * f);
        self.weight += f64::from(f);
    }

    /// Adds a light-tracing contribution, which is not a camera sample:
    /// the sum grows, the weight and the count do not.
    #[inline]
    pub fn add_splat(&mut self, xyzv: [f32; 4]) {
        for (s, v) in self.xyzv.iter_mut().zip(xyzv) {
            *s += v as f64;
        }
    }

    /// The pixel's X, Y, Z, V′: the weighted mean (zero before any
    /// sample reached it).
    pub fn mean(&self) -> [f32; 4] {
        if self.weight <= 0.0 {
            return [0.0; 4];
        }
        self.xyzv.map(|v| (v / self.weight) as f32)
    }
}

/// A width × height image of pixel sums, row-major, top row first, with
/// optional spectral band sums.
#[derive(Debug, Clone, PartialEq)]
pub struct Film {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<PixelSum>,
    pub bands: Option<Bands>,
    /// Band sums, `row_stride()` values per row (one unused slot per row
    /// when there are no bands, so rows can be split the same way).
    pub spectral: Vec<f64>,
    /// Weighted sums of squared camera samples, Σ f·L², `moment_stride()`
    /// per row (one unused entry per row unless [`Film::keep_moments`] was
    /// called).
    pub moments: Vec<[f64; 4]>,
    moments_kept: bool,
}

/// Bytes the output takes per pixel beyond the sums (the X, Y, Z, V′
/// image and its copy written to the EXR).
const OUTPUT_BYTES_PER_PIXEL: u64 = 32;

impl Film {
    /// A film, after checking that its sums (and band sums) and the image
    /// written from them fit the memory budget (`scotopia_image::limits`).
    pub fn try_new(
        width: u32,
        height: u32,
        bands: Option<Bands>,
    ) -> Result<Self, scotopia_image::TooLarge> {
        Self::check_size(width, height, bands)?;
        Ok(Self::new(width, height, bands))
    }

    /// Whether a `width` × `height` film (with `bands`) fits the memory
    /// budget; the error says how much it needs and what the limit is.
    pub fn check_size(
        width: u32,
        height: u32,
        bands: Option<Bands>,
    ) -> Result<(), scotopia_image::TooLarge> {
        let per_pixel = (std::mem::size_of::<PixelSum>() as u64)
            .saturating_add(8u64.saturating_mul(bands.map_or(1, |b| b.0 as u64)))
            .saturating_add(OUTPUT_BYTES_PER_PIXEL);
        scotopia_image::check_image("a film", width as u64, height as u64, per_pixel)?;
        Ok(())
    }

    /// A film of a size already checked (see `try_new`, the only way in
    /// from outside, so no size from input reaches the allocator unchecked).
    pub(crate) fn new(width: u32, height: u32, bands: Option<Bands>) -> Self {
        let mut film = Self {
            width,
            height,
            pixels: vec![PixelSum::default(); width as usize * height as usize],
            bands,
            spectral: Vec::new(),
            moments: vec![[0.0; 4]; height as usize],
            moments_kept: false,
        };
        film.spectral = vec![0.0; film.row_stride() * height as usize];
        film
    }

    /// Keeps each pixel's sum of squared camera samples too (the second
    /// moments a distributed render's shards return).
    pub fn keep_moments(&mut self) {
        self.moments = vec![[0.0; 4]; self.pixels.len()];
        self.moments_kept = true;
    }

    /// Per-pixel sums of squared camera samples, if kept.
    pub fn kept_moments(&self) -> Option<&[[f64; 4]]> {
        self.moments_kept.then_some(&self.moments[..])
    }

    /// Moment entries per row: the width when kept, else 1 (one unused
    /// entry per row, so that rows zip with the pixels either way).
    pub fn moment_stride(&self) -> usize {
        if self.moments_kept {
            self.width as usize
        } else {
            1
        }
    }

    /// Adds a light-tracing sample that landed at film position `raster`
    /// to every pixel the filter reaches from there, weighted by the
    /// filter (see `camera::importance` for why the sum over light paths,
    /// divided by the samples per pixel, is the pixel's value).
    pub fn splat<const K: usize>(
        &mut self,
        filter: &FilterSampler,
        raster: [f32; 2],
        xyzv: [f32; 4],
        radiance: &SampledSpectrum<K>,
        wl: &SampledWavelengths<K>,
    ) {
        let r = filter.radius();
        let (w, h) = (self.width as i64, self.height as i64);
        let x0 = ((raster[0] - 0.5 - r).ceil() as i64).max(0);
        let x1 = ((raster[0] - 0.5 + r).floor() as i64).min(w - 1);
        let y0 = ((raster[1] - 0.5 - r).ceil() as i64).max(0);
        let y1 = ((raster[1] - 0.5 + r).floor() as i64).min(h - 1);
        for y in y0..=y1 {
            for x in x0..=x1 {
                let offset = [raster[0] - (x as f32 + 0.5), raster[1] - (y as f32 + 0.5)];
                let f = filter.weight(offset);
                if f == 0.0 {
                    continue;
                }
                let i = (y * w + x) as usize;
                self.pixels[i].add_splat(xyzv.map(|v| v * f));
                if let Some(b) = self.bands {
                    let sums = &mut self.spectral[i * b.0..(i + 1) * b.0];
                    b.add(sums, &(*radiance * f), wl);
                }
            }
        }
    }

    /// Spectral values per row.
    pub fn row_stride(&self) -> usize {
        self.bands.map_or(1, |b| b.0 * self.width as usize)
    }

    /// Mean spectral radiance of band `band` per pixel (row-major).
    pub fn band_means(&self, band: usize) -> Vec<f32> {
        let Some(b) = self.bands else {
            return Vec::new();
        };
        self.pixels
            .iter()
            .enumerate()
            .map(|(i, p)| {
                let s = self.spectral[i * b.0 + band];
                if p.weight <= 0.0 {
                    0.0
                } else {
                    (s / p.weight) as f32
                }
            })
            .collect()
    }

    /// Means as a row-major H × W × 4 array of X, Y, Z, V′.
    pub fn xyzv(&self) -> Vec<[f32; 4]> {
        self.pixels.iter().map(PixelSum::mean).collect()
    }

    /// The smallest and largest sample count over pixels.
    pub fn sample_range(&self) -> (u32, u32) {
        self.pixels.iter().fold((u32::MAX, 0), |(lo, hi), p| {
            (lo.min(p.samples), hi.max(p.samples))
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn films_that_cannot_fit_are_errors_naming_the_limit() {
        assert!(Film::try_new(64, 48, Some(Bands(47))).is_ok());
        for (w, h) in [
            (1_000_000_000, 1_000_000_000),
            (100_000, 100_000),
            (u32::MAX, 2),
        ] {
            let e = Film::try_new(w, h, None).unwrap_err().to_string();
            assert!(e.contains(&format!("a film of {w} × {h} pixels")), "{e}");
            assert!(e.contains("the limit is"), "{e}");
        }
    }
}
