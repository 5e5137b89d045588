//! Photometric files (issue 24): IES LM-63 and EULUMDAT readers, symmetry
//! expansion, multipliers, flux, and the errors of bad files. All files are
//! synthetic, written here.

use std::f64::consts::PI;

use scotopia_scene::luminaire::{parse_luminaire, read_luminaire, Format, Photometry, Symmetry};

/// A test lamp with quadrant symmetry plus optional asymmetric parts:
/// `c0` adds a part symmetric only about C0–C180, `c90` one symmetric only
/// about C90–C270.
fn lamp_cd(gamma: f64, c: f64, c0: f64, c90: f64) -> f64 {
    let (g, c) = (gamma.to_radians(), c.to_radians());
    let base = 100.0 + 40.0 * g.cos() + 30.0 * (2.0 * c).cos() * g.sin();
    base + c0 * c.cos() * g.sin() + c90 * c.sin() * g.sin()
}

/// Folds C into the part of the circle a symmetry keeps, so that the full
/// and the symmetric files hold the very same values (as text).
fn fold(c: f64, s: Symmetry) -> f64 {
    match s {
        Symmetry::None | Symmetry::Rotational => c,
        Symmetry::AboutC0C180 => {
            if c > 180.0 {
                360.0 - c
            } else {
                c
            }
        }
        Symmetry::AboutC90C270 => {
            if (90.0..=270.0).contains(&c) {
                c
            } else {
                (180.0 - c).rem_euclid(360.0)
            }
        }
        Symmetry::Quadrant => {
            let c = if c > 180.0 { 360.0 - c } else { c };
            if c > 90.0 {
                180.0 - c
            } else {
                c
            }
        }
    }
}

/// What the lamp's file holds at (γ, C) for a lamp of symmetry `s`.
fn value(gamma: f64, c: f64, s: Symmetry) -> String {
    let (c0, c90) = match s {
        Symmetry::AboutC0C180 => (20.0, 0.0),
        Symmetry::AboutC90C270 => (0.0, 20.0),
        Symmetry::None => (20.0, 10.0),
        _ => (0.0, 0.0),
    };
    let cd = if s == Symmetry::Rotational {
        lamp_cd(gamma, 0.0, 0.0, 0.0)
    } else {
        lamp_cd(gamma, fold(c, s), c0, c90)
    };
    format!("{cd:.3}")
}

const GAMMAS: [f64; 7] = [0.0, 30.0, 60.0, 90.0, 120.0, 150.0, 180.0];

fn range(from: f64, to: f64, step: f64) -> Vec<f64> {
    let n = ((to - from) / step).round() as usize;
    (0..=n).map(|k| from + k as f64 * step).collect()
}

/// Numbers wrapped `per_line` to a line (LM-63 allows any wrapping).
fn wrap(values: &[String], per_line: usize) -> String {
    values
        .chunks(per_line)
        .map(|c| c.join(" "))
        .collect::<Vec<_>>()
        .join("\n")
}

/// An IES file of the lamp `s` written with horizontal angles `cs`.
fn ies_of(header: &str, cs: &[f64], s: Symmetry) -> String {
    let mut v: Vec<String> = GAMMAS.iter().map(|g| g.to_string()).collect();
    v.extend(cs.iter().map(|c| c.to_string()));
    for &c in cs {
        v.extend(GAMMAS.iter().map(|&g| value(g, c, s)));
    }
    format!(
        "{header}\n[TEST] synthetic\n[MANUFAC] scotopia tests\nTILT=NONE\n\
         1 -1 1 {} {} 1 2 0.1 0.2 0.05\n1 1 50\n{}\n",
        GAMMAS.len(),
        cs.len(),
        wrap(&v, 5)
    )
}

fn parse(text: &str) -> Photometry {
    parse_luminaire(text, "lamp.ies").unwrap_or_else(|e| panic!("{e}\n{text}"))
}

fn err(text: &str) -> String {
    parse_luminaire(text, "lamp.ies").unwrap_err().to_string()
}

#[test]
fn ies_symmetries_expand_to_the_full_table() {
    let h = "IESNA:LM-63-2002";
    for (s, half) in [
        (Symmetry::Quadrant, range(0.0, 90.0, 15.0)),
        (Symmetry::AboutC0C180, range(0.0, 180.0, 15.0)),
        (Symmetry::AboutC90C270, range(90.0, 270.0, 15.0)),
        (Symmetry::Rotational, vec![0.0]),
    ] {
        let full = parse(&ies_of(h, &range(0.0, 360.0, 15.0), s));
        let sym = parse(&ies_of(h, &half, s));
        assert_eq!(sym.symmetry, s);
        assert_eq!(full.symmetry, Symmetry::None);
        if s == Symmetry::Rotational {
            // The full file repeats one plane; the table differs only in
            // how many planes hold it.
            for c in [0.0, 33.0, 200.0] {
                for g in [0.0, 45.0, 100.0] {
                    assert_eq!(full.intensity(g, c), sym.intensity(g, c));
                }
            }
            continue;
        }
        assert_eq!(full.c_deg, sym.c_deg, "{s:?}");
        assert_eq!(full.candela, sym.candela, "{s:?}");
        // A full table without the 360° plane is the same lamp too.
        let open = parse(&ies_of(h, &range(0.0, 345.0, 15.0), s));
        assert_eq!(open.candela, full.candela);
    }
}

#[test]
fn intensity_interpolates_between_planes_and_angles() {
    let p = parse(&ies_of(
        "IESNA:LM-63-2002",
        &range(0.0, 360.0, 15.0),
        Symmetry::None,
    ));
    // At the nodes: the file's values.
    let at = |g: f64, c: f64| value(g, c, Symmetry::None).parse::<f32>().unwrap();
    assert_eq!(p.intensity(60.0, 45.0), at(60.0, 45.0));
    assert_eq!(p.intensity(180.0, 0.0), at(180.0, 0.0));
    // Between them: close to the smooth lamp (the table is 30° × 15°).
    for (g, c) in [(45.0, 22.5), (100.0, 200.0), (10.0, 352.0)] {
        let want = lamp_cd(g, c, 20.0, 10.0) as f32;
        let got = p.intensity(g as f32, c as f32);
        assert!(
            (got - want).abs() < 0.02 * want,
            "{got} vs {want} at {g}, {c}"
        );
    }
    // Its flux: the C-dependent parts integrate to 0 over the circle and
    // 40 cos γ to 0 over the sphere, leaving 100 cd × 4π (to the table's
    // resolution, 30° × 15°).
    let rel = p.total_flux_lm() / (400.0 * PI) - 1.0;
    assert!(rel.abs() < 2e-3, "relative error {rel}");
    // C is periodic.
    assert_eq!(p.intensity(45.0, 10.0), p.intensity(45.0, 370.0));
    assert_eq!(p.intensity(45.0, -10.0), p.intensity(45.0, 350.0));
}

/// An IES file with one rotationally symmetric plane.
fn rotational(header: &str, gammas: &[f64], cd: &[f64], numbers: &str) -> String {
    let g: Vec<String> = gammas.iter().map(|g| g.to_string()).collect();
    let v: Vec<String> = cd.iter().map(|v| format!("{v:.9}")).collect();
    format!(
        "{header}\nTILT=NONE\n{numbers}\n{}\n0\n{}\n",
        g.join(" "),
        wrap(&v, 10)
    )
}

#[test]
fn flux_of_an_isotropic_lamp_is_four_pi_times_its_intensity() {
    let numbers = "1 1000 1 3 1 1 2 0 0 0\n1 1 10";
    let p = parse(&rotational(
        "IESNA:LM-63-2002",
        &[0.0, 90.0, 180.0],
        &[1.0; 3],
        numbers,
    ));
    assert!((p.total_flux_lm() - 4.0 * PI).abs() < 1e-4);
    let numbers = "1 1000 1 37 1 1 2 0 0 0\n1 1 10";
    let g = range(0.0, 180.0, 5.0);
    let p = parse(&rotational(
        "IESNA:LM-63-2002",
        &g,
        &vec![250.0; 37],
        numbers,
    ));
    assert!((p.total_flux_lm() / (4.0 * PI * 250.0) - 1.0).abs() < 1e-6);
    assert_eq!(p.lamp_lumens, Some(1000.0));
}

#[test]
fn flux_of_a_cosine_lamp_is_pi_times_its_peak() {
    // I = I₀ cos γ below the horizontal: Φ = π I₀. The table's 5° steps
    // cost the monotone cubic ~1e-5 of the flux (measured 8.6e-6 with and
    // without the upper hemisphere's zeros).
    let i0 = 1000.0;
    for (gammas, label) in [
        (range(0.0, 90.0, 5.0), "0–90"),
        (range(0.0, 180.0, 5.0), "0–180"),
    ] {
        let cd: Vec<f64> = gammas
            .iter()
            .map(|g: &f64| {
                if *g <= 90.0 {
                    i0 * g.to_radians().cos()
                } else {
                    0.0
                }
            })
            .collect();
        let numbers = format!("1 -1 1 {} 1 1 2 0 0 0\n1 1 10", gammas.len());
        let p = parse(&rotational("IESNA:LM-63-2002", &gammas, &cd, &numbers));
        let rel = p.total_flux_lm() / (PI * i0) - 1.0;
        assert!(rel.abs() < 3e-5, "{label}: relative error {rel}");
        assert_eq!(p.lamp_lumens, None, "absolute photometry");
        assert_eq!(p.intensity(120.0, 0.0), 0.0);
    }
}

#[test]
fn multipliers_units_and_versions() {
    let g = [0.0, 90.0, 180.0];
    let cd = [100.0, 100.0, 100.0];
    // multiplier 2, ballast factor 0.9, third field 0.5, feet.
    let numbers = "2 500 2 3 1 1 1 1 2 0.5\n0.9 0.5 40";
    for (header, third_applies, year) in [
        ("IESNA:LM-63-1995", true, 1995),
        ("IESNA91", true, 1991),
        ("Made by hand, 1986 style", true, 1986),
        ("IESNA:LM-63-2002", false, 2002),
        ("IES:LM-63-2019", false, 2019),
    ] {
        let p = parse(&rotational(header, &g, &cd, numbers));
        let want = if third_applies { 90.0 } else { 180.0 };
        assert!((p.intensity(45.0, 0.0) - want).abs() < 1e-3, "{header}");
        assert_eq!(p.format, Format::Ies { year });
        assert!((p.opening.width_m - 0.3048).abs() < 1e-12);
        assert!((p.opening.length_m - 0.6096).abs() < 1e-12);
        assert!((p.opening.height_m - 0.1524).abs() < 1e-12);
        assert_eq!(p.lamp_lumens, Some(1000.0));
        assert_eq!(p.input_watts, Some(40.0));
    }
}

#[test]
fn numbers_wrap_and_commas_separate() {
    let text = "IESNA:LM-63-2002\nTILT=NONE\n1\n-1\n1,3,1\n1 2 0 0 0 1 1\n0\n0,90,180 0\n5 5\n5\n";
    let p = parse(text);
    assert_eq!(p.intensity(30.0, 10.0), 5.0);
    assert!(p.opening == Default::default());
}

#[test]
fn tilt_include_is_read() {
    let text = "IESNA:LM-63-2002\n[TEST] x\nTILT=INCLUDE\n1\n3\n0 45 90\n1 0.95 0.9\n\
                1 -1 1 2 1 1 2 0 0 0\n1 1 10\n0 90\n0\n7 7\n";
    let p = parse(text);
    let tilt = p.tilt.as_ref().expect("tilt table");
    assert_eq!(tilt.lamp_to_luminaire_geometry, 1);
    assert_eq!(tilt.angles_deg, vec![0.0, 45.0, 90.0]);
    assert_eq!(tilt.factors, vec![1.0, 0.95, 0.9]);
    assert_eq!(p.intensity(10.0, 0.0), 7.0);
}

#[test]
fn bad_ies_files_name_the_line() {
    let good =
        "IESNA:LM-63-2002\n[TEST] x\nTILT=NONE\n1 -1 1 3 1 1 2 0 0 0\n1 1 10\n0 90 180\n0\n5 6 7\n";
    assert!(parse_luminaire(good, "lamp.ies").is_ok());
    let cases: [(&str, &str); 14] = [
        // truncated
        (
            "IESNA:LM-63-2002\nTILT=NONE\n1 -1 1 3 1 1 2 0 0 0\n1 1 10\n0 90 180\n0\n5 6\n",
            "lamp.ies:7: the file ends: expected candela value 3 of 3",
        ),
        // wrong counts: more values than 3 × 1
        (
            "IESNA:LM-63-2002\nTILT=NONE\n1 -1 1 3 1 1 2 0 0 0\n1 1 10\n0 90 180\n0\n5 6 7\n8\n",
            "lamp.ies:8: '8' after the last of the 3 × 1 candela values",
        ),
        // not a number
        (
            "IESNA:LM-63-2002\nTILT=NONE\n1 -1 1 3 1 1 2 0 0 0\n1 1 10\n0 9O 180\n0\n5 6 7\n",
            "lamp.ies:5: expected vertical angle 2 of 3, found '9O'",
        ),
        // negative candela
        (
            "IESNA:LM-63-2002\nTILT=NONE\n1 -1 1 3 1 1 2 0 0 0\n1 1 10\n0 90 180\n0\n5\n-6 7\n",
            "lamp.ies:8: negative candela -6",
        ),
        // vertical angles out of order
        (
            "IESNA:LM-63-2002\nTILT=NONE\n1 -1 1 3 1 1 2 0 0 0\n1 1 10\n0\n180\n90\n0\n5 6 7\n",
            "lamp.ies:7: vertical angle 90° does not increase (the previous one is 180°)",
        ),
        // out of range
        (
            "IESNA:LM-63-2002\nTILT=NONE\n1 -1 1 3 1 1 2 0 0 0\n1 1 10\n0 90 190\n0\n5 6 7\n",
            "lamp.ies:5: vertical angle 190° is out of range (expected 0° to 180°)",
        ),
        // horizontal angles out of order
        (
            "IESNA:LM-63-2002\nTILT=NONE\n1 -1 1 2 2 1 2 0 0 0\n1 1 10\n0 90\n0 0\n5 6 7 8\n",
            "lamp.ies:6: horizontal angle 0° does not increase",
        ),
        // a horizontal range type C does not allow
        (
            "IESNA:LM-63-2002\nTILT=NONE\n1 -1 1 2 2 1 2 0 0 0\n1 1 10\n0 90\n\n45 90\n5 6 7 8\n",
            "lamp.ies:7: type C horizontal angles run from 45° to 90°",
        ),
        // missing TILT
        (
            "IESNA:LM-63-2002\n[TEST] x\n1 -1 1 3 1 1 2 0 0 0\n1 1 10\n0 90 180\n0\n5 6 7\n",
            "lamp.ies:7: the file ends without a TILT= line",
        ),
        // tilt file
        (
            "IESNA:LM-63-1995\nTILT=lamp.tlt\n1 -1 1 3 1 1 2 0 0 0\n",
            "lamp.ies:2: TILT=lamp.tlt: tilt data in a separate file is not supported",
        ),
        // type B
        (
            "IESNA:LM-63-2002\nTILT=NONE\n1 -1 1 3 1\n2 2 0 0 0\n1 1 10\n-90 0 90\n0\n5 6 7\n",
            "lamp.ies:4: photometric type B (2) is not supported",
        ),
        // a count that is not a whole number
        (
            "IESNA:LM-63-2002\nTILT=NONE\n1 -1 1 2.5 1 1 2 0 0 0\n",
            "lamp.ies:3: the number of vertical angles must be a whole number",
        ),
        // a huge count fails at the end of the data, not in the allocator
        (
            "IESNA:LM-63-2002\nTILT=NONE\n1 -1 1 36001 36001 1 2 0 0 0\n1 1 10\n0 1\n",
            "lamp.ies:5: the file ends: expected vertical angle 3 of 36001",
        ),
        // units out of range
        (
            "IESNA:LM-63-2002\nTILT=NONE\n1 -1 1 3 1 1 3 0 0 0\n",
            "lamp.ies:3: the units type (1 feet, 2 metres) must be a whole number from 1 to 2",
        ),
    ];
    for (text, want) in cases {
        let e = err(text);
        assert!(e.starts_with(want), "got  {e}\nwant {want}");
    }
    assert!(err("hello\nworld\n").starts_with("lamp.ies:1: not a photometric file"));
    assert!(err("").starts_with("lamp.ies:1: not a photometric file"));
}

/// An EULUMDAT file of the lamp `s` stored as `isym` requires, C planes
/// every 15°, at 1000 lm (so cd/klm = cd) unless `flux` says otherwise.
fn ldt_of(isym: u8, s: Symmetry, sets: &[(i32, f64)], conversion: f64) -> String {
    let cs = range(0.0, 345.0, 15.0);
    let stored: Vec<f64> = match isym {
        0 => cs.clone(),
        1 => vec![0.0],
        2 => range(0.0, 180.0, 15.0),
        3 => range(270.0, 450.0, 15.0)
            .iter()
            .map(|c| c % 360.0)
            .collect(),
        _ => range(0.0, 90.0, 15.0),
    };
    let total: f64 = sets.iter().map(|s| s.1).sum();
    let mut l: Vec<String> = vec![
        "Scotopia test luminaires".into(),
        "3".into(),
        isym.to_string(),
        cs.len().to_string(),
        "15".into(),
        GAMMAS.len().to_string(),
        "30".into(),
        "report 1".into(),
        "Test lamp".into(),
        "T-1".into(),
        "test.ldt".into(),
        "2026-12-02".into(),
        "600".into(),
        "300".into(),
        "80".into(),
        "500".into(),
        "200".into(),
        "40".into(),
        "40".into(),
        "40,5".into(),
        "40".into(),
        "100".into(),
        "85".into(),
        format!("{conversion}"),
        "0".into(),
        sets.len().to_string(),
    ];
    l.extend(sets.iter().map(|s| s.0.to_string()));
    l.extend(sets.iter().map(|_| "LED".to_string()));
    l.extend(sets.iter().map(|s| s.1.to_string()));
    l.extend(sets.iter().map(|_| "4000 K".to_string()));
    l.extend(sets.iter().map(|_| "80".to_string()));
    l.extend(sets.iter().map(|_| "20,5".to_string()));
    l.extend((0..10).map(|k| format!("0,{}", 5 + k)));
    l.extend(cs.iter().map(|c| c.to_string()));
    l.extend(GAMMAS.iter().map(|g| g.to_string()));
    for &c in &stored {
        for &g in &GAMMAS {
            // cd/klm of a lamp whose candela are `value` at 1000 lm × conversion.
            let cd: f64 = value(g, c, s).parse().unwrap();
            l.push(format!("{}", cd * 1000.0 / total / conversion));
        }
    }
    l.join("\r\n") + "\r\n"
}

#[test]
fn eulumdat_symmetries_match_the_ies_lamp() {
    for (isym, s) in [
        (0, Symmetry::None),
        (2, Symmetry::AboutC0C180),
        (3, Symmetry::AboutC90C270),
        (4, Symmetry::Quadrant),
        (1, Symmetry::Rotational),
    ] {
        let ldt = parse_luminaire(&ldt_of(isym, s, &[(1, 1000.0)], 1.0), "lamp.ldt")
            .unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(ldt.format, Format::Eulumdat);
        assert_eq!(ldt.symmetry, s);
        let full = parse_luminaire(&ldt_of(0, s, &[(1, 1000.0)], 1.0), "lamp.ldt").unwrap();
        let ies = parse(&ies_of("IES:LM-63-2019", &range(0.0, 360.0, 15.0), s));
        for c in range(0.0, 360.0, 7.5) {
            for g in range(0.0, 180.0, 10.0) {
                let (g, c) = (g as f32, c as f32);
                let want = ies.intensity(g, c);
                assert!(
                    (ldt.intensity(g, c) - want).abs() < 1e-3 * want,
                    "Isym {isym} at {g}, {c}"
                );
                assert!((full.intensity(g, c) - want).abs() < 1e-3 * want);
            }
        }
        if s != Symmetry::Rotational {
            assert_eq!(ldt.c_deg, full.c_deg);
        }
    }
}

#[test]
fn eulumdat_converts_cd_per_klm_with_the_sets_total_flux() {
    // Two sets of 1200 lm and 800 lm in total, conversion factor 1.5: the
    // file's cd/klm × 2000/1000 × 1.5 gives the lamp's candela.
    let text = ldt_of(4, Symmetry::Quadrant, &[(2, 1200.0), (1, 800.0)], 1.5);
    let p = parse_luminaire(&text, "lamp.ldt").unwrap();
    let want: f32 = value(60.0, 30.0, Symmetry::Quadrant).parse().unwrap();
    assert!((p.intensity(60.0, 30.0) - want).abs() < 1e-3);
    assert_eq!(p.lamp_lumens, Some(2000.0));
    assert_eq!(p.input_watts, Some(41.0));
    assert!((p.opening.length_m - 0.5).abs() < 1e-12);
    assert!((p.opening.width_m - 0.2).abs() < 1e-12);
    assert!((p.opening.height_m - 0.0405).abs() < 1e-12);
}

#[test]
fn bad_eulumdat_files_name_the_line() {
    let good = ldt_of(4, Symmetry::Quadrant, &[(1, 1000.0)], 1.0);
    let lines: Vec<&str> = good.split("\r\n").collect();
    let with = |k: usize, v: &str| {
        let mut l = lines.clone();
        l[k - 1] = v;
        l.join("\n")
    };
    let e = |t: String| parse_luminaire(&t, "lamp.ldt").unwrap_err().to_string();
    // 26 + 6 + 10 header lines, 24 C angles, 7 γ angles, 7 × 7 intensities (Isym 4).
    let first_c = 43;
    let first_i = first_c + 24 + 7;
    assert!(e(lines[..30].join("\n")).starts_with("lamp.ldt:30: the file ends: expected line 31"));
    assert!(e(lines[..first_i + 10].join("\n"))
        .starts_with("lamp.ldt:84: the file ends: expected intensity 12 of 49"));
    assert!(e(with(first_i + 3, "-1")).starts_with("lamp.ldt:77: negative intensity -1"));
    assert!(e(with(first_i + 3, "lots")).starts_with("lamp.ldt:77: expected intensity 4 of 49"));
    assert!(e(with(first_c + 2, "10")).starts_with("lamp.ldt:45: C angle 10° does not increase"));
    assert!(
        e(with(first_c + 24 + 6, "200")).starts_with("lamp.ldt:73: γ angle 200° is out of range")
    );
    assert!(e(with(4, "22")).starts_with("lamp.ldt:4: Mc = 22 must be a multiple of 4"));
    assert!(
        e(with(6, "x")).starts_with("lamp.ldt:6: expected Ng, the number of γ angles, found 'x'")
    );
    assert!(e(with(29, "0")).starts_with("lamp.ldt:29: the lamps' total luminous flux is 0 lm"));
    assert!(e(good.clone() + "1\n").contains("after the last of the 49 intensities"));
    // Isym 2 with planes that do not end at C180.
    let mut l = lines.clone();
    l[2] = "2";
    l[first_c + 12 - 1] = "181";
    let text = l.join("\n");
    assert!(e(text).starts_with("lamp.ldt:55: symmetry indicator 2 stores the planes C0° to C180°"));
}

/// A tiny deterministic generator (fixed seed).
struct Lcg(u64);
impl Lcg {
    fn next(&mut self, n: usize) -> usize {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((self.0 >> 33) % n as u64) as usize
    }
}

#[test]
fn mutated_files_never_panic() {
    let files = [
        ies_of("IESNA:LM-63-1995", &range(0.0, 90.0, 15.0), Symmetry::Quadrant),
        ldt_of(3, Symmetry::AboutC90C270, &[(1, 1000.0)], 1.0),
        "IESNA:LM-63-2002\nTILT=INCLUDE\n1\n3\n0 45 90\n1 0.95 0.9\n1 -1 1 2 1 1 2 0 0 0\n1 1 10\n0 90\n0\n7 7\n"
            .to_string(),
    ];
    let pieces = [
        "",
        "-1",
        "0",
        "1e308",
        "nan",
        "360",
        "99999999999",
        ",",
        "\n",
        "TILT=",
        "x",
    ];
    let mut rng = Lcg(24);
    let mut parsed = 0;
    for text in &files {
        // Every truncation.
        for cut in (0..text.len()).filter(|&k| text.is_char_boundary(k)) {
            let _ = parse_luminaire(&text[..cut], "m");
        }
        // Token replacements, deletions and duplications.
        for _ in 0..2000 {
            let mut tokens: Vec<String> = text.split(' ').map(str::to_string).collect();
            let k = rng.next(tokens.len());
            match rng.next(3) {
                0 => tokens[k] = pieces[rng.next(pieces.len())].to_string(),
                1 => {
                    tokens.remove(k);
                }
                _ => {
                    let t = tokens[k].clone();
                    tokens.insert(k, t);
                }
            }
            if let Ok(p) = parse_luminaire(&tokens.join(" "), "m") {
                parsed += 1;
                let f = p.total_flux_lm();
                assert!(f.is_finite() && f >= 0.0);
                for c in [0.0, 91.0, 359.0] {
                    let v = p.intensity(45.0, c);
                    assert!(v.is_finite() && v >= 0.0);
                }
            }
        }
        // Line replacements.
        for _ in 0..2000 {
            let mut lines: Vec<&str> = text.lines().collect();
            let k = rng.next(lines.len());
            lines[k] = pieces[rng.next(pieces.len())];
            let _ = parse_luminaire(&lines.join("\n"), "m");
        }
    }
    assert!(parsed > 0);
}

#[test]
fn files_are_recognised_by_content_and_errors_name_them() {
    let dir = std::env::temp_dir().join(format!("scotopia-luminaire-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    // An EULUMDAT file named .ies and an IES file named .ldt.
    let ldt = dir.join("street.ies");
    std::fs::write(&ldt, ldt_of(2, Symmetry::AboutC0C180, &[(1, 1000.0)], 1.0)).unwrap();
    assert_eq!(read_luminaire(&ldt).unwrap().format, Format::Eulumdat);
    let ies = dir.join("street.ldt");
    std::fs::write(
        &ies,
        ies_of("IESNA:LM-63-2002", &[0.0], Symmetry::Rotational),
    )
    .unwrap();
    assert_eq!(
        read_luminaire(&ies).unwrap().format,
        Format::Ies { year: 2002 }
    );
    // Latin-1 text in a name does not stop a file.
    let mut bytes = ldt_of(1, Symmetry::Rotational, &[(1, 1000.0)], 1.0).into_bytes();
    bytes[0] = 0xC4; // 'Ä' in Latin-1, invalid UTF-8
    let latin = dir.join("latin1.ldt");
    std::fs::write(&latin, bytes).unwrap();
    assert!(read_luminaire(&latin).is_ok());
    let missing = dir.join("missing.ies");
    let e = read_luminaire(&missing).unwrap_err().to_string();
    assert!(e.starts_with(&format!("{}: ", missing.display())), "{e}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_file_of_many_planes_reads_in_linear_logarithmic_time() {
    // 36 001 planes from 0° to 90° (quadrant symmetry: 144 004 images
    // before merging the mirrored ones): a quadratic merge would take
    // minutes here.
    let n = 36_001;
    let cs: Vec<String> = (0..n).map(|k| format!("{}", k as f64 * 0.0025)).collect();
    let text = format!(
        "IESNA:LM-63-2002\nTILT=NONE\n1 -1 1 2 {n} 1 2 0 0 0\n1 1 10\n0 90\n{}\n{}\n",
        wrap(&cs, 10),
        vec!["3"; 2 * n].join(" ")
    );
    let p = parse(&text);
    assert_eq!(p.symmetry, Symmetry::Quadrant);
    assert_eq!(p.c_deg.len(), 4 * (n - 1) + 1);
    assert_eq!(p.intensity(45.0, 123.456), 3.0);
}

#[test]
fn eulumdat_with_ies_words_in_its_text_lines_is_eulumdat() {
    // A company starting "IES", and "TILT=" in the luminaire's name, lamp
    // type and file name: free text, not structure.
    let good = ldt_of(4, Symmetry::Quadrant, &[(1, 1000.0)], 1.0);
    let want = parse_luminaire(&good, "lamp.ldt").unwrap();
    let lines: Vec<&str> = good.split("\r\n").collect();
    for (k, text) in [
        (0, "IES Lighting Ltd"),
        (0, "IESNA member luminaires"),
        (0, "IES:catalogue 2026"),
        (8, "TILT=NONE street lantern"),
        (10, "TILT=INCLUDE.ldt"),
        (27, "TILT=0"),
    ] {
        let mut l = lines.clone();
        l[k] = text;
        let p = parse_luminaire(&l.join("\r\n"), "lamp.ldt")
            .unwrap_or_else(|e| panic!("line {}: {text}: {e}", k + 1));
        assert_eq!(p.format, Format::Eulumdat, "{text}");
        assert_eq!(p.intensity(30.0, 45.0), want.intensity(30.0, 45.0));
    }
    // A broken one is still reported as EULUMDAT (line 24's factor).
    let mut l = lines.clone();
    l[0] = "IES Lighting Ltd";
    l[23] = "-1";
    let e = parse_luminaire(&l.join("\r\n"), "lamp.ldt").unwrap_err();
    assert!(
        e.to_string()
            .starts_with("lamp.ldt:24: the conversion factor"),
        "{e}"
    );
}

#[test]
fn cr_lf_and_crlf_line_endings_all_read() {
    let ldt = ldt_of(2, Symmetry::AboutC0C180, &[(1, 1000.0)], 1.0);
    let ies = ies_of(
        "IESNA:LM-63-2002",
        &range(0.0, 180.0, 15.0),
        Symmetry::AboutC0C180,
    );
    for (text, format) in [(ldt, Format::Eulumdat), (ies, Format::Ies { year: 2002 })] {
        let lf = text.replace("\r\n", "\n");
        let want = parse_luminaire(&lf, "lamp").unwrap();
        for ending in ["\r", "\r\n"] {
            let p = parse_luminaire(&lf.replace('\n', ending), "lamp")
                .unwrap_or_else(|e| panic!("{ending:?}: {e}"));
            assert_eq!(p.format, format);
            assert_eq!(p.intensity(30.0, 45.0), want.intensity(30.0, 45.0));
            assert_eq!(p.c_deg, want.c_deg);
        }
        // Errors name the same line whatever the endings.
        let broken = lf.replacen("\n1\n", "\nx\n", 1);
        if let Err(e) = parse_luminaire(&broken, "lamp") {
            let cr = parse_luminaire(&broken.replace('\n', "\r"), "lamp").unwrap_err();
            assert_eq!(cr.line, e.line);
        }
    }
}
