//! Fisheye pictures: the direction and solid angle of each pixel of an
//! equidistant ("angular", Radiance's `-vta`) or equisolid projection
//! whose full angle `fov` spans the image's width, centred, square pixels.
//! The view looks at the image's centre with its top up: x right, y up,
//! z along the line of sight.

use super::Dir;

pub use scotopia_image::fisheye::Projection;

/// A fisheye picture's geometry.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Fisheye {
    pub projection: Projection,
    /// The full angle across the image's width, degrees (up to 360).
    pub fov: f64,
    pub width: usize,
    pub height: usize,
}

impl Fisheye {
    /// Half the field of view, radians.
    fn theta_max(&self) -> f64 {
        (0.5 * self.fov).to_radians()
    }

    /// The normalised image point (a, b) of a position in pixels (x right,
    /// y down): 1 at the width's edge.
    fn normalised(&self, x: f64, y: f64) -> (f64, f64) {
        let half = 0.5 * self.width as f64;
        ((x - half) / half, (0.5 * self.height as f64 - y) / half)
    }

    /// The angle from the line of sight at normalised radius ρ (None
    /// beyond the field of view).
    fn theta(&self, rho: f64) -> Option<f64> {
        if rho > 1.0 {
            return None;
        }
        Some(self.projection.theta(rho, self.theta_max()))
    }

    /// The unit direction at a position in pixels, or None outside the
    /// picture's circle.
    pub fn direction(&self, x: f64, y: f64) -> Option<Dir> {
        let (a, b) = self.normalised(x, y);
        self.projection.direction(a, b, self.theta_max())
    }

    /// Solid angle per unit normalised area at radius ρ: θm²·sinθ/θ for the
    /// angular projection, 4·sin²(θm/2) for the equisolid.
    fn density(&self, rho: f64) -> Option<f64> {
        let t = self.theta(rho)?;
        Some(self.projection.density(t, self.theta_max()))
    }

    /// The solid angle (sr) of pixel (x, y), by the midpoint rule on 8 × 8
    /// points (exact for the equisolid projection but at the circle's rim;
    /// within 10⁻⁵ of a pixel's own for the angular one).
    pub fn solid_angle(&self, x: usize, y: usize) -> f64 {
        const N: usize = 8;
        let area = (2.0 / self.width as f64).powi(2) / (N * N) as f64;
        let mut sum = 0.0;
        for i in 0..N {
            for j in 0..N {
                let px = x as f64 + (i as f64 + 0.5) / N as f64;
                let py = y as f64 + (j as f64 + 0.5) / N as f64;
                let (a, b) = self.normalised(px, py);
                if let Some(d) = self.density((a * a + b * b).sqrt()) {
                    sum += d * area;
                }
            }
        }
        sum
    }
}
