//! A direct reader for the layout `write_exr` produces — one part,
//! scanlines of one line per block, RLE or no compression, every channel
//! 32-bit float at full resolution — decoding bands of lines in parallel
//! straight into [X, Y, Z, V′] pixels. The general `exr` reader calls a
//! closure per sample (most of `display`'s single-threaded work on a
//! 1920×1080 image); this one unpacks a line in three array passes.
//!
//! It never reports the file's faults itself: any layout it does not know,
//! and any inconsistency (truncation, a bad offset, a corrupt run), makes it
//! return `None`, and the caller reads the file with the general reader,
//! which then gives that reader's error. Only valid files take this path,
//! and for them the two readers agree bit for bit (tests below).
//!
//! The format (OpenEXR file layout, openexr.com "OpenEXR File Layout";
//! RLE as in OpenEXR's ImfRle/ImfRleCompressor): magic and version (8
//! bytes), attributes (name\0 type\0 i32 size, value) ended by a 0 byte,
//! one u64 file offset per block, then blocks: i32 line, i32 size, data. A
//! line's data holds each channel's samples in turn, in the header's
//! (sorted) channel order, little-endian. RLE data, once its runs are
//! expanded, is delta-coded bytes (each stored byte minus its predecessor,
//! plus 128) of the line's bytes split into the even- and the
//! odd-positioned halves; a block whose RLE would not be smaller is stored
//! raw, recognised by its size.

use std::fs::File;
use std::io::{BufReader, Read, Seek, SeekFrom};
use std::path::Path;

use exr::meta::{attribute::SampleType, BlockDescription, MetaData};
use exr::prelude::Compression;
use rayon::prelude::*;

/// Lines per parallel task: large enough for one read to fetch several
/// blocks, small enough for two threads to share the work evenly.
const BAND: usize = 16;

/// The magic number that opens every OpenEXR file.
const MAGIC: [u8; 4] = [0x76, 0x2f, 0x31, 0x01];

/// The pixels of `path`'s channels `slots` (indices into the header's
/// channel list, for X, Y, Z, V′) if the file has `write_exr`'s layout and
/// decodes without fault; `None` otherwise (the caller falls back to the
/// general reader).
pub(crate) fn read_own_layout(
    path: &Path,
    meta: &MetaData,
    slots: [usize; 4],
) -> Option<Vec<[f32; 4]>> {
    let [header] = meta.headers.as_slice() else {
        return None;
    };
    let simple = !header.deep
        && matches!(header.blocks, BlockDescription::ScanLines)
        && matches!(
            header.compression,
            Compression::RLE | Compression::Uncompressed
        )
        && header
            .channels
            .list
            .iter()
            .all(|c| c.sample_type == SampleType::F32 && c.sampling == exr::math::Vec2(1, 1));
    let (width, height) = (header.layer_size.width(), header.layer_size.height());
    if !simple || width == 0 || height == 0 || header.chunk_count != height {
        return None;
    }
    let line_bytes = header.channels.list.len().checked_mul(4 * width)?;
    if slots.iter().any(|&s| s >= header.channels.list.len()) {
        return None;
    }
    let mut file = BufReader::new(File::open(path).ok()?);
    let table = offset_table(&mut file, height)?;
    let file_len = file.get_ref().metadata().ok()?.len();
    // Blocks in file order, each before the next and inside the file: a
    // band of lines is then one read, from its first block to the next
    // band's.
    if table.windows(2).any(|w| w[0] >= w[1]) || table[height - 1] >= file_len {
        return None;
    }
    let layout = Layout {
        raw_only: header.compression == Compression::Uncompressed,
        width,
        line_bytes,
        slots,
        first_line: header.own_attributes.layer_position.y(),
    };
    // Zeroed by the allocator (fresh pages, no pass over them): each page is
    // first touched by the thread that decodes into it.
    let mut pixels = vec![[0.0f32; 4]; width * height];
    let decoded = pixels
        .par_chunks_mut(width * BAND)
        .enumerate()
        .try_for_each(|(band, rows)| {
            let lines = band * BAND..band * BAND + rows.len() / width;
            let end = table.get(lines.end).copied().unwrap_or(file_len);
            layout.decode_band(path, &table[lines.clone()], end, lines.start, rows)
        });
    decoded.map(|()| pixels)
}

/// Where the pieces of a line lie.
struct Layout {
    /// No compression: every block must hold a whole raw line.
    raw_only: bool,
    width: usize,
    /// Bytes of one uncompressed line (every channel).
    line_bytes: usize,
    /// Index of the X, Y, Z and V′ channels in the line.
    slots: [usize; 4],
    /// The data window's top line (blocks name their line by it).
    first_line: i32,
}

thread_local! {
    /// A band's bytes as read, and a line's unpacked bytes: kept per
    /// thread so their pages are faulted in once, not once per band.
    static BUFFERS: std::cell::RefCell<[Vec<u8>; 3]> = const {
        std::cell::RefCell::new([Vec::new(), Vec::new(), Vec::new()])
    };
}

impl Layout {
    /// Decodes the blocks at `offsets` (lines `first..`, the band's bytes
    /// ending at `end`) into `rows`.
    fn decode_band(
        &self,
        path: &Path,
        offsets: &[u64],
        end: u64,
        first: usize,
        rows: &mut [[f32; 4]],
    ) -> Option<()> {
        let start = *offsets.first()?;
        // No more than the band's blocks can hold, whatever lies between
        // (a forged offset, trailing bytes): a block is at most a raw line.
        let most = (offsets.len() as u64).checked_mul(8 + self.line_bytes as u64)?;
        let end = end.min(start.checked_add(most)?);
        let len = usize::try_from(end.checked_sub(start)?).ok()?;
        let mut file = File::open(path).ok()?;
        file.seek(SeekFrom::Start(start)).ok()?;
        BUFFERS.with_borrow_mut(|[bytes, split, line]| {
            bytes.clear();
            // Into spare capacity: no zeroing pass first.
            file.take(len as u64).read_to_end(bytes).ok()?;
            if bytes.len() != len {
                return None;
            }
            line.resize(self.line_bytes, 0);
            let ends = offsets.iter().skip(1).copied().chain([end]);
            for (k, ((&offset, next), row)) in offsets
                .iter()
                .zip(ends)
                .zip(rows.chunks_exact_mut(self.width))
                .enumerate()
            {
                let block = bytes.get((offset - start) as usize..(next - start) as usize)?;
                let (head, data) = block.split_at_checked(8)?;
                let y = i32::from_le_bytes(head[..4].try_into().ok()?);
                let size = u32::from_le_bytes(head[4..].try_into().ok()?) as usize;
                let line_no = i32::try_from(first + k)
                    .ok()?
                    .checked_add(self.first_line)?;
                let data = data.get(..size)?;
                let raw = size == self.line_bytes;
                if y != line_no || size > self.line_bytes || (self.raw_only && !raw) {
                    return None;
                }
                if raw {
                    self.scatter(data, row);
                } else {
                    unpack_rle(data, split, line)?;
                    self.scatter(line, row);
                }
            }
            Some(())
        })
    }

    /// Moves the four channels' samples of an uncompressed line into pixels.
    fn scatter(&self, line: &[u8], row: &mut [[f32; 4]]) {
        let channel_bytes = 4 * self.width;
        for (slot, &c) in self.slots.iter().enumerate() {
            let samples = &line[c * channel_bytes..(c + 1) * channel_bytes];
            for (p, b) in row.iter_mut().zip(samples.chunks_exact(4)) {
                p[slot] = f32::from_le_bytes([b[0], b[1], b[2], b[3]]);
            }
        }
    }
}

/// Skips the header's attributes and reads the offset table of `blocks`
/// blocks (`None` for anything but one plain part's header).
fn offset_table(file: &mut impl Read, blocks: usize) -> Option<Vec<u64>> {
    let mut start = [0u8; 8];
    file.read_exact(&mut start).ok()?;
    // Version 2; flags (bits 9–12: tiled, long names, deep, multi-part)
    // must leave a plain scanline file (long names are fine).
    let flags = u32::from_le_bytes(start[4..].try_into().ok()?);
    if start[..4] != MAGIC || flags & 0xff != 2 || flags & !(0xff | 1 << 10) != 0 {
        return None;
    }
    loop {
        let name = read_name(file)?;
        if name == 0 {
            break;
        }
        read_name(file)?;
        let mut size = [0u8; 4];
        file.read_exact(&mut size).ok()?;
        let size = u64::try_from(i32::from_le_bytes(size)).ok()?;
        if std::io::copy(&mut file.by_ref().take(size), &mut std::io::sink()).ok()? != size {
            return None;
        }
    }
    let mut table = vec![0u8; blocks.checked_mul(8)?];
    file.read_exact(&mut table).ok()?;
    Some(
        table
            .chunks_exact(8)
            .map(|b| u64::from_le_bytes([b[0], b[1], b[2], b[3], b[4], b[5], b[6], b[7]]))
            .collect(),
    )
}

/// Reads a 0-terminated name of at most 255 bytes; returns its length.
fn read_name(file: &mut impl Read) -> Option<usize> {
    let mut byte = [0u8; 1];
    for len in 0..256 {
        file.read_exact(&mut byte).ok()?;
        if byte[0] == 0 {
            return Some(len);
        }
    }
    None
}

/// Expands RLE `packed` into exactly `line.len()` bytes, undoes the delta
/// coding and interleaves the two halves back; `None` if the runs do not
/// fill the line exactly.
fn unpack_rle(packed: &[u8], split: &mut Vec<u8>, line: &mut [u8]) -> Option<()> {
    split.clear();
    let mut rest = packed;
    while let [count, tail @ ..] = rest {
        let count = *count as i8;
        if count < 0 {
            let n = usize::from(count.unsigned_abs());
            split.extend_from_slice(tail.get(..n)?);
            rest = &tail[n..];
        } else {
            let (&value, tail) = tail.split_first()?;
            split.resize(split.len() + count as usize + 1, value);
            rest = tail;
        }
        if split.len() > line.len() {
            return None;
        }
    }
    if split.len() != line.len() {
        return None;
    }
    let mut previous = split[0];
    for b in &mut split[1..] {
        previous = previous.wrapping_add(*b).wrapping_sub(128);
        *b = previous;
    }
    let (even, odd) = split.split_at(line.len().div_ceil(2));
    for (pair, (&e, &o)) in line.chunks_exact_mut(2).zip(even.iter().zip(odd)) {
        pair[0] = e;
        pair[1] = o;
    }
    if line.len() % 2 == 1 {
        line[line.len() - 1] = even[even.len() - 1];
    }
    Some(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{read_xyzv, write_exr, RgbInput};

    fn tmp(name: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("scotopia-exr-fast-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        dir.join(name)
    }

    /// A `w` × `h` image written by `write_exr` with channels V, X, Y, Z
    /// and `extra`: hashed bit patterns (stored raw: RLE cannot pack them)
    /// on odd lines, runs (RLE-packed) on even ones.
    fn write(path: &Path, w: usize, h: usize, extra: &[&str]) -> Vec<(String, Vec<f32>)> {
        let values = |c: u32| -> Vec<f32> {
            (0..(w * h) as u32)
                .map(|i| match (i as usize / w) % 2 {
                    0 => (i / 5) as f32 * 0.25,
                    _ => f32::from_bits((i + 1).wrapping_mul(0x9E37_79B9) ^ (c << 24)),
                })
                .collect()
        };
        let names = ["X", "Y", "Z", "V"].iter().chain(extra);
        let chans: Vec<(String, Vec<f32>)> = names
            .zip(1..)
            .map(|(n, c)| (n.to_string(), values(c)))
            .collect();
        write_exr(path, w, h, chans.clone(), &[]).unwrap();
        chans
    }

    /// The pixels through the fast path (which must take the file).
    fn fast(path: &Path) -> Vec<[f32; 4]> {
        let meta = crate::exr_out::read_exr_headers(path).unwrap();
        let list = &meta.headers[0].channels.list;
        let slot = |n: &str| list.iter().position(|c| c.name == *n).unwrap();
        read_own_layout(path, &meta, ["X", "Y", "Z", "V"].map(slot)).expect("fast path")
    }

    fn bits(pixels: &[[f32; 4]]) -> Vec<[u32; 4]> {
        pixels.iter().map(|p| p.map(f32::to_bits)).collect()
    }

    #[test]
    fn the_writer_round_trips_through_the_fast_path_as_through_the_general_reader() {
        for (w, h, extra) in [
            (37, 23, &[][..]),
            (1, 1, &[][..]),
            (64, 40, &["A", "depth"][..]),
        ] {
            let path = tmp(&format!("own-{w}x{h}.exr"));
            let chans = write(&path, w, h, extra);
            let pixels = fast(&path);
            let want: Vec<[u32; 4]> = (0..w * h)
                .map(|i| [0, 1, 2, 3].map(|c| chans[c].1[i].to_bits()))
                .collect();
            assert_eq!(bits(&pixels), want, "{w}×{h}");
            let general = read_four(&path);
            assert_eq!(bits(&pixels), bits(&general), "{w}×{h}");
            // read_xyzv takes the fast path.
            let img = read_xyzv(&path, RgbInput::default()).unwrap();
            assert_eq!(bits(&img.pixels), want);
        }
    }

    /// The general reader's pixels.
    fn read_four(path: &Path) -> Vec<[f32; 4]> {
        let e = crate::read_exr(path).unwrap();
        let c = |n: &str| &e.channels.iter().find(|c| c.0 == n).unwrap().1;
        let [x, y, z, v] = ["X", "Y", "Z", "V"].map(c);
        (0..e.width * e.height)
            .map(|i| [x[i], y[i], z[i], v[i]])
            .collect()
    }

    #[test]
    fn trailing_bytes_are_not_read() {
        let path = tmp("trailing.exr");
        let chans = write(&path, 9, 5, &[]);
        let mut bytes = std::fs::read(&path).unwrap();
        bytes.extend(std::iter::repeat_n(0xAB, 100_000));
        std::fs::write(&path, bytes).unwrap();
        let x: Vec<u32> = fast(&path).iter().map(|p| p[0].to_bits()).collect();
        let want: Vec<u32> = chans[0].1.iter().map(|v| v.to_bits()).collect();
        assert_eq!(x, want);
    }

    #[test]
    fn truncated_files_are_errors_naming_the_file() {
        let path = tmp("whole.exr");
        write(&path, 40, 30, &[]);
        let bytes = std::fs::read(&path).unwrap();
        let cut = tmp("cut.exr");
        for keep in [bytes.len() - 1, bytes.len() / 2, bytes.len() / 5, 400, 40] {
            std::fs::write(&cut, &bytes[..keep]).unwrap();
            let e = read_xyzv(&cut, RgbInput::default())
                .unwrap_err()
                .to_string();
            assert!(e.contains("cut.exr"), "{keep}: {e}");
        }
    }

    #[test]
    fn corrupt_bytes_are_errors_or_pixels_never_panics() {
        let path = tmp("fine.exr");
        write(&path, 24, 16, &[]);
        let bytes = std::fs::read(&path).unwrap();
        let bad = tmp("bad.exr");
        let mut z: u64 = 0x2545_F491_4F6C_DD1D;
        for _ in 0..300 {
            let mut b = bytes.clone();
            for _ in 0..4 {
                z ^= z << 13;
                z ^= z >> 7;
                z ^= z << 17;
                let at = (z % b.len() as u64) as usize;
                b[at] = (z >> 32) as u8;
            }
            std::fs::write(&bad, &b).unwrap();
            if let Err(e) = read_xyzv(&bad, RgbInput::default()) {
                assert!(e.to_string().contains("bad.exr"), "{e}");
            }
        }
    }

    #[test]
    fn a_corrupt_run_falls_back_to_the_general_reader() {
        let path = tmp("run.exr");
        write(&path, 40, 4, &[]);
        let meta = crate::exr_out::read_exr_headers(&path).unwrap();
        let mut bytes = std::fs::read(&path).unwrap();
        // The first line is RLE-packed: drop its last byte from its size.
        let first = {
            let mut r = std::io::Cursor::new(&bytes);
            offset_table(&mut r, 4).unwrap()[0] as usize
        };
        let size = u32::from_le_bytes(bytes[first + 4..first + 8].try_into().unwrap());
        assert!((size as usize) < 40 * 4 * 4, "line 0 should be packed");
        bytes[first + 4..first + 8].copy_from_slice(&(size - 1).to_le_bytes());
        std::fs::write(&path, &bytes).unwrap();
        assert!(read_own_layout(&path, &meta, [1, 2, 3, 0]).is_none());
        // The general reader then decides (an error or its own pixels).
        let _ = read_xyzv(&path, RgbInput::default());
    }
}
