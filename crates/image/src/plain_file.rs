//! Opening a file that must be a plain one (a checkpoint, a scene's file
//! being hashed) without ever waiting: opening a FIFO waits for a writer,
//! and a device may never end.

use std::fs::{File, OpenOptions};
use std::io;
use std::path::Path;

use crate::output_file::describe;

/// `path` opened for reading if it is a plain file (after links); a FIFO,
/// device, folder or socket is an error saying which. The type is checked
/// before opening, and the open does not wait (O_NONBLOCK) in case the
/// file was swapped in between; what was opened is checked again.
pub fn open_plain(path: &Path) -> io::Result<File> {
    let not_plain =
        |m: &std::fs::Metadata| io::Error::other(format!("{}, not a plain file", describe(m)));
    let m = std::fs::metadata(path)?;
    if !m.is_file() {
        return Err(not_plain(&m));
    }
    let mut options = OpenOptions::new();
    options.read(true);
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt;
        options.custom_flags(libc::O_NONBLOCK);
    }
    let file = options.open(path)?;
    let m = file.metadata()?;
    if !m.is_file() {
        return Err(not_plain(&m));
    }
    Ok(file)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fifos_and_folders_are_refused_without_waiting() {
        let dir = std::env::temp_dir().join(format!("scotopia-plain-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let fifo = dir.join("pipe");
        let _ = std::fs::remove_file(&fifo);
        let made = std::process::Command::new("mkfifo").arg(&fifo).status();
        assert!(made.unwrap().success());
        // No writer ever comes: a blocking open would hang the test.
        let e = open_plain(&fifo).unwrap_err().to_string();
        assert!(e.contains("FIFO"), "{e}");
        let e = open_plain(&dir).unwrap_err().to_string();
        assert!(e.contains("folder"), "{e}");
        std::fs::write(dir.join("f"), b"x").unwrap();
        assert!(open_plain(&dir.join("f")).is_ok());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
