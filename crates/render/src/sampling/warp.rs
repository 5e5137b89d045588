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

/// Uniform direction within the cone of half-angle θmax around +z, given
/// 1 − cos θmax. sin θ is formed from 1 − cos θ, so a narrow cone (a small
/// lamp far away, where cos θ rounds to 1) keeps its spread.
#[inline]
pub fn square_to_uniform_cone(u: [f32; 2], one_minus_cos_max: f32) -> Vec3 {
    let one_minus = u[0] * one_minus_cos_max;
    let sin = (one_minus * (2.0 - one_minus)).max(0.0).sqrt();
    let phi = 2.0 * PI * u[1];
    Vec3::new(sin * phi.cos(), sin * phi.sin(), 1.0 - one_minus)
}

/// Density of `square_to_uniform_cone` per solid angle: 1 / 2π(1 − cos θmax).
#[inline]
pub fn uniform_cone_pdf(one_minus_cos_max: f32) -> f32 {
    0.5 * FRAC_1_PI / one_minus_cos_max
}

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
                // A cone of 1e-6 rad: cos θ is 1 in f32, the spread is not.
                let c = square_to_uniform_cone(u, 5e-13);
                assert!((c.length() - 1.0).abs() < 1e-5 && c.z >= 1.0 - 1e-6);
                let sin = c.x.hypot(c.y);
                assert!(sin <= 1.0000001e-6 && (u[0] < 0.1 || sin > 1e-7), "{sin}");
            }
        }
    }
}
