//! The images the renderer makes, pinned bit for bit (issue 39): every
//! bundled scene is rendered small in several configurations (each
//! integrator, each tracer, the wavelength strategies, illuminance) and
//! measured at points, and a hash of the pixels' bits (or of the CSV) is
//! compared with `same_images.txt`. A restructuring of the transport
//! must leave every line as it is; a change that means to alter images
//! rewrites the table (`SCOTOPIA_BLESS=1 cargo test -p scotopia --test
//! same_images`) and says why in its commit.
//!
//! Mitsuba's own scenes (the conformance suite, not in this repository)
//! are rendered too when `SCOTOPIA_MITSUBA_DATA` names a checkout of
//! mitsuba-data; their lines are skipped where it does not.
//!
//! The hashes hold on any x86-64 with the system's libm: Rust contracts no
//! multiply-adds, the wide tracer gives the scalar one's image bit for bit
//! at every SIMD level, and a pixel's samples do not depend on the number
//! of threads.

mod common;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;

use common::{out_dir, scenes};

const TABLE: &str = "tests/same_images.txt";

/// What each bundled scene is rendered with, besides its own settings.
const RENDERS: &[(&str, &[&str])] = &[
    ("default", &[]),
    ("path", &["--integrator", "path"]),
    ("bdpt", &["--integrator", "bdpt"]),
    (
        "wavefront",
        &["--integrator", "path", "--tracer", "wavefront"],
    ),
    ("hero", &["--wavelengths", "hero", "--cluster", "8"]),
    ("single", &["--wavelengths", "single", "--cluster", "1"]),
    ("illuminance", &["--quantity", "illuminance"]),
];

/// The outcome of one case: a hash of what it wrote, or `refused` when it
/// ended with an error (an unsupported combination).
fn run_case(args: &[String], output: &Path) -> String {
    let _ = std::fs::remove_file(output);
    let out = Command::new(env!("CARGO_BIN_EXE_scotopia"))
        .args(args)
        .output()
        .expect("run scotopia");
    if !out.status.success() {
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            out.status.code() == Some(1) && !err.contains("panicked"),
            "{args:?}: {err}"
        );
        return "refused".into();
    }
    let hash = if output.extension().is_some_and(|e| e == "csv") {
        xxhash_rust::xxh3::xxh3_64(&std::fs::read(output).unwrap())
    } else {
        pixels_hash(output)
    };
    format!("{hash:016x}")
}

/// A hash of an EXR's channel names and the bits of every value (not its
/// metadata, which holds the render time).
fn pixels_hash(path: &Path) -> u64 {
    let image = scotopia_image::read_exr(path).unwrap();
    let mut bytes = Vec::new();
    bytes.extend((image.width as u64).to_le_bytes());
    bytes.extend((image.height as u64).to_le_bytes());
    for (name, values) in &image.channels {
        bytes.extend(name.as_bytes());
        bytes.extend(values.iter().flat_map(|v| v.to_bits().to_le_bytes()));
    }
    xxhash_rust::xxh3::xxh3_64(&bytes)
}

fn s(p: &Path) -> String {
    p.to_str().unwrap().to_string()
}

/// Every case: (name, arguments, output).
fn cases(dir: &Path) -> Vec<(String, Vec<String>, PathBuf)> {
    let mut cases = Vec::new();
    let mut bundled: Vec<PathBuf> = std::fs::read_dir(scenes())
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "xml"))
        .collect();
    bundled.sort();
    let exr = dir.join("case.exr");
    for scene in &bundled {
        let stem = scene.file_stem().unwrap().to_string_lossy().into_owned();
        for (what, extra) in RENDERS {
            let mut args: Vec<String> = ["render", &s(scene), "--res", "24", "--spp", "2"]
                .map(String::from)
                .to_vec();
            args.extend(["--threads", "2", "-o", &s(&exr)].map(String::from));
            args.extend(extra.iter().map(|a| a.to_string()));
            cases.push((format!("{stem} {what}"), args, exr.clone()));
        }
    }
    let csv = dir.join("case.csv");
    let measure = [
        "measure",
        &s(&scenes().join("ies-street.xml")),
        "--points",
        &s(&scenes().join("ies-street-grid.csv")),
        "--spp",
        "4",
        "--threads",
        "2",
        "-o",
        &s(&csv),
    ]
    .map(String::from)
    .to_vec();
    cases.push(("ies-street measure".into(), measure, csv));
    if let Some(data) = std::env::var_os("SCOTOPIA_MITSUBA_DATA") {
        for scene in mitsuba_scenes(Path::new(&data)) {
            let name = scene.strip_prefix(&data).unwrap().display().to_string();
            let args = ["render", &s(&scene), "--res", "16", "--spp", "1"]
                .into_iter()
                .chain(["--threads", "2", "-o", &s(&exr)])
                .map(String::from)
                .collect();
            cases.push((format!("mitsuba-data/{name} default"), args, exr.clone()));
        }
    }
    cases
}

/// The scene files of a mitsuba-data checkout, as the conformance script
/// takes them: not under `include/` or `fragments/`, sorted.
fn mitsuba_scenes(data: &Path) -> Vec<PathBuf> {
    let mut found = Vec::new();
    let mut stack = vec![data.join("scenes"), data.join("docs").join("scenes")];
    while let Some(dir) = stack.pop() {
        let Ok(entries) = std::fs::read_dir(&dir) else {
            continue;
        };
        for e in entries.flatten() {
            let p = e.path();
            let name = e.file_name().to_string_lossy().into_owned();
            if p.is_dir() && name != "include" && name != "fragments" {
                stack.push(p);
            } else if name.ends_with(".xml")
                && std::fs::read_to_string(&p).is_ok_and(|t| t.contains("<scene"))
            {
                found.push(p);
            }
        }
    }
    found.sort();
    found
}

fn read_table(path: &Path) -> BTreeMap<String, String> {
    std::fs::read_to_string(path)
        .unwrap_or_default()
        .lines()
        .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
        .filter_map(|l| l.rsplit_once(' '))
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .collect()
}

#[test]
fn every_image_is_the_one_in_the_table() {
    let table_path = Path::new(env!("CARGO_MANIFEST_DIR")).join(TABLE);
    let table = read_table(&table_path);
    let dir = out_dir("same", "images");
    let cases = cases(&dir);
    let mut got = BTreeMap::new();
    for (name, args, output) in &cases {
        got.insert(name.clone(), run_case(args, output));
    }
    let _ = std::fs::remove_dir_all(&dir);
    if std::env::var_os("SCOTOPIA_BLESS").is_some() {
        // Lines of cases not run here (Mitsuba's scenes without the data)
        // are kept.
        let mut all = table.clone();
        all.extend(got);
        let mut text = String::from(
            "# Hashes of the pixels each case renders (crates/cli/tests/same_images.rs).\n",
        );
        for (k, v) in all {
            text += &format!("{k} {v}\n");
        }
        std::fs::write(&table_path, text).unwrap();
        return;
    }
    let mut differ = Vec::new();
    for (name, hash) in &got {
        match table.get(name) {
            Some(h) if h == hash => {}
            Some(h) => differ.push(format!("{name}: {hash}, the table has {h}")),
            None => differ.push(format!("{name}: {hash}, not in the table")),
        }
    }
    let bundled_missing: Vec<_> = table
        .keys()
        .filter(|k| !k.starts_with("mitsuba-data/") && !got.contains_key(*k))
        .collect();
    assert!(
        differ.is_empty() && bundled_missing.is_empty(),
        "{} of {} cases differ from {TABLE} (rerun with SCOTOPIA_BLESS=1 only if the images are meant to change):\n{}\nno longer run: {bundled_missing:?}",
        differ.len(),
        got.len(),
        differ.join("\n")
    );
}
