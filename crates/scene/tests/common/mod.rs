//! Helpers shared by the integration tests: writers of Mitsuba's
//! serialized meshes and `.vol` grids (for loading tests that need one),
//! and the statistical checks of images and measurements.
#![allow(dead_code)]

use std::io::Write;

use scotopia_render::integrator::Measured;
use scotopia_render::scene::Scene;

/// The bundled scene `scenes/NAME` with parameters `params`.
pub fn scene(name: &str, params: &[(&str, &str)]) -> Scene {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenes")
        .join(name);
    let mut p = scotopia_scene::mitsuba::Parameters::new();
    for (k, v) in params {
        p.insert(k.to_string(), v.to_string());
    }
    scotopia_scene::load_scene(&path, &p).unwrap()
}

/// The scene in `xml`, written to a temporary file `name` and loaded.
pub fn inline(name: &str, xml: &str) -> Scene {
    let file = std::env::temp_dir().join(format!("scotopia-{name}-{}.xml", std::process::id()));
    std::fs::write(&file, xml).expect("the temporary directory takes the scene");
    let s = scotopia_scene::load_scene(&file, &scotopia_scene::mitsuba::Parameters::new())
        .unwrap_or_else(|e| panic!("test scene {name}: {e}"));
    let _ = std::fs::remove_file(&file);
    s
}

/// One shape to write.
#[derive(Clone)]
pub struct Mesh {
    pub name: &'static str,
    pub positions: Vec<[f64; 3]>,
    pub normals: Option<Vec<[f64; 3]>>,
    pub uvs: Option<Vec<[f64; 2]>>,
    pub colors: Option<Vec<[f64; 3]>>,
    pub indices: Vec<[u32; 3]>,
}

/// A quad in the z = `z` plane, as two triangles.
pub fn quad(name: &'static str, z: f64) -> Mesh {
    Mesh {
        name,
        positions: vec![[0.0, 0.0, z], [1.0, 0.0, z], [1.0, 1.0, z], [0.0, 1.0, z]],
        normals: Some(vec![[0.0, 0.0, 1.0]; 4]),
        uvs: Some(vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]),
        colors: Some(vec![[0.25, 0.5, 0.75]; 4]),
        indices: vec![[0, 1, 2], [0, 2, 3]],
    }
}

/// Writes a serialized file (version 3 or 4) holding `meshes`, with the
/// end-of-file dictionary, as Mitsuba's format description states.
pub fn write(meshes: &[Mesh], version: u16, double: bool) -> Vec<u8> {
    let mut out = Vec::new();
    let mut offsets = Vec::new();
    for m in meshes {
        offsets.push(out.len() as u64);
        out.extend_from_slice(&0x041Cu16.to_le_bytes());
        out.extend_from_slice(&version.to_le_bytes());
        let mut d = Vec::new();
        let flags = m.normals.as_ref().map_or(0, |_| 0x1)
            | m.uvs.as_ref().map_or(0, |_| 0x2)
            | m.colors.as_ref().map_or(0, |_| 0x8)
            | if double { 0x2000 } else { 0x1000 };
        d.extend_from_slice(&(flags as u32).to_le_bytes());
        if version == 4 {
            d.extend_from_slice(m.name.as_bytes());
            d.push(0);
        }
        d.extend_from_slice(&(m.positions.len() as u64).to_le_bytes());
        d.extend_from_slice(&(m.indices.len() as u64).to_le_bytes());
        let mut put = |values: &[f64]| {
            for &v in values {
                if double {
                    d.extend_from_slice(&v.to_le_bytes());
                } else {
                    d.extend_from_slice(&(v as f32).to_le_bytes());
                }
            }
        };
        put(m.positions.concat().as_slice());
        if let Some(n) = &m.normals {
            put(n.concat().as_slice());
        }
        if let Some(t) = &m.uvs {
            put(t.concat().as_slice());
        }
        if let Some(c) = &m.colors {
            put(c.concat().as_slice());
        }
        for t in &m.indices {
            for i in t {
                d.extend_from_slice(&i.to_le_bytes());
            }
        }
        let mut z = flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::default());
        z.write_all(&d).unwrap();
        out.extend_from_slice(&z.finish().unwrap());
    }
    for o in &offsets {
        if version == 4 {
            out.extend_from_slice(&o.to_le_bytes());
        } else {
            out.extend_from_slice(&(*o as u32).to_le_bytes());
        }
    }
    out.extend_from_slice(&(meshes.len() as u32).to_le_bytes());
    out
}

/// A Mitsuba `.vol` file (version 3, float32) of `res` cells over the unit
/// box, values `f(x, y, z)` for the cell (x, y, z) in Mitsuba's order.
pub fn vol(res: usize, channels: usize, f: impl Fn(usize, usize, usize) -> Vec<f32>) -> Vec<u8> {
    let mut b = b"VOL\x03".to_vec();
    for v in [1i32, res as i32, res as i32, res as i32, channels as i32] {
        b.extend_from_slice(&v.to_le_bytes());
    }
    for v in [0.0f32, 0.0, 0.0, 1.0, 1.0, 1.0] {
        b.extend_from_slice(&v.to_le_bytes());
    }
    for z in 0..res {
        for y in 0..res {
            for x in 0..res {
                let v = f(x, y, z);
                assert_eq!(v.len(), channels);
                for c in v {
                    b.extend_from_slice(&c.to_le_bytes());
                }
            }
        }
    }
    b
}

/// Asserts that the pixel mean of `a − b` is zero within 4 standard
/// errors in every channel; prints the relative difference of the means.
pub fn agree(what: &str, a: &[[f32; 4]], b: &[[f32; 4]]) {
    for c in 0..4 {
        let d: Vec<f64> = a.iter().zip(b).map(|(p, q)| (p[c] - q[c]) as f64).collect();
        let n = d.len() as f64;
        let mean = d.iter().sum::<f64>() / n;
        let se = (d.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0) / n).sqrt();
        let level = b.iter().map(|p| p[c] as f64).sum::<f64>() / n;
        if c == 1 {
            eprintln!(
                "{what}: mean Y difference {:+.3} % ± {:.3} % (SE) of {level:.4}",
                100.0 * mean / level,
                100.0 * se / level
            );
        }
        assert!(
            mean.abs() <= 4.0 * se && level > 0.0,
            "{what}, channel {c}: difference {mean} ± {se} (level {level})"
        );
    }
}

pub fn assert_close(what: &str, m: &Measured, expected: f64) {
    eprintln!(
        "{what}: E = {:.4} ± {:.4} lx, expected {expected:.4}",
        m.e, m.e_se
    );
    let tol = 4.0 * m.e_se + 5e-3 * expected;
    assert!(
        (m.e - expected).abs() <= tol,
        "{what}: E = {} ± {} lx, expected {expected}",
        m.e,
        m.e_se
    );
}
