//! The temporary files outputs are written to before they are renamed over
//! their target (see `output_file`). A process killed while writing
//! (SIGKILL, the out-of-memory killer) leaves its temporary file behind;
//! the next write to the same path removes the ones whose process is gone.

use std::ffi::OsString;
use std::path::{Path, PathBuf};

/// The longest file name most file systems take (NAME_MAX on Linux, macOS).
const NAME_MAX: usize = 255;
/// `.tmp` and the longest process id (u32).
const SUFFIX_MAX: usize = 4 + 10;

/// The temporary file beside `path` for this process: `NAME.tmp<PID>`.
/// Stale ones of dead processes are removed first.
pub(crate) fn tmp_path(path: &Path) -> PathBuf {
    remove_stale(path);
    with_pid(path, std::process::id())
}

/// What temporaries of `path` start with: its file name, or, where the name
/// with `.tmp<PID>` would exceed NAME_MAX, its first bytes and a hash of
/// the whole name (so that two long names differing at their ends do not
/// share temporaries).
fn stem(path: &Path) -> Vec<u8> {
    let name = path.file_name().map(os_bytes).unwrap_or_default();
    if name.len() + SUFFIX_MAX <= NAME_MAX {
        return name;
    }
    let hash = format!("~{:016x}", xxhash_rust::xxh3::xxh3_64(&name));
    let mut stem = name[..NAME_MAX - SUFFIX_MAX - hash.len()].to_vec();
    stem.extend_from_slice(hash.as_bytes());
    stem
}

fn with_pid(path: &Path, pid: u32) -> PathBuf {
    let mut name = stem(path);
    name.extend_from_slice(format!(".tmp{pid}").as_bytes());
    path.with_file_name(from_bytes(name))
}

#[cfg(unix)]
fn os_bytes(name: &std::ffi::OsStr) -> Vec<u8> {
    std::os::unix::ffi::OsStrExt::as_bytes(name).to_vec()
}

#[cfg(unix)]
fn from_bytes(bytes: Vec<u8>) -> OsString {
    std::os::unix::ffi::OsStringExt::from_vec(bytes)
}

// Elsewhere names are cut as text (a character at a time is never split).
#[cfg(not(unix))]
fn os_bytes(name: &std::ffi::OsStr) -> Vec<u8> {
    name.to_string_lossy().into_owned().into_bytes()
}

#[cfg(not(unix))]
fn from_bytes(bytes: Vec<u8>) -> OsString {
    String::from_utf8_lossy(&bytes).into_owned().into()
}

/// Removes `NAME.tmp<PID>` files beside `path` whose process no longer
/// runs. Only where /proc tells which processes run (Linux); elsewhere
/// nothing is removed. Failures are ignored: this is housekeeping.
pub(crate) fn remove_stale(path: &Path) {
    let proc = Path::new("/proc");
    if !proc.join("self").exists() {
        return;
    }
    let Some(dir) = path.parent() else {
        return;
    };
    let dir = if dir.as_os_str().is_empty() {
        Path::new(".")
    } else {
        dir
    };
    let mut prefix = stem(path);
    prefix.extend_from_slice(b".tmp");
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let file = os_bytes(&entry.file_name());
        let Some(pid) = file.strip_prefix(&prefix[..]) else {
            continue;
        };
        let Some(pid) = std::str::from_utf8(pid)
            .ok()
            .filter(|p| p.bytes().all(|b| b.is_ascii_digit()))
            .and_then(|p| p.parse::<u32>().ok())
        else {
            continue;
        };
        // Only plain files: never a folder or a device someone named so.
        let plain = entry.file_type().is_ok_and(|t| t.is_file());
        if plain && pid != std::process::id() && !proc.join(pid.to_string()).exists() {
            let _ = std::fs::remove_file(entry.path());
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A PID above the kernel's maximum (2^22): its process never runs.
    pub(crate) const DEAD: u32 = 4_194_305;

    #[test]
    fn stale_temporaries_of_dead_processes_are_removed() {
        let dir = std::env::temp_dir().join(format!("scotopia-tmp-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let out = dir.join("render.exr");
        // PID 1 runs.
        let (alive, dead) = (with_pid(&out, 1), with_pid(&out, DEAD));
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

    #[test]
    fn temporaries_of_long_names_stay_within_name_max() {
        let dir = std::env::temp_dir().join(format!("scotopia-tmp-long-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        // 247 bytes, with a two-byte character where the cut falls.
        let name = |end: &str| format!("a{}{end}.exr", "é".repeat(120));
        let (a, b) = (dir.join(name("ab")), dir.join(name("cd")));
        assert_eq!(a.file_name().unwrap().len(), 247);
        let (ta, tb) = (with_pid(&a, u32::MAX), with_pid(&b, u32::MAX));
        assert!(ta.file_name().unwrap().len() <= NAME_MAX);
        assert_ne!(ta, tb, "two long names share a temporary");
        // The file system takes it, and a dead process's one is removed.
        let dead = with_pid(&a, DEAD);
        std::fs::write(&dead, b"partial").unwrap();
        remove_stale(&a);
        assert!(!dead.exists());
        // Short names keep the plain form.
        let short = dir.join("x.png");
        assert_eq!(with_pid(&short, 7), dir.join("x.png.tmp7"));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
