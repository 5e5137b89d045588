//! Correlated colour temperature and Duv by Ohno 2013 ("Practical Use and
//! Calculation of CCT and Duv", LEUKOS 10(1), 2014): the nearest point of the
//! Planckian locus in the CIE 1960 (u, v) diagram, found on a table of the
//! locus refined in cascade, then by Ohno's triangular solution (|Duv| <
//! 0.002) or parabolic solution (otherwise).

use std::sync::OnceLock;

use crate::cie;
use crate::photometry::xyz_to_xy;
use crate::spectrum::planck;
use crate::{LAMBDA_MAX, LAMBDA_MIN};

/// A correlated colour temperature and the signed distance Duv from the
/// Planckian locus (positive above it, towards green).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cct {
    pub kelvin: f64,
    pub duv: f64,
}

/// Range of the Planckian table, K.
pub const CCT_MIN: f64 = 1000.0;
pub const CCT_MAX: f64 = 100_000.0;

/// CIE 1960 UCS: u = 4x / (−2x + 12y + 3), v = 6y / (−2x + 12y + 3).
pub fn xy_to_uv1960([x, y]: [f64; 2]) -> [f64; 2] {
    let d = -2.0 * x + 12.0 * y + 3.0;
    [4.0 * x / d, 6.0 * y / d]
}

/// (u, v) of the Planckian radiator at `kelvin`, integrated with the CIE 1931
/// observer at 1 nm over 360–830 nm.
pub fn planckian_uv(kelvin: f64) -> [f64; 2] {
    let mut xyz = [0.0f64; 3];
    for l in LAMBDA_MIN as u32..=LAMBDA_MAX as u32 {
        let p = planck(l as f64, kelvin);
        let c = cie::xyz_bar(l as f32);
        for k in 0..3 {
            xyz[k] += p * c[k] as f64;
        }
    }
    // A black body always has positive X + Y + Z.
    xy_to_uv1960(xyz_to_xy(xyz).expect("black body has a chromaticity"))
}

/// One row of a Planckian table: T, and (u, v).
type Row = (f64, [f64; 2]);

fn coarse_table() -> &'static [Row] {
    static TABLE: OnceLock<Vec<Row>> = OnceLock::new();
    TABLE.get_or_init(|| {
        // Ohno 2013: 1 % steps in T.
        let mut rows = Vec::new();
        let mut t = CCT_MIN;
        while t <= CCT_MAX * 1.0001 {
            rows.push((t, planckian_uv(t)));
            t *= 1.01;
        }
        rows
    })
}

fn nearest(rows: &[Row], uv: [f64; 2]) -> (usize, Vec<f64>) {
    let d: Vec<f64> = rows
        .iter()
        .map(|(_, p)| (p[0] - uv[0]).hypot(p[1] - uv[1]))
        .collect();
    let m = (0..d.len())
        .min_by(|&a, &b| d[a].total_cmp(&d[b]))
        .unwrap_or(0);
    (m, d)
}

/// CCT and Duv of a CIE 1960 (u, v) chromaticity; `None` outside 1000–100000 K.
pub fn cct_ohno2013(uv: [f64; 2]) -> Option<Cct> {
    // Find the nearest table row, then cascade: re-tabulate the locus finely
    // between the rows either side of it until the step is below 10⁻⁶ T.
    let (m, _) = nearest(coarse_table(), uv);
    if m == 0 || m == coarse_table().len() - 1 {
        return None;
    }
    let mut rows = coarse_table()[m - 1..=m + 1].to_vec();
    for _ in 0..5 {
        let (lo, hi) = (rows[0].0, rows[rows.len() - 1].0);
        rows = (0..=10)
            .map(|i| {
                let t = lo + (hi - lo) * i as f64 / 10.0;
                (t, planckian_uv(t))
            })
            .collect();
        let (m, _) = nearest(&rows, uv);
        let m = m.clamp(1, rows.len() - 2);
        rows = rows[m - 1..=m + 1].to_vec();
    }
    let (_, d) = nearest(&rows, uv);
    let [(t0, p0), (t1, _), (t2, p2)] = [rows[0], rows[1], rows[2]];
    let (d0, d1, d2) = (d[0], d[1], d[2]);

    // Triangular solution (Ohno 2013, eq. 4–7).
    let l = (p2[0] - p0[0]).hypot(p2[1] - p0[1]);
    let x = (d0 * d0 - d2 * d2 + l * l) / (2.0 * l);
    let t_tri = t0 + (t2 - t0) * x / l;
    let v_tri = p0[1] + (p2[1] - p0[1]) * x / l;
    let duv_tri = (d0 * d0 - x * x).max(0.0).sqrt() * (uv[1] - v_tri).signum();
    if duv_tri.abs() < 0.002 {
        return Some(Cct {
            kelvin: t_tri,
            duv: duv_tri,
        });
    }

    // Parabolic solution (Ohno 2013, eq. 8–11): fit d(T) = aT² + bT + c.
    let xd = (t2 - t1) * (t0 - t2) * (t1 - t0);
    let a = (t0 * (d2 - d1) + t1 * (d0 - d2) + t2 * (d1 - d0)) / xd;
    let b = -(t0 * t0 * (d2 - d1) + t1 * t1 * (d0 - d2) + t2 * t2 * (d1 - d0)) / xd;
    let c = -(d0 * (t2 - t1) * t1 * t2 + d1 * (t0 - t2) * t0 * t2 + d2 * (t1 - t0) * t0 * t1) / xd;
    let t = -b / (2.0 * a);
    let v_t = planckian_uv(t)[1];
    let duv = (a * t * t + b * t + c) * (uv[1] - v_t).signum();
    Some(Cct { kelvin: t, duv })
}

/// CCT and Duv of a CIE 1931 (x, y) chromaticity.
pub fn cct_from_xy(xy: [f64; 2]) -> Option<Cct> {
    cct_ohno2013(xy_to_uv1960(xy))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn black_bodies_are_on_the_locus() {
        for t in [1500.0, 2856.0, 4000.0, 6504.0, 10000.0, 30000.0] {
            let c = cct_ohno2013(planckian_uv(t)).unwrap();
            assert!((c.kelvin / t - 1.0).abs() < 1e-6, "{t}: {c:?}");
            assert!(c.duv.abs() < 1e-7, "{t}: {c:?}");
        }
    }

    #[test]
    fn off_locus_points_are_found_at_their_distance() {
        // Move 0.01 above the locus along its normal at 5000 K; CCT stays 5000 K.
        let (t, h) = (5000.0, 1.0);
        let (a, b) = (planckian_uv(t - h), planckian_uv(t + h));
        let tangent = [b[0] - a[0], b[1] - a[1]];
        let n = tangent[0].hypot(tangent[1]);
        // The normal pointing up in v (positive Duv).
        let normal = [tangent[1] / n, -tangent[0] / n];
        assert!(normal[1] > 0.0);
        let p = planckian_uv(t);
        for duv in [0.01, -0.02, 0.001] {
            let uv = [p[0] + duv * normal[0], p[1] + duv * normal[1]];
            let c = cct_ohno2013(uv).unwrap();
            assert!((c.kelvin - t).abs() < 0.5, "{duv}: {c:?}");
            assert!((c.duv - duv).abs() < 1e-5, "{duv}: {c:?}");
        }
    }

    #[test]
    fn out_of_range_is_none() {
        assert!(cct_ohno2013(planckian_uv(500.0)).is_none());
    }
}
