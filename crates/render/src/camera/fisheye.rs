//! The fisheye sensor's rays: directions from film points and back, by
//! the projections of `scotopia_image::fisheye` (angular or equisolid;
//! ρ = 1 at the film's horizontal edge, θm half the field of view, whose
//! full angle spans the width, up to 360°).
//!
//! A ray's film position is uniform, so its density per solid angle is
//! 1/(A·J(θ)), A the film's area in units of the half width and J = dω/dA.

pub use scotopia_image::fisheye::Projection as FisheyeMap;

use crate::math::Vec3;

/// The camera-space unit direction (+z forward, +y up, +x left, as
/// Mitsuba's) at film point (a, b) (a right, b up, 1 at the half width),
/// or `None` outside the field.
pub fn direction(map: FisheyeMap, a: f32, b: f32, tm: f32) -> Option<Vec3> {
    let [x, y, z] = map.direction(f64::from(a), f64::from(b), f64::from(tm))?;
    // The picture's right is camera space's −x.
    Some(Vec3::new(-x as f32, y as f32, z as f32))
}

/// The film point (a, b) of camera-space unit direction `d`, with its
/// angle from the axis; `None` outside the field.
pub fn film_point(map: FisheyeMap, d: Vec3, tm: f32) -> Option<([f32; 2], f32)> {
    let theta = d.z.clamp(-1.0, 1.0).acos();
    // The rim's own directions come back a rounding beyond it.
    if theta > tm + 1e-5 {
        return None;
    }
    let rho = (map.rho(f64::from(theta), f64::from(tm)) as f32).min(1.0);
    let side = (d.x * d.x + d.y * d.y).sqrt();
    if side <= 0.0 {
        return Some(([0.0, 0.0], theta));
    }
    Some(([-d.x / side * rho, d.y / side * rho], theta))
}

/// The rays' density per unit solid angle at angle `theta` from the axis
/// of a film of area `area` (half widths squared).
pub fn pdf(map: FisheyeMap, theta: f32, tm: f32, area: f32) -> f32 {
    1.0 / (area * map.density(f64::from(theta), f64::from(tm)) as f32)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn directions_and_film_points_are_inverse() {
        for map in [FisheyeMap::Angular, FisheyeMap::Equisolid] {
            for fov in [120.0f32, 180.0, 220.0, 360.0] {
                let tm = (0.5 * fov).to_radians();
                for (a, b) in [(0.0, 0.0), (0.3, -0.2), (-0.7, 0.7), (0.0, 1.0), (1.0, 0.0)] {
                    // At 360° the whole rim is the one direction behind.
                    if fov == 360.0 && a * a + b * b >= 1.0 {
                        continue;
                    }
                    let d = direction(map, a, b, tm).unwrap();
                    assert!((d.length() - 1.0).abs() < 1e-5);
                    let ([a2, b2], _) = film_point(map, d, tm).unwrap();
                    assert!(
                        (a2 - a).abs() < 1e-4 && (b2 - b).abs() < 1e-4,
                        "{map:?} {fov}: ({a}, {b}) → ({a2}, {b2})"
                    );
                }
                assert!(direction(map, 0.8, 0.8, tm).is_none());
            }
        }
        // The edge of a 180° fisheye looks sideways: right of the image
        // is camera −x (Mitsuba's +x is left).
        let tm = 90f32.to_radians();
        let right = direction(FisheyeMap::Angular, 1.0, 0.0, tm).unwrap();
        assert!((right - Vec3::new(-1.0, 0.0, 0.0)).length() < 1e-6);
        let up = direction(FisheyeMap::Equisolid, 0.0, 1.0, tm).unwrap();
        assert!((up - Vec3::new(0.0, 1.0, 0.0)).length() < 1e-6);
        // 45° off axis on an angular 180° fisheye: half way out.
        let d = direction(FisheyeMap::Angular, 0.5, 0.0, tm).unwrap();
        assert!((d.z - std::f32::consts::FRAC_1_SQRT_2).abs() < 1e-6);
    }
}
