//! The GGX (Trowbridge–Reitz) distribution's pieces, written for the
//! stretched configuration where the roughness is 1 (Heitz 2014,
//! "Understanding the Masking-Shadowing Function in Microfacet-Based
//! BRDFs", JCGT 3(2), §5.3): the caller stretches and unstretches.

use crate::math::Vec3;
use crate::sampling::warp::square_to_disk_concentric;

/// D(m)·(π α_u α_v) as a function of s = (m_x/α_u)² + (m_y/α_v)² and
/// c² = m_z², for a unit m: 1 / (s + c²)² (Walter et al. 2007, eq. 33).
#[inline]
pub fn d_unnormalised(s: f32, c2: f32) -> f32 {
    let t = s + c2;
    1.0 / (t * t)
}

/// Smith's G₁ for t² = α² tan²θ (α projected on the direction's azimuth):
/// 2 / (1 + √(1 + α² tan²θ)) (Walter et al. 2007, eq. 34).
#[inline]
pub fn g1(t2: f32) -> f32 {
    2.0 / (1.0 + (1.0 + t2).sqrt())
}

/// A normal drawn from those visible from `vh` (unit, vh.z > 0) on the
/// hemisphere of roughness 1 (Heitz 2018, "Sampling the GGX Distribution of
/// Visible Normals", JCGT 7(4), listing 1).
#[inline]
pub fn sample_visible_11(vh: Vec3, u: [f32; 2]) -> Vec3 {
    // An orthonormal basis around vh.
    let lensq = vh.x * vh.x + vh.y * vh.y;
    let t1 = if lensq > 0.0 {
        Vec3::new(-vh.y, vh.x, 0.0) / lensq.sqrt()
    } else {
        Vec3::new(1.0, 0.0, 0.0)
    };
    let t2 = vh.cross(t1);
    // A point on the projected area (Shirley–Chiu's concentric map, as
    // Mitsuba), warped towards the visible half disk.
    let [p1, mut p2] = square_to_disk_concentric(u);
    let s = 0.5 * (1.0 + vh.z);
    p2 = (1.0 - s) * (1.0 - p1 * p1).max(0.0).sqrt() + s * p2;
    // Project back up to the hemisphere.
    t1 * p1 + t2 * p2 + vh * (1.0 - p1 * p1 - p2 * p2).max(0.0).sqrt()
}
