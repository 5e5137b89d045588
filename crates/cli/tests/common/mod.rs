//! What the CLI tests share: running the binary and a scratch folder.

#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::Command;

/// Runs `scotopia` with `args`: (exit code, stdout, stderr).
pub fn scotopia(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_scotopia"))
        .args(args)
        .output()
        .expect("run scotopia");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// A fresh folder for one test's files, unique to this run.
pub fn out_dir(suite: &str, name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("scotopia-{suite}-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// The bundled scenes.
pub fn scenes() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes")
}
