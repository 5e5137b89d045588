//! Writing an output without destroying what it should not.
//!
//! A file is written to a temporary beside it and renamed over it when
//! complete, so a reader never sees half an image and a failed write
//! leaves the old file whole. A symbolic link is followed: the temporary
//! goes beside the link's target and is renamed onto the target, so the
//! link stays and points at the new file. A character device (`/dev/null`)
//! or a FIFO is written through in place — renaming over it would replace
//! the device node with a plain file. Anything else (a folder, a block
//! device, a socket) is an error.

use std::fs::{File, OpenOptions};
use std::io::{self, BufWriter, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};

use crate::tmp_file::tmp_path;

/// How an output is written.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct OutputOptions {
    /// Flush the file to the disk before renaming it (checkpoints: the
    /// previous one must stay whole until the new one is).
    pub durable: bool,
    /// Write through to a character device or FIFO; if false, one is an
    /// error (a checkpoint must be a file that can be read back).
    pub devices: bool,
}

impl OutputOptions {
    /// Images and tables: devices and FIFOs written through.
    pub const OUTPUT: Self = Self {
        durable: false,
        devices: true,
    };
    /// Checkpoints: plain files only, synced before the rename.
    pub const CHECKPOINT: Self = Self {
        durable: true,
        devices: false,
    };
}

/// Where an output's bytes go: a temporary file (seekable) or a device or
/// FIFO written in place (not seekable: a FIFO refuses seeks).
pub struct OutputFile {
    inner: BufWriter<File>,
    seekable: bool,
}

impl OutputFile {
    /// Whether seeks work (a temporary file); encoders that must seek
    /// encode to memory first otherwise.
    pub fn seekable(&self) -> bool {
        self.seekable
    }
}

impl Write for OutputFile {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        self.inner.write(buf)
    }

    fn flush(&mut self) -> io::Result<()> {
        self.inner.flush()
    }
}

impl Seek for OutputFile {
    fn seek(&mut self, to: SeekFrom) -> io::Result<u64> {
        if !self.seekable {
            return Err(io::Error::new(
                io::ErrorKind::Unsupported,
                "a device or FIFO cannot seek",
            ));
        }
        self.inner.seek(to)
    }
}

/// Writes `path` with `fill` (see the module's note for what happens to
/// links, devices and FIFOs).
pub fn write_output(
    path: &Path,
    options: OutputOptions,
    fill: impl FnOnce(&mut OutputFile) -> io::Result<()>,
) -> io::Result<()> {
    let target = follow_links(path)?;
    match std::fs::metadata(&target) {
        Ok(m) if m.is_file() => replace(&target, options, fill),
        Ok(m) if options.devices && is_stream(&m) => write_through(&target, fill),
        Ok(m) => Err(not_a_file(&m)),
        Err(e) if e.kind() == io::ErrorKind::NotFound => replace(&target, options, fill),
        Err(e) => Err(e),
    }
}

/// Writes `bytes` to `path` as [`write_output`] does for images.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> io::Result<()> {
    write_output(path, OutputOptions::OUTPUT, |out| out.write_all(bytes))
}

fn replace(
    target: &Path,
    options: OutputOptions,
    fill: impl FnOnce(&mut OutputFile) -> io::Result<()>,
) -> io::Result<()> {
    let tmp = tmp_path(target);
    let result = (|| {
        let mut out = OutputFile {
            inner: BufWriter::new(create_new(&tmp)?),
            seekable: true,
        };
        fill(&mut out)?;
        let file = out.inner.into_inner().map_err(|e| e.into_error())?;
        if options.durable {
            file.sync_all()?;
        }
        std::fs::rename(&tmp, target)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}

/// A new file at `tmp`; never opened through a link someone left there.
/// A leftover of this process id (an earlier process's, killed) is removed.
fn create_new(tmp: &Path) -> io::Result<File> {
    let open = || OpenOptions::new().write(true).create_new(true).open(tmp);
    match open() {
        Err(e) if e.kind() == io::ErrorKind::AlreadyExists => {
            std::fs::remove_file(tmp)?;
            open()
        }
        other => other,
    }
}

fn write_through(
    target: &Path,
    fill: impl FnOnce(&mut OutputFile) -> io::Result<()>,
) -> io::Result<()> {
    // Opening a FIFO waits for its reader, as a shell's `>` does.
    let file = OpenOptions::new().write(true).open(target)?;
    // Replaced by a plain file since it was looked at: writing it in place
    // without truncating would leave old bytes after the new ones.
    if file.metadata()?.is_file() {
        return Err(io::Error::other(
            "became a plain file while it was opened; write again",
        ));
    }
    let mut out = OutputFile {
        inner: BufWriter::new(file),
        seekable: false,
    };
    fill(&mut out)?;
    out.flush()
}

/// The file `path` names after following symbolic links (relative links
/// from their own folder); `path` itself if it is not a link.
pub fn follow_links(path: &Path) -> io::Result<PathBuf> {
    let mut p = path.to_path_buf();
    // Linux's own limit on links followed in one lookup.
    for _ in 0..40 {
        match std::fs::symlink_metadata(&p) {
            Ok(m) if m.file_type().is_symlink() => {
                let to = std::fs::read_link(&p)?;
                p = match p.parent() {
                    Some(dir) if to.is_relative() => dir.join(to),
                    _ => to,
                };
            }
            _ => return Ok(p),
        }
    }
    Err(io::Error::other("too many levels of symbolic links"))
}

/// A character device or FIFO: written in place, never renamed over.
fn is_stream(m: &std::fs::Metadata) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        let t = m.file_type();
        t.is_char_device() || t.is_fifo()
    }
    #[cfg(not(unix))]
    {
        let _ = m;
        false
    }
}

/// What a file that is not a plain one is, in words.
pub fn describe(m: &std::fs::Metadata) -> &'static str {
    let t = m.file_type();
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if t.is_fifo() {
            return "a FIFO (named pipe)";
        }
        if t.is_char_device() {
            return "a character device";
        }
        if t.is_block_device() {
            return "a block device";
        }
        if t.is_socket() {
            return "a socket";
        }
    }
    if t.is_dir() {
        "a folder"
    } else if t.is_file() {
        "a file"
    } else {
        "not a plain file"
    }
}

fn not_a_file(m: &std::fs::Metadata) -> io::Error {
    io::Error::other(format!("{}, not a file scotopia can write", describe(m)))
}

/// What a path names, to tell whether two paths are one file: an existing
/// file by its device and inode (hard links and links alike), a missing
/// one by its folder's canonical path and its name.
#[derive(Debug, PartialEq, Eq)]
enum Identity {
    Existing(u64, u64),
    Missing(PathBuf),
}

fn identity(path: &Path) -> Identity {
    if let Ok(m) = std::fs::metadata(path) {
        #[cfg(unix)]
        {
            use std::os::unix::fs::MetadataExt;
            return Identity::Existing(m.dev(), m.ino());
        }
        #[cfg(not(unix))]
        let _ = m;
    }
    let target = follow_links(path).unwrap_or_else(|_| path.to_path_buf());
    let dir = match target.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let dir = std::fs::canonicalize(&dir).unwrap_or(dir);
    Identity::Missing(dir.join(target.file_name().unwrap_or_default()))
}

fn is_char_device(path: &Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        std::fs::metadata(path).is_ok_and(|m| m.file_type().is_char_device())
    }
    #[cfg(not(unix))]
    {
        let _ = path;
        false
    }
}

/// Checks a run's outputs against its inputs and each other, each given
/// with what names it (a flag such as `-o`, or "the scene"): an output
/// that is an input would destroy it, two outputs that are one file would
/// leave only the last. Character devices (`/dev/null`) are left out:
/// writing one destroys nothing.
pub fn check_outputs(inputs: &[(&str, &Path)], outputs: &[(&str, &Path)]) -> Result<(), String> {
    let outputs: Vec<_> = outputs
        .iter()
        .filter(|(_, p)| !is_char_device(p))
        .map(|&(name, p)| (name, p, identity(p)))
        .collect();
    for &(input, path) in inputs {
        if is_char_device(path) {
            continue;
        }
        let id = identity(path);
        if let Some((flag, out, _)) = outputs.iter().find(|o| o.2 == id) {
            return Err(format!(
                "{flag} {} is {input} ({}): writing it would destroy an input of this run; give another output",
                out.display(),
                path.display()
            ));
        }
    }
    for (i, (a, pa, ia)) in outputs.iter().enumerate() {
        if let Some((b, pb, _)) = outputs[i + 1..].iter().find(|o| &o.2 == ia) {
            return Err(format!(
                "{a} {} and {b} {} are the same file: give each output its own",
                pa.display(),
                pb.display()
            ));
        }
    }
    Ok(())
}

#[cfg(test)]
#[path = "output_file_tests.rs"]
mod tests;
