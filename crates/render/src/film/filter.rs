//! Reconstruction filters, as Mitsuba's weighted splatting: a camera
//! sample lands uniformly in its own pixel and adds f·L and f to every
//! pixel whose filter reaches it; a pixel is Σ f·L / Σ f.
//!
//! Until issue 40 scotopia drew each sample's offset from the filter and
//! counted it in its own pixel alone (filter importance sampling, pbrt-v4
//! §8.8). That converges to the same image, but each pixel then averages
//! only its own samples, where splatting averages every sample under its
//! filter: for Mitsuba's Gaussian (σ = ½ pixel) about 1/∫f² = 4πσ² = π
//! times as many, so a pixel's variance is about a third. A rare sample
//! in the filter's tail that saw something bright beside the pixel
//! counted fully there (the night street's lone bright pixels beyond
//! bright edges); splatted, it counts with its small weight. The ratio
//! Σ f·L / Σ f also renormalises the filter at the image's borders, where
//! part of it would lie outside the film (no dark frame). Renders stay
//! deterministic: see `Renderer::pass`.

use crate::sampling::distribution::Distribution1D;

/// The film's reconstruction filter (Mitsuba's `rfilter`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Filter {
    Box,
    Gaussian { stddev: f32 },
}

/// Bins of the tabulated Gaussian (per axis).
const GAUSSIAN_BINS: usize = 1024;

#[derive(Debug, Clone, PartialEq)]
pub enum FilterSampler {
    /// The pixel's own square, [−½, ½]².
    Box,
    /// Mitsuba's `gaussian`: stddev σ, truncated at its radius 4σ,
    /// separable; tabulated finely per axis.
    Gaussian { radius: f32, table: Distribution1D },
}

impl FilterSampler {
    pub fn new(filter: Filter) -> Self {
        match filter {
            Filter::Gaussian { stddev } if stddev > 0.0 && stddev.is_finite() => {
                let radius = 4.0 * stddev;
                let weights = (0..GAUSSIAN_BINS)
                    .map(|i| {
                        let x = -radius + 2.0 * radius * (i as f32 + 0.5) / GAUSSIAN_BINS as f32;
                        (-(x * x) / (2.0 * stddev * stddev)).exp()
                    })
                    .collect();
                FilterSampler::Gaussian {
                    radius,
                    table: Distribution1D::new(weights),
                }
            }
            _ => FilterSampler::Box,
        }
    }

    /// How far from a pixel's centre the filter reaches, pixels.
    pub fn radius(&self) -> f32 {
        match self {
            FilterSampler::Box => 0.5,
            FilterSampler::Gaussian { radius, .. } => *radius,
        }
    }

    /// How many rows (and columns) away from its own pixel a camera
    /// sample can reach: 0 for the box (each sample counts in its own
    /// pixel alone), 2 for Mitsuba's default Gaussian.
    pub fn reach(&self) -> usize {
        match self {
            FilterSampler::Box => 0,
            // A sample at offset t ∈ [−½, ½) from its pixel's centre
            // reaches the pixel d away when |t − d| < radius.
            FilterSampler::Gaussian { radius, .. } => (radius - 0.5).ceil().max(0.0) as usize,
        }
    }

    /// The filter's value at `offset` from a pixel centre, normalised to
    /// integrate to 1 over the plane: what a splatted sample (a camera
    /// sample, or a light-tracing one) is weighted by in each pixel it
    /// reaches.
    pub fn weight(&self, offset: [f32; 2]) -> f32 {
        self.axis_weight(offset[0]) * self.axis_weight(offset[1])
    }

    /// The filter's value along one axis (both filters are separable),
    /// normalised to integrate to 1 over the line.
    #[inline]
    pub fn axis_weight(&self, x: f32) -> f32 {
        match self {
            FilterSampler::Box => {
                if (-0.5..0.5).contains(&x) {
                    1.0
                } else {
                    0.0
                }
            }
            FilterSampler::Gaussian { radius, table } => {
                let t = (x + radius) / (2.0 * radius);
                if (0.0..1.0).contains(&t) {
                    table.pdf(t) / (2.0 * radius)
                } else {
                    0.0
                }
            }
        }
    }

    /// A camera sample's offset from its pixel's centre, in pixels:
    /// uniform over the pixel, whatever the filter.
    #[inline]
    pub fn sample(&self, u: [f32; 2]) -> [f32; 2] {
        [u[0] - 0.5, u[1] - 0.5]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn weights_integrate_to_one() {
        for f in [
            FilterSampler::new(Filter::Box),
            FilterSampler::new(Filter::Gaussian { stddev: 0.5 }),
        ] {
            // Midpoint rule over the support at 1/64 pixel.
            let r = f.radius();
            let n = (128.0 * r) as usize;
            let h = 2.0 * r / n as f32;
            let mut sum = 0.0f64;
            for i in 0..n {
                for j in 0..n {
                    let o = [-r + (i as f32 + 0.5) * h, -r + (j as f32 + 0.5) * h];
                    sum += (f.weight(o) * h * h) as f64;
                }
            }
            assert!((sum - 1.0).abs() < 1e-3, "{f:?}: {sum}");
        }
    }

    #[test]
    fn offsets_are_uniform_over_the_pixel_and_reach_what_the_filter_does() {
        for f in [
            FilterSampler::new(Filter::Box),
            FilterSampler::new(Filter::Gaussian { stddev: 0.5 }),
        ] {
            assert_eq!(f.sample([0.0, 0.75]), [-0.5, 0.25]);
        }
        let reach = |stddev| FilterSampler::new(Filter::Gaussian { stddev }).reach();
        assert_eq!(FilterSampler::new(Filter::Box).reach(), 0);
        assert_eq!(reach(0.5), 2);
        assert_eq!(reach(0.3), 1);
        // No sample reaches a pixel beyond `reach`: the farthest offset
        // from that pixel's centre is reach + ½, outside the radius.
        for stddev in [0.1f32, 0.3, 0.5, 0.8, 1.0] {
            let f = FilterSampler::new(Filter::Gaussian { stddev });
            let d = f.reach() as f32 + 1.0;
            assert_eq!(f.weight([d - 0.5, 0.0]), 0.0, "σ {stddev}");
            if f.reach() > 0 {
                assert!(f.weight([f.reach() as f32 - 0.49, 0.0]) > 0.0, "σ {stddev}");
            }
        }
    }
}
