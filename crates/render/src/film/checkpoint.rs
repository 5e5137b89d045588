//! A render's state at a pass boundary, saved to disk so that a render
//! killed outright (SIGKILL, the out-of-memory killer, a lost node) can be
//! resumed: the film's running sums exactly as they are in memory, the
//! samples per pixel done and the render's counters. The sample sequence
//! depends only on the seed, the pixel and the sample index, so a resumed
//! render adds the same numbers in the same order as an uninterrupted one
//! and ends bit-identical to it.
//!
//! Format 3 (little-endian): magic `SCOTCKPT`, version u32, key u64 (the
//! caller's fingerprint of the scene, its files and the options), samples
//! done u32, width u32, height u32, bands u32 (0: none), four u64
//! counters; the files the scene read: a u32 count, then each as a u32
//! length, its path (UTF-8) and its content's hash u64; per pixel four f64
//! sums, the f64 sum of filter weights and a u32 count; the f64 band sums; last, the XXH3-64 hash of
//! every byte before it. A checkpoint is checked whole before it is used:
//! its size against its header, the hash, and that its numbers agree
//! (see [`Checkpoint::check`]).

use std::io::{BufReader, BufWriter, Read, Write};
use std::path::Path;

use xxhash_rust::xxh3::Xxh3;

use scotopia_image::{open_plain, write_output, OutputOptions};

use super::{Bands, Film, PixelSum};

const MAGIC: &[u8; 8] = b"SCOTCKPT";
/// 3: each pixel keeps its sum of filter weights (camera samples are
/// splatted, `film::filter`).
const VERSION: u32 = 3;
const PIXEL: u64 = 4 * 8 + 8 + 4;
/// Bounds on the list of files, checked before anything is allocated.
const MAX_SOURCES: u32 = 1 << 20;
const MAX_SOURCE_PATH: u32 = 1 << 16;

/// What a render has accumulated after `done` samples per pixel.
#[derive(Debug, Clone, PartialEq)]
pub struct Checkpoint {
    /// The caller's fingerprint of what the render depends on (scene,
    /// seed, options): a checkpoint resumes only the render it came from.
    pub key: u64,
    pub done: u32,
    pub counts: SampleCounts,
    pub film: Film,
}

/// What a render's samples counted besides their sums: what a pass adds
/// up and a checkpoint keeps.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct SampleCounts {
    /// Samples whose estimate was not finite, dropped.
    pub dropped: u64,
    /// Light-tracing splats that were not finite, dropped.
    pub dropped_splats: u64,
    /// Rays traced (camera, continuation and shadow rays).
    pub rays: u64,
    /// Samples whose whole cluster collapsed at a dispersive refraction.
    pub collapsed: u64,
}

impl std::ops::AddAssign for SampleCounts {
    fn add_assign(&mut self, b: SampleCounts) {
        self.dropped += b.dropped;
        self.dropped_splats += b.dropped_splats;
        self.rays += b.rays;
        self.collapsed += b.collapsed;
    }
}

impl SampleCounts {
    /// In the checkpoint's order.
    fn to_array(self) -> [u64; 4] {
        [self.dropped, self.dropped_splats, self.rays, self.collapsed]
    }

    fn from_array([dropped, dropped_splats, rays, collapsed]: [u64; 4]) -> Self {
        SampleCounts {
            dropped,
            dropped_splats,
            rays,
            collapsed,
        }
    }
}

/// A file the render depends on and the hash of its content, kept in the
/// checkpoint so that a refused resume can say which file changed.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Source {
    pub path: String,
    pub hash: u64,
}

impl Checkpoint {
    /// Writes the checkpoint (without a list of files) atomically.
    pub fn write(&self, path: &Path) -> Result<(), String> {
        self.write_with(path, &[])
    }

    /// Writes the checkpoint and `sources` to a temporary file beside
    /// `path`, synced, and renames it over `path`, so that a kill during
    /// the write leaves the previous checkpoint whole. `path` must be a
    /// plain file (or not exist yet): a FIFO or device is an error.
    pub fn write_with(&self, path: &Path, sources: &[Source]) -> Result<(), String> {
        write_output(path, OutputOptions::CHECKPOINT, |out| {
            let mut w = Hashing::new(BufWriter::new(out));
            self.encode(&mut w, sources)?;
            let sum = w.hash.digest();
            w.inner.write_all(&sum.to_le_bytes())?;
            w.inner.flush()
        })
        .map_err(|e| format!("{}: cannot write the checkpoint: {e}", path.display()))
    }

    fn encode(&self, w: &mut impl Write, sources: &[Source]) -> std::io::Result<()> {
        w.write_all(MAGIC)?;
        w.write_all(&VERSION.to_le_bytes())?;
        w.write_all(&self.key.to_le_bytes())?;
        w.write_all(&self.done.to_le_bytes())?;
        let f = &self.film;
        w.write_all(&f.width.to_le_bytes())?;
        w.write_all(&f.height.to_le_bytes())?;
        w.write_all(&(f.bands.map_or(0, |b| b.0) as u32).to_le_bytes())?;
        for c in self.counts.to_array() {
            w.write_all(&c.to_le_bytes())?;
        }
        w.write_all(&(sources.len() as u32).to_le_bytes())?;
        for s in sources {
            w.write_all(&(s.path.len() as u32).to_le_bytes())?;
            w.write_all(s.path.as_bytes())?;
            w.write_all(&s.hash.to_le_bytes())?;
        }
        for p in &f.pixels {
            for v in p.xyzv {
                w.write_all(&v.to_le_bytes())?;
            }
            w.write_all(&p.weight.to_le_bytes())?;
            w.write_all(&p.samples.to_le_bytes())?;
        }
        for v in &f.spectral {
            w.write_all(&v.to_le_bytes())?;
        }
        Ok(())
    }

    /// Whether `path` can hold a checkpoint: a plain file or nothing yet
    /// (checked before a render, so a FIFO or device there is an error at
    /// once, not at the first save).
    pub fn check_path(path: &Path) -> Result<(), String> {
        match std::fs::metadata(path) {
            Ok(m) if !m.is_file() => Err(format!(
                "{}: {}, not a checkpoint file: give an output whose .ckpt can be a file",
                path.display(),
                scotopia_image::output_file::describe(&m)
            )),
            _ => Ok(()),
        }
    }

    /// Reads a checkpoint and checks it whole (see the module's note).
    pub fn read(path: &Path) -> Result<Self, String> {
        Self::read_with(path).map(|(c, _)| c)
    }

    /// [`Checkpoint::read`], with the files it was saved with.
    pub fn read_with(path: &Path) -> Result<(Self, Vec<Source>), String> {
        let io = |e: std::io::Error| format!("{}: cannot read the checkpoint: {e}", path.display());
        let file = open_plain(path).map_err(io)?;
        let len = file.metadata().map_err(io)?.len();
        Self::decode(BufReader::new(file), len, &path.display().to_string())
    }

    /// A checkpoint from `len` bytes of `r`; `name` is what errors call it.
    fn decode(r: impl Read, len: u64, name: &str) -> Result<(Self, Vec<Source>), String> {
        let bad = |what: &str| format!("{name}: not a usable scotopia checkpoint: {what}");
        let io = |e: std::io::Error| format!("{name}: cannot read the checkpoint: {e}");
        let mut r = Hashing::new(r);
        let truncated = |_| bad("truncated");
        let mut magic = [0u8; 8];
        r.read_exact(&mut magic).map_err(truncated)?;
        if &magic != MAGIC {
            return Err(bad("wrong magic number"));
        }
        let version = u32s(&mut r).map_err(truncated)?;
        if version != VERSION {
            return Err(bad(&format!(
                "format version {version}, where this scotopia reads {VERSION} (older \
                 checkpoints carry no checksum): delete it and render afresh"
            )));
        }
        let key = u64s(&mut r).map_err(truncated)?;
        let done = u32s(&mut r).map_err(truncated)?;
        let (width, height, bands) = (
            u32s(&mut r).map_err(truncated)?,
            u32s(&mut r).map_err(truncated)?,
            u32s(&mut r).map_err(truncated)?,
        );
        let mut counts = [0u64; 4];
        for c in &mut counts {
            *c = u64s(&mut r).map_err(truncated)?;
        }
        let sources = read_sources(&mut r, len).map_err(|e| bad(&e))?;
        let bands = (bands > 0).then_some(Bands(bands as usize));
        let pixels = width as u64 * height as u64;
        // As `Film::row_stride`: one unused slot per row without bands.
        let stride = bands.map_or(1, |b| b.0 as u64 * width as u64);
        let want = pixels
            .checked_mul(PIXEL)
            .and_then(|p| p.checked_add(stride.checked_mul(height as u64)?.checked_mul(8)?))
            .and_then(|p| p.checked_add(r.count + 8));
        if want != Some(len) {
            return Err(bad(&format!(
                "{len} bytes, where a {width}×{height} film needs {}",
                want.map_or("more than can be addressed".into(), |w| w.to_string())
            )));
        }
        // The size is the file's: what is allocated is no more than it.
        let mut film = Film::new(width, height, bands);
        if film.spectral.len() as u64 != stride * height as u64 {
            return Err(bad("band layout"));
        }
        for p in &mut film.pixels {
            let mut xyzv = [0.0f64; 4];
            for v in &mut xyzv {
                *v = f64::from_bits(u64s(&mut r).map_err(io)?);
            }
            let weight = f64::from_bits(u64s(&mut r).map_err(io)?);
            *p = PixelSum {
                xyzv,
                weight,
                samples: u32s(&mut r).map_err(io)?,
            };
        }
        for v in &mut film.spectral {
            *v = f64::from_bits(u64s(&mut r).map_err(io)?);
        }
        let sum = r.hash.digest();
        let mut stored = [0u8; 8];
        r.inner.read_exact(&mut stored).map_err(io)?;
        if u64::from_le_bytes(stored) != sum {
            return Err(bad(
                "its checksum does not match (the file is damaged): delete it and render afresh",
            ));
        }
        let c = Self {
            key,
            done,
            counts: SampleCounts::from_array(counts),
            film,
        };
        c.check().map_err(|e| bad(&e))?;
        Ok((c, sources))
    }

    /// Whether the numbers agree: each pixel has at most `done` samples,
    /// the samples missing are the dropped ones counted, and every sum is
    /// finite (non-finite samples are dropped, never added).
    pub fn check(&self) -> Result<(), String> {
        let f = &self.film;
        let mut missing = 0u64;
        for (i, p) in f.pixels.iter().enumerate() {
            let (x, y) = (i % f.width as usize, i / f.width as usize);
            if p.samples > self.done {
                return Err(format!(
                    "pixel ({x}, {y}) has {} samples, more than the {} done",
                    p.samples, self.done
                ));
            }
            if p.xyzv.iter().any(|v| !v.is_finite()) {
                return Err(format!("pixel ({x}, {y}) has a sum that is not finite"));
            }
            if !(p.weight.is_finite() && p.weight >= 0.0) {
                return Err(format!(
                    "pixel ({x}, {y}) has a weight that is not a finite number ≥ 0"
                ));
            }
            missing += (self.done - p.samples) as u64;
        }
        if missing != self.counts.dropped {
            return Err(format!(
                "{missing} samples are missing from the pixels, where {} were dropped",
                self.counts.dropped
            ));
        }
        if f.spectral.iter().any(|v| !v.is_finite()) {
            return Err("a band sum is not finite".into());
        }
        Ok(())
    }
}

fn read_sources(r: &mut Hashing<impl Read>, len: u64) -> Result<Vec<Source>, String> {
    let truncated = |_| "truncated".to_string();
    let count = u32s(r).map_err(truncated)?;
    if count > MAX_SOURCES {
        return Err(format!("{count} files listed, more than {MAX_SOURCES}"));
    }
    let mut sources = Vec::new();
    for _ in 0..count {
        let n = u32s(r).map_err(truncated)?;
        if n > MAX_SOURCE_PATH || r.count + n as u64 > len {
            return Err(format!("a file name of {n} bytes"));
        }
        let mut path = vec![0u8; n as usize];
        r.read_exact(&mut path).map_err(truncated)?;
        let path = String::from_utf8(path).map_err(|_| "a file name that is not UTF-8")?;
        let hash = u64s(r).map_err(truncated)?;
        sources.push(Source { path, hash });
    }
    Ok(sources)
}

fn u32s(r: &mut impl Read) -> std::io::Result<u32> {
    let mut b = [0u8; 4];
    r.read_exact(&mut b)?;
    Ok(u32::from_le_bytes(b))
}

fn u64s(r: &mut impl Read) -> std::io::Result<u64> {
    let mut b = [0u8; 8];
    r.read_exact(&mut b)?;
    Ok(u64::from_le_bytes(b))
}

/// A reader or writer that hashes the bytes passing through and counts them.
struct Hashing<T> {
    inner: T,
    hash: Xxh3,
    count: u64,
}

impl<T> Hashing<T> {
    fn new(inner: T) -> Self {
        Self {
            inner,
            hash: Xxh3::new(),
            count: 0,
        }
    }
}

impl<R: Read> Read for Hashing<R> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let n = self.inner.read(buf)?;
        self.hash.update(&buf[..n]);
        self.count += n as u64;
        Ok(n)
    }
}

impl<W: Write> Write for Hashing<W> {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        let n = self.inner.write(buf)?;
        self.hash.update(&buf[..n]);
        self.count += n as u64;
        Ok(n)
    }

    fn flush(&mut self) -> std::io::Result<()> {
        self.inner.flush()
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
#[path = "checkpoint_tests.rs"]
mod tests;
