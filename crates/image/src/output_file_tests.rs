use super::*;

use std::io::Read;
use std::os::unix::fs::FileTypeExt;
use std::process::Command;

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("scotopia-out-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn mkfifo(path: &Path) {
    let ok = Command::new("mkfifo").arg(path).status().unwrap().success();
    assert!(ok, "mkfifo {}", path.display());
}

/// The folder's entries by name (to see that no temporary is left).
fn names(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

#[test]
fn a_fifo_is_written_through_and_stays_a_fifo() {
    let dir = scratch("fifo");
    let fifo = dir.join("pipe.png");
    mkfifo(&fifo);
    let reader = {
        let fifo = fifo.clone();
        std::thread::spawn(move || {
            let mut got = Vec::new();
            File::open(&fifo).unwrap().read_to_end(&mut got).unwrap();
            got
        })
    };
    let bytes: Vec<u8> = (0..100_000u32).map(|i| (i % 251) as u8).collect();
    write_atomic(&fifo, &bytes).unwrap();
    assert_eq!(reader.join().unwrap(), bytes);
    let t = std::fs::symlink_metadata(&fifo).unwrap().file_type();
    assert!(t.is_fifo(), "the FIFO was replaced");
    assert_eq!(names(&dir), ["pipe.png"]);
    // A checkpoint must be a file: a FIFO is an error, found before any
    // open (which would wait for a reader that never comes).
    let e = write_output(&fifo, OutputOptions::CHECKPOINT, |o| o.write_all(b"x")).unwrap_err();
    assert!(e.to_string().contains("FIFO"), "{e}");
    std::fs::remove_dir_all(&dir).unwrap();
}

fn uid_is_root() -> bool {
    std::fs::read_to_string("/proc/self/status").is_ok_and(|s| {
        s.lines()
            .find(|l| l.starts_with("Uid:"))
            .and_then(|l| l.split_whitespace().nth(1))
            == Some("0")
    })
}

/// A character device written through, never replaced: a private node
/// like /dev/null where the test may make one (root), else /dev/null
/// itself — only when not root, where renaming over it is refused anyway.
#[test]
fn a_character_device_is_written_through_and_stays_a_device() {
    let dir = scratch("device");
    let node = dir.join("null");
    let made = Command::new("mknod")
        .arg(&node)
        .args(["c", "1", "3"])
        .stderr(std::process::Stdio::null())
        .status()
        .is_ok_and(|s| s.success());
    let device = if made {
        node
    } else if !uid_is_root() {
        PathBuf::from("/dev/null")
    } else {
        eprintln!("root without mknod: the device case is left to the FIFO test");
        return;
    };
    write_atomic(&device, b"discarded").unwrap();
    let exr = |o: &mut OutputFile| {
        assert!(!o.seekable());
        o.write_all(&[1; 70_000])
    };
    write_output(&device, OutputOptions::OUTPUT, exr).unwrap();
    let t = std::fs::symlink_metadata(&device).unwrap().file_type();
    assert!(t.is_char_device(), "{} was replaced", device.display());
    let e = write_output(&device, OutputOptions::CHECKPOINT, |_| Ok(())).unwrap_err();
    assert!(e.to_string().contains("character device"), "{e}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_symlink_is_followed_and_its_target_replaced() {
    let dir = scratch("link");
    let real = dir.join("real");
    std::fs::create_dir_all(&real).unwrap();
    std::fs::write(real.join("a.png"), b"old").unwrap();
    // A relative link from another folder, and a link to a link.
    std::os::unix::fs::symlink("real/a.png", dir.join("a.png")).unwrap();
    std::os::unix::fs::symlink("a.png", dir.join("b.png")).unwrap();
    write_atomic(&dir.join("b.png"), b"new").unwrap();
    assert_eq!(std::fs::read(real.join("a.png")).unwrap(), b"new");
    for link in ["a.png", "b.png"] {
        let m = std::fs::symlink_metadata(dir.join(link)).unwrap();
        assert!(m.file_type().is_symlink(), "{link} was replaced");
    }
    assert_eq!(names(&dir), ["a.png", "b.png", "real"]);
    assert_eq!(names(&real), ["a.png"]);
    // A dangling link makes its target.
    std::os::unix::fs::symlink("real/c.png", dir.join("c.png")).unwrap();
    write_atomic(&dir.join("c.png"), b"made").unwrap();
    assert_eq!(std::fs::read(real.join("c.png")).unwrap(), b"made");
    // A loop is an error, not a hang.
    std::os::unix::fs::symlink("d.png", dir.join("d.png")).unwrap();
    let e = write_atomic(&dir.join("d.png"), b"x").unwrap_err();
    assert!(e.to_string().contains("symbolic links"), "{e}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn folders_are_refused_and_failed_writes_leave_the_old_file() {
    let dir = scratch("refuse");
    let e = write_atomic(&dir, b"x").unwrap_err();
    assert!(e.to_string().contains("folder"), "{e}");
    let out = dir.join("t.csv");
    std::fs::write(&out, b"old").unwrap();
    let failed = write_output(&out, OutputOptions::OUTPUT, |o| {
        o.write_all(b"half")?;
        Err(io::Error::other("disk full"))
    });
    assert!(failed.is_err());
    assert_eq!(std::fs::read(&out).unwrap(), b"old");
    assert_eq!(names(&dir), ["t.csv"]);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn outputs_that_are_inputs_or_twice_the_same_file_are_refused() {
    let dir = scratch("same");
    let scene = dir.join("scene.xml");
    std::fs::write(&scene, b"<scene/>").unwrap();
    std::fs::hard_link(&scene, dir.join("hard.xml")).unwrap();
    std::os::unix::fs::symlink("scene.xml", dir.join("soft.xml")).unwrap();
    let inputs = [("the scene", scene.as_path())];
    for out in ["scene.xml", "hard.xml", "soft.xml", "sub/../scene.xml"] {
        std::fs::create_dir_all(dir.join("sub")).unwrap();
        let o = dir.join(out);
        let e = check_outputs(&inputs, &[("-o", &o)]).unwrap_err();
        assert!(
            e.contains("-o") && e.contains(out) && e.contains("the scene"),
            "{e}"
        );
    }
    // Two outputs that do not exist yet, named two ways.
    let (a, b) = (dir.join("a.png"), dir.join("sub/../a.png"));
    let e = check_outputs(
        &inputs,
        &[
            ("-o", &dir.join("x.exr")),
            ("--preview", &a),
            ("--display", &b),
        ],
    )
    .unwrap_err();
    assert!(e.contains("--preview") && e.contains("--display"), "{e}");
    assert!(check_outputs(&inputs, &[("-o", &dir.join("x.exr")), ("--preview", &a)]).is_ok());
    // /dev/null twice destroys nothing.
    let null = Path::new("/dev/null");
    assert!(check_outputs(&inputs, &[("-o", null), ("--preview", null)]).is_ok());
    std::fs::remove_dir_all(&dir).unwrap();
}
