//! A render's state at a pass boundary, saved to disk so that a render
//! killed outright (SIGKILL, the out-of-memory killer, a lost node) can be
//! resumed: the film's running sums exactly as they are in memory, the
//! samples per pixel done and the render's counters. The sample sequence
//! depends only on the seed, the pixel and the sample index, so a resumed
//! render adds the same numbers in the same order as an uninterrupted one
//! and ends bit-identical to it.
//!
//! Format (little-endian): magic `SCOTCKPT`, version u32, key u64 (the
//! caller's fingerprint of the scene and options), samples done u32,
//! width u32, height u32, bands u32 (0: none), four u64 counters, then per
//! pixel four f64 sums and a u32 count, then the f64 band sums.

use std::fs::File;
use std::io::{BufReader, BufWriter, Read, Write};
use std::path::Path;

use super::{Bands, Film, PixelSum};

const MAGIC: &[u8; 8] = b"SCOTCKPT";
const VERSION: u32 = 1;
const HEADER: u64 = 8 + 4 + 8 + 4 + 4 + 4 + 4 + 4 * 8;
const PIXEL: u64 = 4 * 8 + 4;

/// What a render has accumulated after `done` samples per pixel.
#[derive(Debug, Clone, PartialEq)]
pub struct Checkpoint {
    /// The caller's fingerprint of what the render depends on (scene,
    /// seed, options): a checkpoint resumes only the render it came from.
    pub key: u64,
    pub done: u32,
    /// Dropped non-finite samples, dropped splats, rays, collapsed clusters.
    pub counts: [u64; 4],
    pub film: Film,
}

impl Checkpoint {
    /// Writes the checkpoint to a temporary file beside `path` and renames
    /// it over `path`, so that a kill during the write leaves the previous
    /// checkpoint whole.
    pub fn write(&self, path: &Path) -> Result<(), String> {
        let fail =
            |e: std::io::Error| format!("{}: cannot write the checkpoint: {e}", path.display());
        let mut name = path.file_name().unwrap_or_default().to_os_string();
        name.push(format!(".tmp{}", std::process::id()));
        let tmp = path.with_file_name(name);
        let result = (|| {
            let mut w = BufWriter::new(File::create(&tmp)?);
            w.write_all(MAGIC)?;
            w.write_all(&VERSION.to_le_bytes())?;
            w.write_all(&self.key.to_le_bytes())?;
            w.write_all(&self.done.to_le_bytes())?;
            let f = &self.film;
            w.write_all(&f.width.to_le_bytes())?;
            w.write_all(&f.height.to_le_bytes())?;
            w.write_all(&(f.bands.map_or(0, |b| b.0) as u32).to_le_bytes())?;
            for c in self.counts {
                w.write_all(&c.to_le_bytes())?;
            }
            for p in &f.pixels {
                for v in p.xyzv {
                    w.write_all(&v.to_le_bytes())?;
                }
                w.write_all(&p.samples.to_le_bytes())?;
            }
            for v in &f.spectral {
                w.write_all(&v.to_le_bytes())?;
            }
            let file = w.into_inner().map_err(|e| e.into_error())?;
            file.sync_all()?;
            std::fs::rename(&tmp, path)
        })();
        if result.is_err() {
            let _ = std::fs::remove_file(&tmp);
        }
        result.map_err(fail)
    }

    /// Reads a checkpoint, checking its size against its header before
    /// allocating anything.
    pub fn read(path: &Path) -> Result<Self, String> {
        let bad = |what: &str| format!("{}: not a scotopia checkpoint: {what}", path.display());
        let io = |e: std::io::Error| format!("{}: cannot read the checkpoint: {e}", path.display());
        let file = File::open(path).map_err(io)?;
        let len = file.metadata().map_err(io)?.len();
        let mut r = BufReader::new(file);
        let mut magic = [0u8; 8];
        r.read_exact(&mut magic).map_err(|_| bad("too short"))?;
        if &magic != MAGIC {
            return Err(bad("wrong magic number"));
        }
        let u32s = |r: &mut BufReader<File>| -> Result<u32, String> {
            let mut b = [0u8; 4];
            r.read_exact(&mut b).map_err(|_| bad("truncated header"))?;
            Ok(u32::from_le_bytes(b))
        };
        let version = u32s(&mut r)?;
        if version != VERSION {
            return Err(bad(&format!(
                "version {version}, this scotopia reads {VERSION}"
            )));
        }
        let mut b8 = [0u8; 8];
        r.read_exact(&mut b8).map_err(|_| bad("truncated header"))?;
        let key = u64::from_le_bytes(b8);
        let done = u32s(&mut r)?;
        let (width, height, bands) = (u32s(&mut r)?, u32s(&mut r)?, u32s(&mut r)?);
        let mut counts = [0u64; 4];
        for c in &mut counts {
            r.read_exact(&mut b8).map_err(|_| bad("truncated header"))?;
            *c = u64::from_le_bytes(b8);
        }
        let bands = (bands > 0).then_some(Bands(bands as usize));
        let pixels = width as u64 * height as u64;
        // As `Film::row_stride`: one unused slot per row without bands.
        let stride = bands.map_or(1, |b| b.0 as u64 * width as u64);
        let want = pixels
            .checked_mul(PIXEL)
            .and_then(|p| p.checked_add(stride.checked_mul(height as u64)?.checked_mul(8)?))
            .and_then(|p| p.checked_add(HEADER));
        if want != Some(len) {
            return Err(bad(&format!(
                "{len} bytes, where a {width}×{height} film needs {}",
                want.map_or("more than can be addressed".into(), |w| w.to_string())
            )));
        }
        let mut film = Film::new(width, height, bands);
        if film.spectral.len() as u64 != stride * height as u64 {
            return Err(bad("band layout"));
        }
        for p in &mut film.pixels {
            let mut xyzv = [0.0f64; 4];
            for v in &mut xyzv {
                r.read_exact(&mut b8).map_err(io)?;
                *v = f64::from_le_bytes(b8);
            }
            *p = PixelSum {
                xyzv,
                samples: u32s(&mut r)?,
            };
        }
        for v in &mut film.spectral {
            r.read_exact(&mut b8).map_err(io)?;
            *v = f64::from_le_bytes(b8);
        }
        Ok(Self {
            key,
            done,
            counts,
            film,
        })
    }
}

/// A fingerprint of what a render's sample sequence depends on, from its
/// parts (the scene file's bytes, its parameters, the options): FNV-1a,
/// 64 bits, the same in every build.
pub fn fingerprint(parts: &[&[u8]]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for part in parts {
        // The length first, so that parts cannot run into each other.
        for b in (part.len() as u64).to_le_bytes().iter().chain(part.iter()) {
            h = (h ^ *b as u64).wrapping_mul(0x0100_0000_01b3);
        }
    }
    h
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> Checkpoint {
        let mut film = Film::new(3, 2, Some(Bands(5)));
        for (i, p) in film.pixels.iter_mut().enumerate() {
            p.add([i as f32, 0.1, -2.5, 1e30]);
        }
        for (i, v) in film.spectral.iter_mut().enumerate() {
            *v = i as f64 * 0.37;
        }
        Checkpoint {
            key: 0xdead_beef_1234,
            done: 7,
            counts: [1, 2, 3, 4],
            film,
        }
    }

    #[test]
    fn fingerprints_tell_parts_apart() {
        let a = fingerprint(&[b"ab", b"c"]);
        assert_eq!(a, fingerprint(&[b"ab", b"c"]));
        assert_ne!(a, fingerprint(&[b"a", b"bc"]));
        assert_ne!(a, fingerprint(&[b"ab", b"d"]));
    }

    #[test]
    fn a_checkpoint_reads_back_bit_for_bit() {
        let path = std::env::temp_dir().join(format!("ckpt-rt-{}.ckpt", std::process::id()));
        let c = sample();
        c.write(&path).unwrap();
        assert_eq!(Checkpoint::read(&path).unwrap(), c);
        let _ = std::fs::remove_file(&path);
    }

    #[test]
    fn damaged_checkpoints_are_errors_naming_the_file() {
        let path = std::env::temp_dir().join(format!("ckpt-bad-{}.ckpt", std::process::id()));
        sample().write(&path).unwrap();
        let bytes = std::fs::read(&path).unwrap();
        // Truncated, a header claiming a huge film, and not one at all.
        std::fs::write(&path, &bytes[..bytes.len() - 1]).unwrap();
        let e = Checkpoint::read(&path).unwrap_err();
        assert!(
            e.contains(&path.display().to_string()) && e.contains("bytes"),
            "{e}"
        );
        let mut huge = bytes.clone();
        huge[24..28].copy_from_slice(&u32::MAX.to_le_bytes());
        huge[28..32].copy_from_slice(&u32::MAX.to_le_bytes());
        std::fs::write(&path, &huge).unwrap();
        assert!(Checkpoint::read(&path).unwrap_err().contains("film needs"));
        std::fs::write(&path, b"hello").unwrap();
        assert!(Checkpoint::read(&path)
            .unwrap_err()
            .contains("not a scotopia checkpoint"));
        let _ = std::fs::remove_file(&path);
    }
}
