use super::*;

/// Looking along +z with +y up.
const VIEW: View = View {
    sight: [0.0, 0.0, 1.0],
    up: [0.0, 1.0, 0.0],
};

/// A small source giving `e` lx at the eye from `deg` degrees above the
/// line of sight.
fn lamp_above(e: f64, deg: f64) -> Source {
    let t = deg.to_radians();
    let omega = 1e-5;
    Source {
        luminance: e / (omega * t.cos()),
        solid_angle: omega,
        dir: [0.0, t.sin(), t.cos()],
    }
}

#[test]
fn cie_146_veiling_luminance_per_lux_at_ten_degrees_grows_with_age() {
    // CIE 146:2002 (shared/vision-equations.md §9): p = 0.5, θ = 10°:
    // 0.0677 sr⁻¹ at 25 years, 0.153 at 70.
    for (age, want) in [(25.0, 0.0677), (70.0, 0.153)] {
        let o = Observer::new(age, 0.5).unwrap();
        let v = VIEW.veiling(&[lamp_above(1.0, 10.0)], &o);
        assert!((v / want - 1.0).abs() < 5e-3, "{age}: {v}");
    }
}

#[test]
fn threshold_increment_of_one_lux_at_ten_degrees_over_one_candela() {
    // EN 13201-3: L_v = k·E/θ², k ≈ 10 at 23 years: 1 lx at 10° over a road
    // of 1 cd/m² gives TI ≈ 6.5 % (vision-equations.md §9).
    let lv = road_veiling(&[(1.0, 10.0)], TI_AGE);
    assert!((lv - 0.1).abs() < 2e-3, "{lv}");
    let ti = threshold_increment(lv, 1.0).unwrap();
    assert!((ti - 6.5).abs() < 0.15, "{ti}");
    // Twice the road luminance: 2^0.8 less; luminaires nearer than 1.5°
    // or beyond 60° do not count; an older driver's k is larger.
    let half = threshold_increment(lv, 2.0).unwrap();
    assert!((ti / half - 2f64.powf(0.8)).abs() < 1e-9);
    assert_eq!(
        road_veiling(&[(1.0, 10.0), (5.0, 1.0), (5.0, 70.0)], TI_AGE),
        lv
    );
    assert!(ti_age_factor(60.0) > 1.5 * ti_age_factor(TI_AGE));
    assert_eq!(threshold_increment(lv, 0.0), None);
}

#[test]
fn the_position_index_is_guths_above_the_line_of_sight_and_iwatas_below() {
    assert!((VIEW.position_index([0.0, 0.0, 1.0]) - 1.0).abs() < 1e-12);
    // Straight above (τ = 0) at σ = 30°: exp(33.98e-3·30 + 21e-5·900).
    let up30 = VIEW.position_index(lamp_above(1.0, 30.0).dir);
    assert!(
        (up30 - (33.98e-3 * 30.0 + 21e-5 * 900.0f64).exp()).abs() < 1e-9,
        "{up30}"
    );
    // Beside (τ = 90°) it grows more slowly at first: 1.22e^(−20) ≈ 0.
    let t = 30f64.to_radians();
    let side = VIEW.position_index([t.sin(), 0.0, t.cos()]);
    let want = ((35.2f64 - 0.31889 * 90.0) * 1e-3 * 30.0
        + (21.0 + 0.26667 * 90.0 - 0.002963 * 8100.0) * 1e-5 * 900.0)
        .exp();
    assert!((side - want).abs() < 1e-9, "{side} against {want}");
    // Left and right alike; farther is larger, and at most 16.
    assert_eq!(side, VIEW.position_index([-t.sin(), 0.0, t.cos()]));
    assert!(VIEW.position_index(lamp_above(1.0, 50.0).dir) > up30);
    assert_eq!(VIEW.position_index([0.0, 0.98, 0.2]), 16.0);
    // 20° below: R = tan 20° = 0.364 ≤ 0.6, P = 1 + 0.8R; 40° below, 1.2R.
    for (deg, fact) in [(20.0f64, 0.8), (40.0, 1.2)] {
        let d = deg.to_radians();
        let p = VIEW.position_index([0.0, -d.sin(), d.cos()]);
        assert!((p - (1.0 + fact * d.tan())).abs() < 1e-9, "{deg}: {p}");
    }
}

#[test]
fn ugr_and_dgp_of_one_source_are_their_formulas() {
    // A 10 000 cd/m² source of 0.01 sr on the line of sight (P = 1).
    let s = [Source {
        luminance: 1e4,
        solid_angle: 0.01,
        dir: [0.0, 0.0, 1.0],
    }];
    // UGR = 8·log₁₀(0.25/L_b · L²ω/P²) over 100 cd/m²: 8·log₁₀ 2500.
    let ugr = VIEW.ugr(&s, 100.0).unwrap();
    assert!((ugr - 8.0 * 2500f64.log10()).abs() < 1e-9, "{ugr}");
    assert_eq!(VIEW.ugr(&s, 0.0), None);
    assert_eq!(VIEW.ugr(&[], 100.0), None);
    // DGP at 2000 lx (no low-light correction).
    let dgp = VIEW.dgp(&s, 2000.0);
    let want = 5.87e-5 * 2000.0 + 9.18e-2 * (1.0 + 1e6 / 2000f64.powf(1.87)).log10() + 0.16;
    assert!((dgp - want).abs() < 1e-12, "{dgp}");
    // At 200 lx, corrected by e^0.8/(1 + e^0.8).
    let low = VIEW.dgp(&s, 200.0);
    let raw = 5.87e-5 * 200.0 + 9.18e-2 * (1.0 + 1e6 / 200f64.powf(1.87)).log10() + 0.16;
    let c = 0.8f64.exp() / (1.0 + 0.8f64.exp());
    assert!((low - raw * c).abs() < 1e-12, "{low}");
    // A source four times as far from the line of sight glares less.
    let far = [Source {
        dir: lamp_above(1.0, 40.0).dir,
        ..s[0]
    }];
    assert!(VIEW.ugr(&far, 100.0).unwrap() < ugr && VIEW.dgp(&far, 2000.0) < dgp);
}

#[test]
fn a_fisheyes_solid_angles_sum_to_its_field_of_view() {
    // 180°: the hemisphere, 2π; 120° equisolid: 2π(1 − cos 60°) = π.
    for (projection, fov, want) in [
        (Projection::Angular, 180.0, 2.0 * std::f64::consts::PI),
        (Projection::Equisolid, 180.0, 2.0 * std::f64::consts::PI),
        (Projection::Equisolid, 120.0, std::f64::consts::PI),
        (Projection::Angular, 120.0, std::f64::consts::PI),
    ] {
        let eye = Fisheye {
            projection,
            fov,
            width: 128,
            height: 128,
        };
        let sum: f64 = (0..128)
            .flat_map(|y| (0..128).map(move |x| (x, y)))
            .map(|(x, y)| eye.solid_angle(x, y))
            .sum();
        assert!(
            (sum / want - 1.0).abs() < 1e-3,
            "{projection:?} {fov}: {sum}"
        );
    }
    // The angular projection: the rim at 90°, halfway at 45°.
    let eye = Fisheye {
        projection: Projection::Angular,
        fov: 180.0,
        width: 100,
        height: 100,
    };
    let d = eye.direction(75.0, 50.0).unwrap();
    assert!(
        (d[2] - 45f64.to_radians().cos()).abs() < 1e-12 && d[0] > 0.0,
        "{d:?}"
    );
    assert!(eye.direction(0.5, 0.5).is_none());
}

/// A 180° angular picture of `n` × `n` pixels of luminance `sky`, with a
/// disc of luminance `lamp` and angular radius `radius` (degrees) centred
/// `up` degrees above the line of sight.
fn sky_with_lamp(n: usize, sky: f32, lamp: f32, up: f64, radius: f64) -> (Vec<f32>, Fisheye) {
    let eye = Fisheye {
        projection: Projection::Angular,
        fov: 180.0,
        width: n,
        height: n,
    };
    let c = [0.0, up.to_radians().sin(), up.to_radians().cos()];
    let cos_r = radius.to_radians().cos();
    let lum = (0..n * n)
        .map(|i| {
            let d = eye.direction((i % n) as f64 + 0.5, (i / n) as f64 + 0.5);
            match d {
                Some(d) if dot(d, c) >= cos_r => lamp,
                Some(_) => sky,
                None => 0.0,
            }
        })
        .collect();
    (lum, eye)
}

#[test]
fn a_uniform_sky_gives_pi_l_and_no_source() {
    let (lum, eye) = sky_with_lamp(200, 1000.0, 1000.0, 0.0, 0.0);
    let f = evaluate(&lum, &eye, 5.0, &Observer::default());
    assert!(
        (f.ev_lx / (std::f64::consts::PI * 1000.0) - 1.0).abs() < 1e-3,
        "{}",
        f.ev_lx
    );
    assert!(f.sources.is_empty() && f.ugr.is_none());
    assert!((f.dgp - (5.87e-5 * f.ev_lx + 0.16)).abs() < 1e-9);
}

#[test]
fn a_lamp_in_a_fisheye_is_found_and_rated_by_the_formulas() {
    // 20 000 cd/m² over 3° of radius, 30° above the line of sight, in a
    // sky of 100 cd/m².
    let (lum, eye) = sky_with_lamp(400, 100.0, 2e4, 30.0, 3.0);
    let f = evaluate(&lum, &eye, 5.0, &Observer::default());
    assert_eq!(f.sources.len(), 1);
    let s = f.sources[0].source;
    let omega = 2.0 * std::f64::consts::PI * (1.0 - 3f64.to_radians().cos());
    // The disc's pixels: its solid angle within the rim's pixels.
    assert!(
        (s.solid_angle / omega - 1.0).abs() < 0.05,
        "{} against {omega}",
        s.solid_angle
    );
    assert!((s.luminance - 2e4).abs() < 1e-6);
    assert!((FISHEYE_VIEW.sigma(s.dir) - 30.0).abs() < 0.2);
    // CIE 117's background: the sky's indirect illuminance over π, the
    // sky less what the disc hides.
    let cos30 = 30f64.to_radians().cos();
    let lb = 100.0 * (1.0 - s.solid_angle * cos30 / std::f64::consts::PI);
    assert!(
        (f.background_cdm2 / lb - 1.0).abs() < 1e-3,
        "{} against {lb}",
        f.background_cdm2
    );
    // E_v: the sky's π·100 less what the disc hides, plus the disc's.
    let ev = std::f64::consts::PI * 100.0 + (2e4 - 100.0) * s.solid_angle * cos30;
    assert!(
        (f.ev_lx / ev - 1.0).abs() < 2e-3,
        "{} against {ev}",
        f.ev_lx
    );
    // UGR and DGP of that one source, as their formulas give them.
    let p = FISHEYE_VIEW.position_index(s.dir);
    let ugr = 8.0 * (0.25 / f.background_cdm2 * (2e4 / p).powi(2) * s.solid_angle).log10();
    assert!((f.ugr.unwrap() - ugr).abs() < 1e-9);
    assert_eq!(f.dgp, FISHEYE_VIEW.dgp(&[s], f.ev_lx));
    assert!(f.veil_cdm2 > 0.0);
    // A disc across the line of sight veils by its pixels, each at its own
    // angle (a point source's formula at the centre's 0.1° alone would
    // count all of it there): as CIE 146 integrated over the disc in
    // rings, within what 0.45° pixels resolve of f's 1/θ² near the centre.
    let (on_axis, eye0) = sky_with_lamp(400, 100.0, 2e4, 0.0, 3.0);
    let v0 = evaluate(&on_axis, &eye0, 5.0, &Observer::default()).veil_cdm2;
    let spread = crate::glare::psf::GlareSpread::new(&Observer::default());
    let rings = |from: f64| -> f64 {
        let n = 3000;
        let step = (3.0 - from) / n as f64;
        (0..n)
            .map(|i| {
                let t = from + (i as f64 + 0.5) * step;
                let dw = 2.0 * std::f64::consts::PI * t.to_radians().sin() * step.to_radians();
                2e4 * dw * t.to_radians().cos() * spread.general(t.max(0.1))
            })
            .sum()
    };
    // The pixels nearest the centre are 0.32° from it: the core inside
    // them, where f is steepest, is counted at their angle.
    let (outer, all) = (rings(0.45), rings(0.0));
    eprintln!(
        "veil on the line of sight: {v0} by pixels; by rings {outer} from 0.45°, {all} from 0°"
    );
    assert!(
        v0 > outer && v0 < all,
        "{v0} by pixels; by rings {outer} from 0.45°, {all} from 0°"
    );
    // A threshold above 100 is a luminance: 50 000 cd/m² finds nothing,
    // 150 finds the disc (the sky is 100).
    assert!(evaluate(&lum, &eye, 5e4, &Observer::default())
        .sources
        .is_empty());
    let fixed = evaluate(&lum, &eye, 150.0, &Observer::default());
    assert_eq!(fixed.sources.len(), 1);
    assert_eq!(fixed.threshold_cdm2, 150.0);
}

#[test]
fn bright_regions_nearer_than_evalglares_search_radius_are_one_source() {
    // Two 1.5° discs 8° apart (a gap of 5°) are one source, as evalglare
    // finds them; 30° apart they are two.
    let pair = |a: f64, b: f64| {
        let (one, eye) = sky_with_lamp(400, 20.0, 2e4, a, 1.5);
        let (two, _) = sky_with_lamp(400, 20.0, 2e4, b, 1.5);
        let lum: Vec<f32> = one.iter().zip(&two).map(|(x, y)| x.max(*y)).collect();
        evaluate(&lum, &eye, 5.0, &Observer::default())
    };
    let close = pair(10.0, 18.0);
    assert_eq!(close.sources.len(), 1);
    let disc = 2.0 * std::f64::consts::PI * (1.0 - 1.5f64.to_radians().cos());
    let s = close.sources[0].source;
    assert!(
        (s.solid_angle / (2.0 * disc) - 1.0).abs() < 0.1,
        "{}",
        s.solid_angle
    );
    // Its centre between the two.
    assert!((FISHEYE_VIEW.sigma(s.dir) - 14.0).abs() < 0.3);
    assert_eq!(pair(10.0, 40.0).sources.len(), 2);
}
