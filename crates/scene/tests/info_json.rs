//! `SceneInfo` serialises to the keys `scotopia info --json` prints and
//! Python's `scene_info` returns, in their order.

use std::path::Path;

use scotopia_scene::{load_scene, MediumInfo, SceneInfo};
use serde_json::Value;

fn keys(v: &Value) -> Vec<&str> {
    v.as_object().unwrap().keys().map(String::as_str).collect()
}

#[test]
fn scene_info_serialises_to_infos_keys() {
    let scenes = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
    let scene = load_scene(&scenes.join("foggy-street.xml"), &Default::default()).unwrap();
    let v = serde_json::to_value(SceneInfo::of(&scene)).unwrap();
    assert_eq!(
        keys(&v),
        [
            "shapes",
            "triangles",
            "instances",
            "materials",
            "emitters",
            "camera",
            "film",
            "samples_per_pixel",
            "max_depth",
            "lights",
            "media",
            "warnings"
        ]
    );
    assert_eq!(
        keys(&v["camera"]),
        [
            "fov_degrees",
            "thin_lens",
            "projection",
            "irradiancemeter_shape"
        ]
    );
    assert_eq!(keys(&v["film"]), ["width", "height", "filter"]);
    assert_eq!(keys(&v["lights"][0]), ["type", "watts", "lumens"]);
    assert_eq!(
        keys(&v["media"][0]),
        [
            "type",
            "sigma_t_550",
            "albedo_550",
            "g",
            "optical_thickness",
            "grids"
        ]
    );
    assert_eq!(v["camera"]["irradiancemeter_shape"], Value::Null);
    assert_eq!(v["film"]["width"], 640);
}

#[test]
fn a_heterogeneous_mediums_extinction_is_its_largest() {
    let m = MediumInfo {
        kind: "heterogeneous",
        sigma_t: 25.0,
        albedo: None,
        g: 0.0,
        optical_thickness: 1.0,
        grids: Vec::new(),
    };
    let v = serde_json::to_value(&m).unwrap();
    assert_eq!(v["sigma_t_max"], 25.0);
    assert!(v.get("sigma_t_550").is_none());
    assert_eq!(v["albedo_550"], Value::Null);
}
