//! EN 13201-3:2015's calculation grid and observers for a straight road
//! (§ 6.2, 6.3): the field is the road between two luminaires of one row,
//! `spacing` long, over all lanes.
//!
//! - Along the road, N points per row: N = 10 where the spacing S ≤ 30 m,
//!   else the least integer with S/N ≤ 3 m; D = S/N apart, the first D/2
//!   from the field's start.
//! - Across, 3 points per lane, d = W_L/3 apart, the outer ones d/2 from the
//!   lane's edges: the middle one is on the lane's centre line.
//! - One observer per lane, on its centre line, 60 m before the field,
//!   the eye 1.5 m above the road, looking along the road 1° down.

use crate::math::Vec3;

/// A straight road: its field's start on its first edge, the unit
/// directions along it and across it (from the first lane to the last),
/// up, and its lanes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Road {
    pub start: Vec3,
    pub along: Vec3,
    pub across: Vec3,
    pub up: Vec3,
    /// The luminaires' spacing: the field's length, m.
    pub spacing: f32,
    pub lanes: u32,
    pub lane_width: f32,
}

/// A point of the grid.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GridPoint {
    pub p: Vec3,
    /// Its lane (0 first).
    pub lane: u32,
    /// Its row along the road (0 nearest the observers).
    pub row: u32,
    /// Whether it lies on its lane's centre line (for U_l).
    pub centre: bool,
}

/// What makes a road unusable.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RoadError {
    #[error("the road's spacing ({MAX_SPACING} m at most) and lane width must be positive, and it needs 1 to {MAX_LANES} lanes")]
    Size,
    #[error("the road's directions along, across and up must be finite and not zero")]
    Direction,
}

/// The longest spacing (m) and the most lanes a road may have: a grid of
/// at most 334 rows × 48 points, each seen by 16 observers.
pub const MAX_SPACING: f32 = 1000.0;
pub const MAX_LANES: u32 = 16;

/// The observer's distance before the field (m) and eye height (m),
/// EN 13201-3 § 6.3.
pub const OBSERVER_DISTANCE: f32 = 60.0;
pub const EYE_HEIGHT: f32 = 1.5;

impl Road {
    /// Checked, with its directions at unit length.
    pub fn checked(self) -> Result<Self, RoadError> {
        let ok = |v: f32| v.is_finite() && v > 0.0;
        let fits = self.spacing <= MAX_SPACING && (1..=MAX_LANES).contains(&self.lanes);
        if !(ok(self.spacing) && ok(self.lane_width) && fits) {
            return Err(RoadError::Size);
        }
        let unit = |v: Vec3| {
            let finite = v.x.is_finite() && v.y.is_finite() && v.z.is_finite();
            (finite && v.length_squared() > 0.0)
                .then(|| v.normalize())
                .ok_or(RoadError::Direction)
        };
        Ok(Self {
            along: unit(self.along)?,
            across: unit(self.across)?,
            up: unit(self.up)?,
            ..self
        })
    }

    /// Points per row along the road, and their spacing D.
    pub fn along_points(&self) -> (u32, f32) {
        let n = if self.spacing <= 30.0 {
            10
        } else {
            (self.spacing / 3.0).ceil() as u32
        };
        (n, self.spacing / n as f32)
    }

    /// The grid, row by row, lane by lane.
    pub fn grid(&self) -> Vec<GridPoint> {
        let (n, d) = self.along_points();
        let w = self.lane_width / 3.0;
        let mut out = Vec::new();
        for row in 0..n {
            let x = d * (row as f32 + 0.5);
            for lane in 0..self.lanes {
                for k in 0..3 {
                    let y = self.lane_width * lane as f32 + w * (k as f32 + 0.5);
                    out.push(GridPoint {
                        p: self.start + self.along * x + self.across * y,
                        lane,
                        row,
                        centre: k == 1,
                    });
                }
            }
        }
        out
    }

    /// The eye of lane `lane`'s observer.
    pub fn observer(&self, lane: u32) -> Vec3 {
        self.start - self.along * OBSERVER_DISTANCE
            + self.across * (self.lane_width * (lane as f32 + 0.5))
            + self.up * EYE_HEIGHT
    }

    /// The observers' line of sight: along the road, 1° down.
    pub fn line_of_sight(&self) -> Vec3 {
        let a = 1f32.to_radians();
        (self.along * a.cos() - self.up * a.sin()).normalize()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn road(spacing: f32, lanes: u32) -> Road {
        Road {
            start: Vec3::new(0.0, 0.0, 0.0),
            along: Vec3::new(0.0, 0.0, -2.0),
            across: Vec3::new(1.0, 0.0, 0.0),
            up: Vec3::new(0.0, 1.0, 0.0),
            spacing,
            lanes,
            lane_width: 3.5,
        }
        .checked()
        .unwrap()
    }

    #[test]
    fn the_grid_is_en_13201_3s() {
        // 30 m: 10 rows 3 m apart, the first 1.5 m in; 2 lanes of 3 points.
        let r = road(30.0, 2);
        let g = r.grid();
        assert_eq!(g.len(), 60);
        assert_eq!(r.along_points(), (10, 3.0));
        assert!((g[0].p - Vec3::new(3.5 / 6.0, 0.0, -1.5)).length() < 1e-6);
        // The middle point of each lane is its centre line.
        let centres: Vec<f32> = g
            .iter()
            .filter(|p| p.centre && p.row == 0)
            .map(|p| p.p.x)
            .collect();
        assert_eq!(centres, [1.75, 5.25]);
        // 40 m: 14 rows (40/14 ≤ 3 m).
        assert_eq!(road(40.0, 1).along_points().0, 14);
        // The observer: 60 m before, on the lane's centre, 1.5 m up.
        assert!((r.observer(1) - Vec3::new(5.25, 1.5, 60.0)).length() < 1e-5);
        let los = r.line_of_sight();
        assert!((los.y + 1f32.to_radians().sin()).abs() < 1e-6 && los.z < 0.0);
        assert_eq!(Road { lanes: 0, ..r }.checked(), Err(RoadError::Size));
        assert_eq!(
            Road {
                up: Vec3::ZERO,
                ..r
            }
            .checked(),
            Err(RoadError::Direction)
        );
    }
}
