//! Fisheye projections, shared by the fisheye sensor that renders them
//! (`scotopia_render::camera`) and the glare ratings that read them
//! (`scotopia_vision::ratings`): how the angle θ from the axis maps to
//! the radius ρ on the picture, ρ = 1 at its horizontal edge, where θ is
//! half the field of view θm (whose full angle spans the width).
//!
//! - Angular (equidistant, Radiance's `-vta`): ρ = θ/θm.
//! - Equisolid (equal-area): ρ = sin(θ/2)/sin(θm/2).
//!
//! J = dω/dA, the solid angle per unit of picture area (the half width
//! being 1): θm²·sin θ/θ for the angular projection, 4·sin²(θm/2) for the
//! equisolid.

/// How a fisheye maps angles from its axis to radii on the picture.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Projection {
    /// ρ ∝ θ (equidistant; Radiance's angular fisheye, `-vta`).
    Angular,
    /// ρ ∝ sin(θ/2) (equal-area: every pixel the same solid angle).
    Equisolid,
}

impl Projection {
    pub fn from_name(name: &str) -> Option<Self> {
        match name.trim() {
            "angular" => Some(Self::Angular),
            "equisolid" => Some(Self::Equisolid),
            _ => None,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Self::Angular => "angular",
            Self::Equisolid => "equisolid",
        }
    }

    /// The angle from the axis at radius `rho` (≤ 1) for half field `tm`
    /// (radians).
    pub fn theta(self, rho: f64, tm: f64) -> f64 {
        match self {
            Self::Angular => rho * tm,
            Self::Equisolid => 2.0 * (rho * (0.5 * tm).sin()).clamp(-1.0, 1.0).asin(),
        }
    }

    /// The radius at angle `theta` (≤ `tm`) from the axis.
    pub fn rho(self, theta: f64, tm: f64) -> f64 {
        match self {
            Self::Angular => theta / tm,
            Self::Equisolid => (0.5 * theta).sin() / (0.5 * tm).sin(),
        }
    }

    /// The unit direction at picture point (a, b) (a right, b up, 1 at
    /// the half width) for half field `tm`, in a frame of x right, y up, z
    /// along the axis; `None` outside the field.
    pub fn direction(self, a: f64, b: f64, tm: f64) -> Option<[f64; 3]> {
        let rho = (a * a + b * b).sqrt();
        if rho > 1.0 {
            return None;
        }
        if rho == 0.0 {
            return Some([0.0, 0.0, 1.0]);
        }
        let t = self.theta(rho, tm);
        let s = t.sin() / rho;
        Some([a * s, b * s, t.cos()])
    }

    /// J = dω/dA at angle `theta` from the axis.
    pub fn density(self, theta: f64, tm: f64) -> f64 {
        match self {
            Self::Angular if theta > 1e-9 => tm * tm * theta.sin() / theta,
            Self::Angular => tm * tm,
            Self::Equisolid => 4.0 * (0.5 * tm).sin().powi(2),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::Projection;

    #[test]
    fn the_density_is_the_solid_angle_per_picture_area() {
        // The disc ρ ≤ 1 holds the solid angle 2π(1 − cos θm): the
        // density integrated over it in rings; and ρ inverts θ.
        for p in [Projection::Angular, Projection::Equisolid] {
            for fov in [90.0f64, 180.0, 260.0] {
                let tm = (0.5 * fov).to_radians();
                let n = 20_000;
                let mut sum = 0.0;
                for i in 0..n {
                    let rho = (i as f64 + 0.5) / n as f64;
                    let theta = p.theta(rho, tm);
                    assert!((p.rho(theta, tm) - rho).abs() < 1e-9);
                    sum += p.density(theta, tm) * 2.0 * std::f64::consts::PI * rho / n as f64;
                }
                let exact = 2.0 * std::f64::consts::PI * (1.0 - tm.cos());
                assert!(
                    (sum / exact - 1.0).abs() < 1e-6,
                    "{p:?} {fov}: {sum} against {exact}"
                );
            }
        }
        assert_eq!(
            Projection::from_name(" equisolid"),
            Some(Projection::Equisolid)
        );
        assert_eq!(Projection::from_name("stereographic"), None);
    }
}
