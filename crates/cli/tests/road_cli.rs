//! `scotopia road`: EN 13201-3's luminance method on the bundled street
//! with the CIE R3 road: the figures in JSON, the grid as CSV, and bad
//! roads refused.

mod common;

use common::{out_dir, scenes, scotopia};

#[test]
fn the_street_gets_its_road_figures_grid_and_points() {
    let dir = out_dir("road", "street");
    let scene = scenes().join("ies-street.xml");
    let (grid, out) = (dir.join("grid.csv"), dir.join("road.csv"));
    let (code, json, err) = scotopia(&[
        "road",
        scene.to_str().unwrap(),
        "-D",
        "road=r3",
        "--start=-3.5,0,0",
        "--along",
        "0,0,-1",
        "--across",
        "1,0,0",
        "--spacing",
        "30",
        "--spp",
        "16",
        "--direct",
        "--json",
        "-o",
        out.to_str().unwrap(),
        "--grid",
        grid.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    assert_eq!(v["points"], 60);
    let observers = v["observers"].as_array().unwrap();
    assert_eq!(observers.len(), 2);
    for o in observers {
        for key in ["L_av_cdm2", "U_o", "U_l", "Lv_cdm2", "TI_percent"] {
            assert!(o[key].as_f64().unwrap() > 0.0, "{key}: {o}");
        }
    }
    // The grid as a points file `measure` reads, and one row per point
    // and observer.
    let g = std::fs::read_to_string(&grid).unwrap();
    assert!(
        g.starts_with("x,y,z,nx,ny,nz\n") && g.lines().count() == 61,
        "{g}"
    );
    assert!(g.lines().nth(1).unwrap().starts_with("-2.9166"), "{g}");
    let rows = std::fs::read_to_string(&out).unwrap();
    assert!(rows.starts_with("lane,row,x,y,z,observer,L_cdm2,L_cdm2_se,SP,Lmes_cdm2\n"));
    assert_eq!(rows.lines().count(), 121);
    // The text table.
    let (code, text, err) = scotopia(&[
        "road",
        scene.to_str().unwrap(),
        "--start=-3.5,0,0",
        "--along",
        "0,0,-1",
        "--across",
        "1,0,0",
        "--spacing",
        "30",
        "--spp",
        "4",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(
        text.contains("L_av cd/m²") && text.contains("TI %"),
        "{text}"
    );
    // A road without lanes, or along nothing, is refused.
    for (lanes, along, says) in [("0", "0,0,-1", "lanes"), ("2", "0,0,0", "not zero")] {
        let args = vec![
            "road",
            scene.to_str().unwrap(),
            "--start=-3.5,0,0",
            "--along",
            along,
            "--across",
            "1,0,0",
            "--spacing",
            "30",
            "--lanes",
            lanes,
        ];
        let (code, _, err) = scotopia(&args);
        assert_ne!(code, 0);
        assert!(err.contains(says), "{lanes} lanes along {along}: {err}");
    }
}
