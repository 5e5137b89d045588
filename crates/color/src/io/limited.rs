//! Reading a whole file into memory, with a size limit: a file named by a
//! scene may be `/dev/zero`, a pipe or a runaway log, and reading it whole
//! would take all memory before failing. One function for every format
//! read whole (XML, spectra, matrices, meshes), each with its own limit.

use std::io::{self, Read};
use std::path::Path;

/// One mebibyte, to write limits readably.
pub const MIB: u64 = 1 << 20;

/// The bytes of `path`, or an error if it holds more than `limit` bytes.
/// A regular file's size is checked before reading; anything else (a
/// device, a pipe) is read up to `limit + 1` bytes, so an endless input
/// stops there.
pub fn read_limited(path: &Path, limit: u64) -> io::Result<Vec<u8>> {
    let file = std::fs::File::open(path)?;
    let meta = file.metadata()?;
    if meta.is_dir() {
        return Err(io::Error::new(io::ErrorKind::IsADirectory, "is a folder"));
    }
    if meta.is_file() && meta.len() > limit {
        return Err(too_large(limit));
    }
    let mut bytes = Vec::new();
    file.take(limit + 1).read_to_end(&mut bytes)?;
    if bytes.len() as u64 > limit {
        return Err(too_large(limit));
    }
    Ok(bytes)
}

/// [`read_limited`] as UTF-8 text; invalid UTF-8 names its byte offset.
pub fn read_text_limited(path: &Path, limit: u64) -> io::Result<String> {
    String::from_utf8(read_limited(path, limit)?).map_err(|e| {
        io::Error::new(
            io::ErrorKind::InvalidData,
            format!(
                "not UTF-8 text (invalid byte at offset {})",
                e.utf8_error().valid_up_to()
            ),
        )
    })
}

fn too_large(limit: u64) -> io::Error {
    let size = if limit >= MIB && limit.is_multiple_of(MIB) {
        format!("{} MiB", limit / MIB)
    } else {
        format!("{limit} bytes")
    };
    io::Error::new(
        io::ErrorKind::FileTooLarge,
        format!("larger than the limit of {size} for this kind of file"),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_file_over_the_limit_is_refused_and_one_at_it_read() {
        let dir = std::env::temp_dir().join(format!("scotopia-limited-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("ten.txt");
        std::fs::write(&path, "0123456789").unwrap();
        assert_eq!(read_text_limited(&path, 10).unwrap(), "0123456789");
        let e = read_text_limited(&path, 9).unwrap_err().to_string();
        assert!(e.contains("limit of 9 bytes"), "{e}");
        std::fs::write(&path, b"ab\xffc").unwrap();
        let e = read_text_limited(&path, 10).unwrap_err().to_string();
        assert!(e.contains("offset 2"), "{e}");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[cfg(target_os = "linux")]
    #[test]
    fn an_endless_device_stops_at_the_limit() {
        let e = read_limited(Path::new("/dev/zero"), 2 * MIB).unwrap_err();
        assert!(e.to_string().contains("limit of 2 MiB"), "{e}");
    }
}
