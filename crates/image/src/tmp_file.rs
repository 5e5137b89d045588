//! Outputs are written to a temporary file beside the target and renamed
//! over it when complete, so a reader never sees half an image. A process
//! killed while writing (SIGKILL, the out-of-memory killer) leaves its
//! temporary file behind; the next write to the same path removes the
//! ones whose process is gone.

use std::path::{Path, PathBuf};

/// The temporary file beside `path` for this process: `NAME.tmp<PID>`.
/// Stale ones of dead processes are removed first.
pub(crate) fn tmp_path(path: &Path) -> PathBuf {
    remove_stale(path);
    with_pid(path, std::process::id())
}

/// Writes `bytes` to `path` through a temporary file renamed over it.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let tmp = tmp_path(path);
    std::fs::write(&tmp, bytes)
        .and_then(|_| std::fs::rename(&tmp, path))
        .inspect_err(|_| {
            let _ = std::fs::remove_file(&tmp);
        })
}

fn with_pid(path: &Path, pid: u32) -> PathBuf {
    let mut name = path
        .file_name()
        .map(|n| n.to_os_string())
        .unwrap_or_default();
    name.push(format!(".tmp{pid}"));
    path.with_file_name(name)
}

/// Removes `NAME.tmp<PID>` files beside `path` whose process no longer
/// runs. Only where /proc tells which processes run (Linux); elsewhere
/// nothing is removed. Failures are ignored: this is housekeeping.
fn remove_stale(path: &Path) {
    let proc = Path::new("/proc");
    if !proc.join("self").exists() {
        return;
    }
    let (Some(dir), Some(name)) = (path.parent(), path.file_name()) else {
        return;
    };
    let dir = if dir.as_os_str().is_empty() {
        Path::new(".")
    } else {
        dir
    };
    let prefix = format!("{}.tmp", name.to_string_lossy());
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let file = entry.file_name();
        let file = file.to_string_lossy();
        let Some(pid) = file.strip_prefix(&prefix) else {
            continue;
        };
        let Ok(pid) = pid.parse::<u32>() else {
            continue;
        };
        if pid != std::process::id() && !proc.join(pid.to_string()).exists() {
            let _ = std::fs::remove_file(entry.path());
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stale_temporaries_of_dead_processes_are_removed() {
        let dir = std::env::temp_dir().join(format!("scotopia-tmp-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let out = dir.join("render.exr");
        // PID 1 runs; a PID above the kernel's maximum (2^22) never does.
        let (alive, dead) = (with_pid(&out, 1), with_pid(&out, 4_194_305));
        let other = dir.join("other.exr.tmp4194305");
        for f in [&alive, &dead, &other] {
            std::fs::write(f, b"partial").unwrap();
        }
        let mine = tmp_path(&out);
        assert_eq!(mine, with_pid(&out, std::process::id()));
        assert!(!dead.exists(), "a dead process's temporary file stays");
        assert!(alive.exists() && other.exists());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
