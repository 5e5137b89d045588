//! Warping uniform samples in [0, 1)² to distributions over disks,
//! hemispheres and spheres, each with its density.

use std::f32::consts::{FRAC_1_PI, FRAC_PI_2, FRAC_PI_4, PI};

use crate::math::Vec3;

/// Uniform point on the unit disk, Shirley & Chiu 1997's concentric map
/// (low distortion, keeps stratification).
#[inline]
pub fn square_to_disk_concentric(u: [f32; 2]) -> [f32; 2] {
    let (a, b) = (2.0 * u[0] - 1.0, 2.0 * u[1] - 1.0);
    if a == 0.0 && b == 0.0 {
        return [0.0, 0.0];
    }
    let (r, phi) = if a.abs() > b.abs() {
        (a, FRAC_PI_4 * (b / a))
    } else {
        (b, FRAC_PI_2 - FRAC_PI_4 * (a / b))
    };
    [r * phi.cos(), r * phi.sin()]
}

/// Cosine-weighted direction on the +z hemisphere (Malley's method).
#[inline]
pub fn square_to_cosine_hemisphere(u: [f32; 2]) -> Vec3 {
    let [x, y] = square_to_disk_concentric(u);
    let z = (1.0 - x * x - y * y).max(0.0).sqrt();
    Vec3::new(x, y, z)
}

/// Density of `square_to_cosine_hemisphere` per solid angle: cos θ / π.
#[inline]
pub fn cosine_hemisphere_pdf(cos_theta: f32) -> f32 {
    cos_theta.max(0.0) * FRAC_1_PI
}

/// Uniform direction on the unit sphere.
#[inline]
pub fn square_to_uniform_sphere(u: [f32; 2]) -> Vec3 {
    let z = 1.0 - 2.0 * u[0];
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = 2.0 * PI * u[1];
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// Density of `square_to_uniform_sphere`: 1 / 4π.
pub const UNIFORM_SPHERE_PDF: f32 = 0.25 * FRAC_1_PI;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn maps_land_where_they_should() {
        for i in 0..32 {
            for j in 0..32 {
                let u = [(i as f32 + 0.5) / 32.0, (j as f32 + 0.5) / 32.0];
                let [x, y] = square_to_disk_concentric(u);
                assert!(x * x + y * y <= 1.0 + 1e-6);
                let d = square_to_cosine_hemisphere(u);
                assert!((d.length() - 1.0).abs() < 1e-5 && d.z >= 0.0);
                assert!((square_to_uniform_sphere(u).length() - 1.0).abs() < 1e-5);
            }
        }
    }
}
