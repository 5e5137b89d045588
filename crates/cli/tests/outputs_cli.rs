//! Outputs that never destroy what they should not (issue 38): an output
//! that is an input or named twice is refused, FIFOs and character devices
//! are written through, symbolic links followed, long names written,
//! temporaries of dead processes removed; checkpoints that are damaged,
//! of an edited scene or not plain files are refused.

use std::os::unix::fs::FileTypeExt;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

mod common;

/// A PID above the kernel's maximum (2^22): its process never runs.
const DEAD: &str = "4194305";

/// A fresh folder with a 2 × 1 scene whose reflectance is a spectrum file
/// (`refl.spd`) and which includes `world.xml` (its light).
fn setup(name: &str) -> PathBuf {
    let dir = common::out_dir("outputs", name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(
        dir.join("s.xml"),
        r#"<scene version="3.0.0"><sensor type="perspective"><film type="hdrfilm"><integer name="width" value="2"/><integer name="height" value="1"/></film><sampler type="independent"><integer name="sample_count" value="2"/></sampler></sensor><shape type="sphere"><float name="radius" value="0.5"/><transform name="to_world"><translate z="3"/></transform><bsdf type="diffuse"><spectrum name="reflectance" filename="refl.spd"/></bsdf></shape><include filename="world.xml"/></scene>"#,
    )
    .unwrap();
    std::fs::write(
        dir.join("world.xml"),
        r#"<scene version="3.0.0"><emitter type="constant"/></scene>"#,
    )
    .unwrap();
    std::fs::write(dir.join("refl.spd"), "400 0.5\n700 0.6\n").unwrap();
    std::fs::write(dir.join("points.csv"), "0,0,2,0,0,-1\n").unwrap();
    dir
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// Runs `scotopia` in `dir` with `args`: (exit code, stderr).
fn run_in(dir: &Path, args: &[&str]) -> (i32, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_scotopia"))
        .current_dir(dir)
        .args(args)
        .output()
        .unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// Runs `scotopia` in `dir`, killed if it has not ended after a minute
/// (a watchdog for what must not block: the test fails instead of hanging).
fn run_bounded(dir: &Path, args: &[&str]) -> (i32, String) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_scotopia"))
        .current_dir(dir)
        .args(args)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let start = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        if start.elapsed() > Duration::from_secs(60) {
            let _ = child.kill();
            panic!("{args:?}: blocked (killed after 60 s)");
        }
        std::thread::sleep(Duration::from_millis(10));
    };
    let mut err = String::new();
    std::io::Read::read_to_string(&mut child.stderr.take().unwrap(), &mut err).unwrap();
    (status.code().unwrap_or(-1), err)
}

#[test]
fn an_output_that_is_an_input_is_refused_and_the_input_kept() {
    let dir = setup("same");
    let (code, err) = run_in(&dir, &["render", "s.xml", "-o", "a.exr"]);
    assert_eq!(code, 0, "{err}");
    let kept: Vec<(&str, Vec<u8>)> = ["s.xml", "refl.spd", "world.xml", "points.csv", "a.exr"]
        .iter()
        .map(|f| (*f, std::fs::read(dir.join(f)).unwrap()))
        .collect();
    let cases: &[(&[&str], &[&str])] = &[
        (
            &["render", "s.xml", "-o", "s.xml"],
            &["-o s.xml", "the scene"],
        ),
        (
            &["render", "s.xml", "-o", "./refl.spd"],
            &["refl.spd", "a file the scene reads"],
        ),
        (
            &["render", "s.xml", "-o", "b.exr", "--preview", "world.xml"],
            &["--preview", "world.xml"],
        ),
        (
            &["render", "s.xml", "-o", "b.exr", "--preview", "./b.exr"],
            &["-o b.exr", "--preview ./b.exr", "same file"],
        ),
        (
            &[
                "render",
                "s.xml",
                "-o",
                "b.exr",
                "--spectral",
                "c.exr",
                "--display",
                "c.exr",
            ],
            &["--spectral", "--display", "same file"],
        ),
        (
            &[
                "render",
                "s.xml",
                "-o",
                "b.exr",
                "--checkpoint",
                "1",
                "--preview",
                "b.exr.ckpt",
            ],
            &["--preview", "the checkpoint"],
        ),
        (
            &["display", "a.exr", "-o", "a.exr"],
            &["-o a.exr", "the input"],
        ),
        (
            &["display", "a.exr", "-o", "x.png", "--compare", "x.png"],
            &["-o x.png", "--compare x.png"],
        ),
        (
            &[
                "measure",
                "s.xml",
                "--points",
                "points.csv",
                "-o",
                "points.csv",
            ],
            &["-o points.csv", "--points"],
        ),
        (
            &["measure", "s.xml", "--points", "points.csv", "-o", "s.xml"],
            &["-o s.xml", "the scene"],
        ),
        (
            &[
                "measure",
                "s.xml",
                "--points",
                "points.csv",
                "-o",
                "refl.spd",
            ],
            &["-o refl.spd", "a file the scene reads"],
        ),
        (
            &["view", "a.exr", "-o", "./a.exr", "--port", "0"],
            &["-o ./a.exr", "the input (a.exr)"],
        ),
        (
            &["spectrum", "--file", "refl.spd", "--plot", "./refl.spd"],
            &["--plot ./refl.spd", "the --file spectrum (refl.spd)"],
        ),
    ];
    for (args, words) in cases {
        let (code, err) = run_in(&dir, args);
        assert_eq!(code, 1, "{args:?}: {err}");
        for w in *words {
            assert!(err.contains(w), "{args:?}: {w:?} not in {err}");
        }
    }
    // A hard link to the scene is the scene too.
    std::fs::hard_link(dir.join("s.xml"), dir.join("hard.xml")).unwrap();
    let (code, err) = run_in(&dir, &["render", "s.xml", "-o", "hard.xml"]);
    assert_eq!(code, 1, "{err}");
    for (f, bytes) in kept {
        assert_eq!(std::fs::read(dir.join(f)).unwrap(), bytes, "{f} changed");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_symlinked_output_is_written_through_to_its_target() {
    let dir = setup("link");
    std::fs::create_dir_all(dir.join("real")).unwrap();
    std::fs::write(dir.join("real/a.exr"), b"old").unwrap();
    std::os::unix::fs::symlink("real/a.exr", dir.join("a.exr")).unwrap();
    let (code, err) = run_in(&dir, &["render", "s.xml", "-o", "a.exr"]);
    assert_eq!(code, 0, "{err}");
    assert!(std::fs::symlink_metadata(dir.join("a.exr"))
        .unwrap()
        .file_type()
        .is_symlink());
    let image = scotopia_image::read_exr(&dir.join("real/a.exr")).unwrap();
    assert_eq!((image.width, image.height), (2, 1));
    assert_eq!(std::fs::read_dir(dir.join("real")).unwrap().count(), 1);
    std::fs::remove_dir_all(&dir).unwrap();
}

fn mkfifo(path: &Path) {
    assert!(Command::new("mkfifo").arg(path).status().unwrap().success());
}

/// Reads `fifo` whole on another thread.
fn drain(fifo: &Path) -> std::thread::JoinHandle<Vec<u8>> {
    let fifo = fifo.to_path_buf();
    std::thread::spawn(move || std::fs::read(fifo).unwrap())
}

#[test]
fn fifos_are_written_through_and_stay_fifos() {
    let dir = setup("fifo");
    let (exr, png) = (dir.join("pipe.exr"), dir.join("pipe.png"));
    mkfifo(&exr);
    mkfifo(&png);
    let (e, p) = (drain(&exr), drain(&png));
    let (code, err) = run_bounded(
        &dir,
        &["render", "s.xml", "-o", "pipe.exr", "--preview", "pipe.png"],
    );
    assert_eq!(code, 0, "{err}");
    // What came through the FIFOs is a whole EXR and PNG.
    let (e, p) = (e.join().unwrap(), p.join().unwrap());
    std::fs::write(dir.join("got.exr"), &e).unwrap();
    let image = scotopia_image::read_exr(&dir.join("got.exr")).unwrap();
    assert_eq!((image.width, image.height), (2, 1));
    assert_eq!(&p[1..4], b"PNG");
    for f in [&exr, &png] {
        let t = std::fs::symlink_metadata(f).unwrap().file_type();
        assert!(t.is_fifo(), "{} was replaced", f.display());
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

fn is_root() -> bool {
    std::fs::read_to_string("/proc/self/status").is_ok_and(|s| {
        s.lines()
            .find(|l| l.starts_with("Uid:"))
            .and_then(|l| l.split_whitespace().nth(1))
            == Some("0")
    })
}

/// `-o` a character device: a private one like /dev/null where the test
/// can make one (root); /dev/null itself only when not root, where nothing
/// could replace it anyway.
#[test]
fn a_character_device_output_is_written_through_and_stays_a_device() {
    let dir = setup("device");
    let node = dir.join("null");
    let made = Command::new("mknod")
        .arg(&node)
        .args(["c", "1", "3"])
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|s| s.success());
    let device = match made {
        true => node,
        false if !is_root() => PathBuf::from("/dev/null"),
        false => return eprintln!("root without mknod: left to the FIFO test"),
    };
    let d = s(&device);
    let (code, err) = run_in(&dir, &["render", "s.xml", "-o", d, "--preview", d]);
    assert_eq!(code, 0, "{err}");
    let (code, err) = run_in(
        &dir,
        &["measure", "s.xml", "--points", "points.csv", "-o", d],
    );
    assert_eq!(code, 0, "{err}");
    let t = std::fs::symlink_metadata(&device).unwrap().file_type();
    assert!(t.is_char_device(), "{d} was replaced");
    // A checkpoint beside a device would be a stray file among devices.
    let (code, err) = run_in(&dir, &["render", "s.xml", "-o", d, "--checkpoint", "1"]);
    assert_eq!(code, 1, "{err}");
    assert!(
        err.contains("a character device") && err.contains("give -o a file"),
        "{err}"
    );
    assert!(
        !Path::new(&format!("{d}.ckpt")).exists(),
        "{d}.ckpt was made"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn long_output_names_are_written() {
    let dir = setup("long");
    // 250 bytes: with `.tmp<PID>` the plain temporary name would not fit.
    let name = format!("{}.exr", "n".repeat(246));
    let (code, err) = run_in(&dir, &["render", "s.xml", "-o", &name, "--checkpoint", "0"]);
    assert_eq!(code, 0, "{err}");
    // And the checkpoint's, 255 bytes: NAME_MAX.
    assert!(dir.join(&name).exists());
    assert!(dir.join(format!("{name}.ckpt")).exists());
    let mut names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .collect();
    names.sort();
    assert!(names.iter().all(|n| !n.contains(".tmp")), "{names:?}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn stale_temporaries_of_dead_processes_are_removed_for_every_output() {
    let dir = setup("stale");
    let stale = [
        "a.exr",
        "a.png",
        "a.exr.ckpt",
        "spectral.exr",
        "shown.png",
        "out.csv",
    ]
    .map(|f| dir.join(format!("{f}.tmp{DEAD}")));
    for f in &stale {
        std::fs::write(f, b"partial").unwrap();
    }
    let (code, err) = run_in(
        &dir,
        &[
            "render",
            "s.xml",
            "-o",
            "a.exr",
            "--preview",
            "a.png",
            "--spectral",
            "spectral.exr",
            "--display",
            "shown.png",
            "--checkpoint",
            "0",
        ],
    );
    assert_eq!(code, 0, "{err}");
    let (code, err) = run_in(
        &dir,
        &[
            "measure",
            "s.xml",
            "--points",
            "points.csv",
            "-o",
            "out.csv",
        ],
    );
    assert_eq!(code, 0, "{err}");
    for f in &stale {
        assert!(!f.exists(), "{} stays", f.display());
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Every byte of a small checkpoint flipped, and every shorter length:
/// each refused (exit 1, naming the checkpoint), none resumed.
#[test]
fn every_flipped_byte_and_truncation_of_a_checkpoint_is_refused() {
    let dir = setup("flip");
    let (code, err) = run_in(
        &dir,
        &["render", "s.xml", "-o", "a.exr", "--checkpoint", "0"],
    );
    assert_eq!(code, 0, "{err}");
    let good = std::fs::read(dir.join("a.exr.ckpt")).unwrap();
    assert!(good.len() < 400, "{} bytes: not small", good.len());
    let mut cases: Vec<(String, Vec<u8>)> = (0..good.len())
        .map(|at| {
            let mut b = good.clone();
            b[at] ^= 0xff;
            (format!("byte {at} flipped"), b)
        })
        .collect();
    cases.extend((0..good.len()).map(|n| (format!("cut to {n} bytes"), good[..n].to_vec())));
    // Two workers, each in its own folder (the checkpoint sits beside -o).
    let failures: Vec<String> = std::thread::scope(|scope| {
        let workers: Vec<_> = cases
            .chunks(cases.len().div_ceil(2))
            .enumerate()
            .map(|(w, chunk)| {
                let (dir, work) = (&dir, dir.join(format!("w{w}")));
                scope.spawn(move || {
                    std::fs::create_dir_all(&work).unwrap();
                    let out = work.join("a.exr");
                    let mut failed = Vec::new();
                    for (what, bytes) in chunk {
                        std::fs::write(work.join("a.exr.ckpt"), bytes).unwrap();
                        let args = ["render", "s.xml", "-o", s(&out), "--resume", "--spp", "4"];
                        let (code, err) = run_in(dir, &args);
                        if code != 1 || !err.contains("a.exr.ckpt") || err.contains("panicked") {
                            failed.push(format!("{what}: exit {code}: {err}"));
                        }
                    }
                    failed
                })
            })
            .collect();
        workers
            .into_iter()
            .flat_map(|w| w.join().unwrap())
            .collect()
    });
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    // The checkpoint unharmed resumes.
    std::fs::write(dir.join("a.exr.ckpt"), &good).unwrap();
    let (code, err) = run_in(
        &dir,
        &["render", "s.xml", "-o", "a.exr", "--resume", "--spp", "4"],
    );
    assert_eq!(code, 0, "{err}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn an_edited_file_of_the_scene_refuses_to_resume_naming_it() {
    let dir = setup("asset");
    let resume = ["render", "s.xml", "-o", "a.exr", "--resume", "--spp", "4"];
    for (file, edit) in [
        ("refl.spd", "400 0.5\n700 0.7\n"),
        (
            "world.xml",
            r#"<scene version="3.0.0"><emitter type="constant"><rgb name="radiance" value="2"/></emitter></scene>"#,
        ),
    ] {
        let (code, err) = run_in(
            &dir,
            &["render", "s.xml", "-o", "a.exr", "--checkpoint", "0"],
        );
        assert_eq!(code, 0, "{err}");
        let before = std::fs::read(dir.join(file)).unwrap();
        std::fs::write(dir.join(file), edit).unwrap();
        let (code, err) = run_in(&dir, &resume);
        assert_eq!(code, 1, "{file}: {err}");
        assert!(
            err.contains("a.exr.ckpt") && err.contains(file) && err.contains("changed"),
            "{file}: {err}"
        );
        // Restored, it resumes.
        std::fs::write(dir.join(file), before).unwrap();
        let (code, err) = run_in(&dir, &resume);
        assert_eq!(code, 0, "{file}: {err}");
        assert!(err.contains("resuming from"), "{err}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_fifo_as_checkpoint_is_an_error_without_blocking() {
    let dir = setup("ckpt-fifo");
    mkfifo(&dir.join("a.exr.ckpt"));
    // No one ever opens the other end: an open would wait forever.
    for extra in [&["--resume"][..], &["--checkpoint", "0"][..]] {
        let mut args = vec!["render", "s.xml", "-o", "a.exr"];
        args.extend_from_slice(extra);
        let (code, err) = run_bounded(&dir, &args);
        assert_eq!(code, 1, "{extra:?}: {err}");
        assert!(err.contains("a.exr.ckpt") && err.contains("FIFO"), "{err}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_checkpoint_of_the_old_format_is_refused_saying_what_to_do() {
    let dir = setup("old");
    let (code, err) = run_in(
        &dir,
        &["render", "s.xml", "-o", "a.exr", "--checkpoint", "0"],
    );
    assert_eq!(code, 0, "{err}");
    let mut bytes = std::fs::read(dir.join("a.exr.ckpt")).unwrap();
    bytes[8..12].copy_from_slice(&1u32.to_le_bytes());
    std::fs::write(dir.join("a.exr.ckpt"), &bytes).unwrap();
    let (code, err) = run_in(&dir, &["render", "s.xml", "-o", "a.exr", "--resume"]);
    assert_eq!(code, 1, "{err}");
    assert!(
        err.contains("version 1") && err.contains("delete it"),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_radiance_picture_holds_the_renders_luminance_and_view() {
    // --radiance writes Ward's RGBE in Radiance's primaries and units
    // (179 lm/W): its luminance, 179·(0.265R + 0.670G + 0.065B), is the
    // EXR's Y within RGBE's 8-bit mantissa.
    let dir = common::out_dir("outputs", "radiance");
    let (exr, hdr) = (dir.join("street.exr"), dir.join("street.hdr"));
    let s = |p: &std::path::Path| p.to_str().unwrap().to_string();
    let scene = common::scenes().join("night-street.xml");
    let (code, _, err) = common::scotopia(&[
        "render",
        &s(&scene),
        "--res",
        "40x24",
        "--spp",
        "4",
        "-o",
        &s(&exr),
        "--radiance",
        &s(&hdr),
    ]);
    assert_eq!(code, 0, "{err}");
    let bytes = std::fs::read(&hdr).unwrap();
    let end = bytes.windows(2).position(|w| w == b"\n\n").unwrap() + 2;
    let head = String::from_utf8_lossy(&bytes[..end]);
    assert!(head.starts_with("#?RADIANCE\n") && head.contains("FORMAT=32-bit_rle_rgbe\n"));
    assert!(head.contains("VIEW= -vtv -vh 60"), "{head}");
    let rest = &bytes[end..];
    let size = b"-Y 24 +X 40\n";
    assert!(rest.starts_with(size), "{head}");
    let px = &rest[size.len()..];
    assert_eq!(px.len(), 40 * 24 * 4);
    let film = scotopia_image::read_xyzv(&exr, Default::default()).unwrap();
    for (i, p) in px.chunks(4).enumerate() {
        // Radiance's reader: (m + 0.5)·2^(e − 136).
        let f = |m: u8| {
            if p[3] == 0 {
                0.0
            } else {
                (f64::from(m) + 0.5) * 2f64.powi(i32::from(p[3]) - 136)
            }
        };
        let l = 179.0 * (0.265 * f(p[0]) + 0.670 * f(p[1]) + 0.065 * f(p[2]));
        let y = f64::from(film.pixels[i][1]);
        assert!(
            (l - y).abs() <= 0.02 * y + 1e-6,
            "pixel {i}: {l} against {y}"
        );
    }
}
