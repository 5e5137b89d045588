//! Bounded, seeded fuzzing of everything scotopia reads (issue 22): scenes
//! (XML), meshes (OBJ, PLY, Mitsuba's serialized), spectra and reradiation
//! matrices (CSV), images (EXR), checkpoints, photometric files (IES,
//! EULUMDAT) and `measure`'s points files (issue 38) are mutated
//! — bytes flipped, cut, repeated, extreme numbers and odd tokens spliced
//! in — and fed to the command line in a child process each. Every run
//! must end in success or a clean error: no panic, no death by a signal,
//! no hang, and an error names the file it is about.
//!
//! `SCOTOPIA_FUZZ_CASES` sets the mutations per input (default 40, about
//! half a minute on 2 cores); `make fuzz` runs many more.

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

mod common;
// The serialized-mesh writer of the loader's tests.
#[path = "../../scene/tests/common/mod.rs"]
mod serialized_writer;

use common::{out_dir, scenes};

/// SplitMix64: reproducible mutations.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
}

/// What mutations splice in: extreme and odd numbers, names that mean
/// something to the loader, bytes that are not UTF-8.
const TOKENS: &[&[u8]] = &[
    b"1e38",
    b"-1e38",
    b"3.4e39",
    b"1e-45",
    b"nan",
    b"inf",
    b"-inf",
    b"-1",
    b"0",
    b"-0",
    b"4294967296",
    b"99999999999999999999",
    b"1e9",
    b"$undefined",
    b"\xff\xfe",
    b"\0",
    b"<bsdf type=\"twosided\">",
    b"</scene>",
    b"<ref id=\"x\"/>",
    b"\"",
    b"<",
    b"&amp;",
    b",,,",
    b"e",
    b"\n",
    b" ",
    b"\r",
    b"\xef\xbb\xbf",
    b"TILT=NONE",
    b"IESNA:LM-63-2002",
    b"1e-40",
];

fn mutate(input: &[u8], rng: &mut Rng) -> Vec<u8> {
    let mut b = input.to_vec();
    for _ in 0..1 + rng.below(4) {
        let at = rng.below(b.len() + 1);
        match rng.below(6) {
            0 if at < b.len() => b[at] ^= 1 << rng.below(8),
            1 => {
                let end = (at + 1 + rng.below(16)).min(b.len());
                b.drain(at..end);
            }
            2 => {
                let end = (at + 1 + rng.below(64)).min(b.len());
                let copy = b[at..end].to_vec();
                b.splice(at..at, copy);
            }
            3 => {
                // A number replaced by an extreme one.
                let digits = b[at..].iter().position(|c| c.is_ascii_digit());
                if let Some(d) = digits {
                    let s = at + d;
                    let e = s + b[s..]
                        .iter()
                        .take_while(|c| c.is_ascii_digit() || **c == b'.')
                        .count();
                    let t = TOKENS[rng.below(12)];
                    b.splice(s..e, t.iter().copied());
                }
            }
            4 => b.truncate(at),
            _ => {
                let t = TOKENS[rng.below(TOKENS.len())];
                b.splice(at..at, t.iter().copied());
            }
        }
    }
    b
}

/// Runs `scotopia args` with a time limit: Err with what went wrong.
fn run_clean(args: &[&str], about: &str) -> Result<(), String> {
    run_program(env!("CARGO_BIN_EXE_scotopia"), args, about)
}

fn run_program(program: &str, args: &[&str], about: &str) -> Result<(), String> {
    let mut child = Command::new(program)
        .args(args)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| e.to_string())?;
    let start = Instant::now();
    let status = loop {
        if let Some(s) = child.try_wait().map_err(|e| e.to_string())? {
            break s;
        }
        if start.elapsed() > Duration::from_secs(60) {
            let _ = child.kill();
            return Err(format!("{args:?}: still running after 60 s"));
        }
        std::thread::sleep(Duration::from_millis(5));
    };
    let mut err = String::new();
    if let Some(mut e) = child.stderr.take() {
        let _ = std::io::Read::read_to_string(&mut e, &mut err);
    }
    match status.code() {
        Some(0) => Ok(()),
        Some(1) if err.contains("panicked") => Err(format!("{args:?}: panicked: {err}")),
        Some(1) if !err.contains(about) => {
            Err(format!("{args:?}: the error does not name {about}: {err}"))
        }
        Some(1) => Ok(()),
        Some(c) => Err(format!("{args:?}: exit {c}: {err}")),
        None => Err(format!("{args:?}: killed by a signal: {err}")),
    }
}

fn cases() -> usize {
    std::env::var("SCOTOPIA_FUZZ_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(40)
}

/// Mutates `input` `cases()` times (seeded by `seed`), writes each to
/// `dir/name` and checks `command(path)`; all failures are reported.
fn fuzz(seed: u64, input: &[u8], dir: &Path, name: &str, command: impl Fn(&Path) -> Vec<String>) {
    fuzz_with(seed, input, dir, name, |b| b.to_vec(), command)
}

/// [`fuzz`] with `wrap` applied to each mutation before it is written (to
/// mutate a compressed format's contents and compress them again).
fn fuzz_with(
    seed: u64,
    input: &[u8],
    dir: &Path,
    name: &str,
    wrap: impl Fn(&[u8]) -> Vec<u8>,
    command: impl Fn(&Path) -> Vec<String>,
) {
    // The input itself must work, or the mutations test nothing.
    let path = dir.join(name);
    std::fs::write(&path, wrap(input)).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_scotopia"))
        .args(command(&path))
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{name} unmutated fails: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let mut rng = Rng(seed);
    let mut failures = Vec::new();
    for case in 0..cases() {
        let bytes = wrap(&mutate(input, &mut rng));
        let path = dir.join(name);
        std::fs::write(&path, &bytes).unwrap();
        let args = command(&path);
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        if let Err(e) = run_clean(&args, name) {
            let keep = dir.join(format!("failing-{case}-{name}"));
            let _ = std::fs::copy(&path, &keep);
            failures.push(format!("case {case} (kept as {}): {e}", keep.display()));
        }
    }
    assert!(
        failures.is_empty(),
        "{} failures:\n{}",
        failures.len(),
        failures.join("\n")
    );
}

fn s(p: &Path) -> String {
    p.to_str().unwrap().to_string()
}

fn s_ref(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// The night street with its shared world written in place of its
/// `<include>`, so that the mutations reach the world's elements too.
fn inline_world(text: &str) -> Vec<u8> {
    let include = r#"<include filename="include/night-street-world.xml"/>"#;
    if !text.contains(include) {
        return text.as_bytes().to_vec();
    }
    let world = std::fs::read_to_string(scenes().join("include/night-street-world.xml")).unwrap();
    let body = &world[world.find("<scene").unwrap()..];
    let body = &body[body.find('>').unwrap() + 1..body.rfind("</scene>").unwrap()];
    text.replace(include, body).into_bytes()
}

#[test]
fn mutated_scenes_load_or_fail_cleanly() {
    let dir = out_dir("fuzz", "xml");
    // The scene's relative files resolve from the copy's folder.
    for sub in ["meshes", "lamps", "materials", "textures", "include"] {
        let _ = std::os::unix::fs::symlink(scenes().join(sub), dir.join(sub));
    }
    // A small scene whose film size and spectra are literal numbers, for
    // the mutations of numbers to reach them.
    let small = br#"<scene version="3.0.0"><sensor type="perspective"><float name="fov" value="40"/><film type="hdrfilm"><integer name="width" value="5"/><integer name="height" value="4"/></film><sampler type="independent"><integer name="sample_count" value="2"/></sampler></sensor><shape type="sphere"><float name="radius" value="0.5"/><transform name="to_world"><translate z="3"/></transform><bsdf type="diffuse"><spectrum name="reflectance" value="400:0.2, 500:0.5, 700:0.9"/></bsdf></shape><emitter type="point"><point name="position" x="0" y="0" z="0"/><spectrum name="intensity" value="400:1, 700:3"/></emitter></scene>"#;
    for (i, scene) in ["cornell-box.xml", "prism.xml", "night-street.xml", ""]
        .iter()
        .enumerate()
    {
        let text = match *scene {
            "" => small.to_vec(),
            name => inline_world(&std::fs::read_to_string(scenes().join(name)).unwrap()),
        };
        let out = dir.join("out.exr");
        // The Cornell box at 8 pixels through its parameter, the small
        // scene at its own film size (a mutated size must be refused or
        // rendered), the others 6 pixels wide.
        let res: &[&str] = match i {
            0 => &["-D", "res=8"],
            3 => &[],
            _ => &["--res", "6"],
        };
        fuzz(10 + i as u64, &text, &dir, "case.xml", |p| {
            let mut a = vec!["render".into(), s(p), "--spp".into(), "1".into()];
            a.extend(["-o".into(), s(&out)]);
            a.extend(res.iter().map(|v| v.to_string()));
            a
        });
    }
}

/// Writes `dir/name` — a 4 × 4 scene of `shape` under a constant sky —
/// and gives the command that renders it at 1 spp (the fuzzed file is
/// one the shape names).
fn tiny_scene(dir: &Path, name: &str, shape: &str) -> impl Fn(&Path) -> Vec<String> {
    let xml = format!(
        "<scene version=\"3.0.0\"><sensor type=\"perspective\"><film type=\"hdrfilm\"><integer name=\"width\" value=\"4\"/><integer name=\"height\" value=\"4\"/></film></sensor>{shape}<emitter type=\"constant\"/></scene>"
    );
    let scene = dir.join(name);
    std::fs::write(&scene, xml).unwrap();
    let out = dir.join("out.exr");
    move |_| {
        ["render", &s(&scene), "--spp", "1", "-o", &s(&out)]
            .map(String::from)
            .to_vec()
    }
}

#[test]
fn mutated_meshes_load_or_fail_cleanly() {
    let dir = out_dir("fuzz", "mesh");
    let obj = std::fs::read(scenes().join("meshes/prism.obj")).unwrap();
    let ply = b"ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n0 0 0 255 0 0\n1 0 0 0 255 0\n1 1 0 0 0 255\n0 1 0 9 9 9\n3 0 1 2\n3 0 2 3\n".to_vec();
    for (seed, name, bytes) in [(20, "case.obj", obj), (21, "case.ply", ply)] {
        let kind = &name[5..];
        let shape =
            format!("<shape type=\"{kind}\"><string name=\"filename\" value=\"{name}\"/></shape>");
        let render = tiny_scene(&dir, &format!("{kind}.xml"), &shape);
        fuzz(seed, &bytes, &dir, name, render);
    }
}

/// A one-shape serialized file holding `payload` (the shape's bytes before
/// compression), as Mitsuba writes it: format id, version 4, the zlib
/// stream, the shape's offset and the shape count.
fn serialized_file(payload: &[u8]) -> Vec<u8> {
    use std::io::Write;
    let mut out = vec![0x1C, 0x04, 4, 0];
    let mut z = flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::fast());
    z.write_all(payload).unwrap();
    out.extend(z.finish().unwrap());
    out.extend(0u64.to_le_bytes());
    out.extend(1u32.to_le_bytes());
    out
}

#[test]
fn mutated_serialized_meshes_load_or_fail_cleanly() {
    let dir = out_dir("fuzz", "serialized");
    let mut quad = serialized_writer::quad("quad", 0.0);
    quad.positions.push([0.5, 0.5, 1.0]);
    quad.normals.as_mut().unwrap().push([0.0, 0.0, 1.0]);
    quad.uvs.as_mut().unwrap().push([0.5, 0.5]);
    quad.colors.as_mut().unwrap().push([1.0, 0.0, 0.0]);
    quad.indices.push([0, 1, 4]);
    let file = serialized_writer::write(&[quad], 4, false);
    // The shape's bytes, for mutations that reach the parser through zlib.
    let mut payload = Vec::new();
    std::io::Read::read_to_end(
        &mut flate2::read::ZlibDecoder::new(&file[4..]),
        &mut payload,
    )
    .unwrap();
    assert_eq!(serialized_file(&payload)[..4], file[..4]);
    let render = tiny_scene(
        &dir,
        "serialized.xml",
        "<shape type=\"serialized\"><string name=\"filename\" value=\"case.serialized\"/></shape>",
    );
    // The file's bytes (header, dictionary, compressed stream) and the
    // shape's own bytes compressed again.
    fuzz(22, &file, &dir, "case.serialized", &render);
    fuzz_with(
        23,
        &payload,
        &dir,
        "case.serialized",
        serialized_file,
        render,
    );
}

#[test]
fn mutated_reradiation_matrices_load_or_fail_cleanly() {
    let dir = out_dir("fuzz", "matrix");
    let csv = std::fs::read(scenes().join("materials/highlighter-yellow.csv")).unwrap();
    let render = tiny_scene(
        &dir,
        "matrix.xml",
        "<shape type=\"sphere\"><bsdf type=\"fluorescent\"><string name=\"matrix\" value=\"case.csv\"/></bsdf></shape>",
    );
    fuzz(31, &csv, &dir, "case.csv", render);
}

#[test]
fn mutated_spectra_read_or_fail_cleanly() {
    let dir = out_dir("fuzz", "csv");
    let csv = std::fs::read(scenes().join("lamps/led-4000k.csv")).unwrap();
    fuzz(30, &csv, &dir, "case.csv", |p| {
        vec!["spectrum".into(), "--file".into(), s(p)]
    });
}

#[test]
fn mutated_images_display_or_fail_cleanly() {
    let dir = out_dir("fuzz", "exr");
    let exr = dir.join("seed.exr");
    let scene = scenes().join("cornell-box.xml");
    let (code, _, err) = common::scotopia(&[
        "render",
        scene.to_str().unwrap(),
        "--res",
        "8",
        "--spp",
        "1",
        "-o",
        exr.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let bytes = std::fs::read(&exr).unwrap();
    let png = dir.join("out.png");
    fuzz(40, &bytes, &dir, "case.exr", |p| {
        vec!["display".into(), s(p), "-o".into(), s(&png)]
    });
}

/// Checkpoints mutated as the other inputs are: every mutation that
/// changes a byte is refused (exit 1, naming the checkpoint), never
/// resumed; one that changes nothing resumes.
#[test]
fn mutated_checkpoints_are_refused() {
    let dir = out_dir("fuzz", "ckpt");
    // The scene is written by `tiny_scene`; its output here is case.exr.
    let _ = tiny_scene(&dir, "ckpt.xml", "<shape type=\"sphere\"/>");
    let (scene, out) = (s(&dir.join("ckpt.xml")), dir.join("case.exr"));
    let ckpt = dir.join("case.exr.ckpt");
    let run = |extra: &[&str]| {
        let mut a = vec!["render", &scene, "-o", s_ref(&out)];
        a.extend_from_slice(extra);
        a.into_iter().map(String::from).collect::<Vec<String>>()
    };
    let first = Command::new(env!("CARGO_BIN_EXE_scotopia"))
        .args(run(&["--spp", "1", "--checkpoint", "0"]))
        .output()
        .unwrap();
    assert!(
        first.status.success(),
        "{}",
        String::from_utf8_lossy(&first.stderr)
    );
    let good = std::fs::read(&ckpt).unwrap();
    let resume = run(&["--resume", "--spp", "3"]);
    let resume: Vec<&str> = resume.iter().map(String::as_str).collect();
    let mut rng = Rng(50);
    let mut failures = Vec::new();
    for case in 0..cases() {
        let bytes = mutate(&good, &mut rng);
        std::fs::write(&ckpt, &bytes).unwrap();
        let _ = std::fs::remove_file(&out);
        let result = run_clean(&resume, "case.exr.ckpt");
        let resumed = out.exists();
        let wrong = match result {
            Err(e) => Some(e),
            Ok(()) if resumed && bytes != good => Some("resumed from a damaged checkpoint".into()),
            Ok(()) => None,
        };
        if let Some(e) = wrong {
            let keep = dir.join(format!("failing-{case}.ckpt"));
            let _ = std::fs::write(&keep, &bytes);
            failures.push(format!("case {case} (kept as {}): {e}", keep.display()));
        }
    }
    assert!(
        failures.is_empty(),
        "{} failures:\n{}",
        failures.len(),
        failures.join("\n")
    );
}

/// A small EULUMDAT file: one rotationally symmetric plane, three γ angles.
fn small_ldt() -> Vec<u8> {
    let mut l: Vec<&str> = vec![
        "scotopia fuzz",
        "1",
        "1",
        "1",
        "0",
        "3",
        "90",
        "r1",
        "lamp",
        "L-1",
        "case.ldt",
        "2026-12-03",
        "100",
        "100",
        "50",
        "50",
        "0",
        "0",
        "0",
        "0",
        "0",
        "100",
        "80",
        "1",
        "0",
        "1",
        "1",
        "LED",
        "1000",
        "3000 K",
        "80",
        "10",
    ];
    l.extend(["0,5"; 10]);
    l.extend(["0", "0", "90", "180", "300", "100", "0"]);
    (l.join("\r\n") + "\r\n").into_bytes()
}

#[test]
fn mutated_photometric_files_load_or_fail_cleanly() {
    let dir = out_dir("fuzz", "luminaire");
    let ies = std::fs::read(scenes().join("lamps/street-type2.ies")).unwrap();
    for (seed, name, bytes) in [(50, "case.ies", ies), (51, "case.ldt", small_ldt())] {
        let lamp =
            format!("<emitter type=\"ies\"><string name=\"filename\" value=\"{name}\"/></emitter>");
        let render = tiny_scene(&dir, &format!("{name}.xml"), &lamp);
        fuzz(seed, &bytes, &dir, name, render);
    }
}

#[test]
fn mutated_points_files_measure_or_fail_cleanly() {
    let dir = out_dir("fuzz", "points");
    let scene = dir.join("lamp.xml");
    std::fs::write(
        &scene,
        r#"<scene version="3.0.0"><emitter type="point"><point name="position" x="0" y="2" z="0"/><spectrum name="intensity" value="400:1, 700:3"/></emitter></scene>"#,
    )
    .unwrap();
    let points = b"# a grid\nx,y,z,nx,ny,nz\n0,0,0,0,1,0\n1,0,0,0,1,0\n0,0,1,0,2.5,0\n\n-1,0.5,-1,0.1,1,0.1\n";
    let out = dir.join("out.csv");
    fuzz(52, points, &dir, "case.csv", |p| {
        [
            "measure",
            &s(&scene),
            "--points",
            &s(p),
            "--spp",
            "4",
            "-o",
            &s(&out),
        ]
        .map(String::from)
        .to_vec()
    });
}

/// The harness itself sees what it must: a panic message, an abort, a
/// death by a signal and an error that does not name its file.
#[test]
fn the_harness_catches_panics_signals_and_anonymous_errors() {
    let sh = |script: &str, about: &str| run_program("sh", &["-c", script], about);
    assert!(sh("exit 0", "x").is_ok());
    assert!(sh("echo 'x.xml: bad' >&2; exit 1", "x.xml").is_ok());
    assert!(sh("echo 'bad' >&2; exit 1", "x.xml").is_err());
    assert!(sh(
        "echo \"thread 'main' panicked at x.xml\" >&2; exit 1",
        "x.xml"
    )
    .is_err());
    assert!(sh("exit 101", "x").is_err());
    assert!(sh("kill -SEGV $$", "x").is_err());
}
