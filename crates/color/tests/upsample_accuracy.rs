//! Accuracy of RGB → spectrum on reflectances: the round trip RGB →
//! spectrum → XYZ under the space's white illuminant → CIEDE2000 against
//! the RGB's own colour, on the 32×32×32 grid of the RGB cube.

use scotopia_color::upsample::jakob2019::{fit::Fitter, table, xy_nodes};
use scotopia_color::upsample::{rgb_cube, round_trip, round_trip_colours};
use scotopia_color::{RgbSpace, UpsampleMethod};

#[test]
fn jakob2019_srgb_meets_the_accuracy_target() {
    let r = round_trip(UpsampleMethod::Jakob2019, RgbSpace::Srgb, 32).unwrap();
    println!("jakob2019 sRGB: {r:?}");
    assert_eq!(r.count, 32 * 32 * 32);
    assert!(
        r.max_de <= 0.1,
        "max ΔE00 {} at {:?}",
        r.max_de,
        r.worst_rgb
    );
    assert!(r.mean_de <= 0.01, "mean ΔE00 {}", r.mean_de);
    assert_eq!(r.out_of_range, 0, "every reflectance in [0, 1]");
}

#[test]
fn jakob2019_wide_gamuts_round_trip_what_reflectances_can_reach() {
    // Rec.2020's primaries lie on the spectral locus and ACEScg's beyond it:
    // their saturated corners are colours no reflectance has, and the fit
    // there is only the nearest reachable one. What must round-trip is every
    // colour a reflectance can have, such as the sRGB gamut, expressed in
    // the wide space.
    let srgb = RgbSpace::Srgb.def();
    // Bounds a little above the measured figures (README): the colours of the
    // sRGB gamut lie nearer the edge of what ACEScg's table reaches.
    for (space, max) in [
        (RgbSpace::Rec2020, 0.5),
        (RgbSpace::DisplayP3, 0.5),
        (RgbSpace::AcesCg, 1.0),
    ] {
        let def = space.def();
        let colours: Vec<[f32; 3]> = rgb_cube(16)
            .iter()
            .map(|c| def.xyz_to_rgb(srgb.rgb_to_xyz(c.map(|v| v as f64))))
            .filter(|c| c.iter().all(|v| (0.0..=1.0).contains(v)))
            .map(|c| c.map(|v| v as f32))
            .collect();
        assert!(colours.len() > 3000, "{}: {}", space.name(), colours.len());
        let r = round_trip_colours(UpsampleMethod::Jakob2019, space, &colours).unwrap();
        println!("jakob2019 sRGB colours in {}: {r:?}", space.name());
        assert!(
            r.max_de <= max && r.mean_de <= 0.02,
            "{}: {r:?}",
            space.name()
        );
        assert_eq!(r.out_of_range, 0);
    }
}

#[test]
fn baselines_are_worse_than_jakob2019() {
    let smits = round_trip(UpsampleMethod::Smits, RgbSpace::Srgb, 16).unwrap();
    let prim = round_trip(UpsampleMethod::Primaries, RgbSpace::Srgb, 16).unwrap();
    println!("smits: {smits:?}\nprimaries: {prim:?}");
    assert!(smits.mean_de > 0.1 && prim.mean_de > smits.mean_de);
}

#[test]
fn stored_srgb_table_is_this_fitter_s_converged_output() {
    // Re-fit a spread of nodes from their stored value: a converged table is a
    // fixed point of the fitter, so the coefficients barely move.
    let t = table(RgbSpace::Srgb).unwrap();
    let fitter = Fitter::new(RgbSpace::Srgb);
    let n = t.resolution();
    for (l, k, j, i) in [
        (0, 40, 3, 60),
        (1, 20, 63, 0),
        (2, 63, 10, 10),
        (0, 63, 0, 0),
        (1, 5, 30, 31),
    ] {
        let z = t.z(k) as f64;
        let mut rgb = [0.0; 3];
        rgb[l] = z;
        rgb[(l + 1) % 3] = xy_nodes(n)[i] * z;
        rgb[(l + 2) % 3] = xy_nodes(n)[j] * z;
        let stored = t.get(l, k, j, i).map(|v| v as f64);
        let refit = fitter.fit(rgb, stored);
        assert!(
            refit.residual < 1e-2,
            "node {l},{k},{j},{i}: residual {}",
            refit.residual
        );
        for c in 0..3 {
            let tol = 1e-3 * stored[c].abs().max(1.0);
            assert!(
                (refit.coeffs[c] - stored[c]).abs() < tol,
                "{stored:?} → {:?}",
                refit.coeffs
            );
        }
    }
}
