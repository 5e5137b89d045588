//! Voxel grids from Mitsuba's binary `.vol` files (its `gridvolume`; the
//! format of Mitsuba 0.6 and 3, little-endian):
//!
//! | bytes | content |
//! |---|---|
//! | 0–2 | `VOL` |
//! | 3 | version, 3 |
//! | 4–7 | encoding (i32): 1 = float32, the only one defined |
//! | 8–19 | cells along x, y, z (i32 each) |
//! | 20–23 | channels (i32): 1, 3 or 6 |
//! | 24–47 | the box: xmin, ymin, zmin, xmax, ymax, zmax (f32) |
//! | 48– | values, `data[((z·ny + y)·nx + x)·channels + c]` |
//!
//! Every fault is an error naming the file and the byte where it is:
//! a wrong signature, version or encoding, sizes that are not positive or
//! would not fit in memory, a box that is not finite or is inverted, too
//! few values (a truncated file) or too many, and values that are not
//! finite or are negative (densities, albedos and colours are not).

use std::path::Path;

use scotopia_render::math::Aabb;
use scotopia_render::math::Vec3;
use scotopia_render::medium::Grid;

const HEADER: usize = 48;

/// A `.vol` file that cannot be used.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{file}: byte {byte}: {message}")]
pub struct VolumeError {
    pub file: String,
    pub byte: usize,
    pub message: String,
}

/// Reads a `.vol` file.
pub fn read_vol(path: &Path) -> Result<Grid, VolumeError> {
    let file = path.display().to_string();
    let bytes = std::fs::read(path).map_err(|e| VolumeError {
        file: file.clone(),
        byte: 0,
        message: format!("cannot read it: {e}"),
    })?;
    parse_vol(&bytes, &file)
}

/// A `.vol` file's bytes; `source` names it in errors.
pub fn parse_vol(bytes: &[u8], source: &str) -> Result<Grid, VolumeError> {
    let fail = |byte: usize, message: String| VolumeError {
        file: source.to_string(),
        byte,
        message,
    };
    if bytes.len() < HEADER {
        return Err(fail(
            bytes.len(),
            format!(
                "the file ends inside its {HEADER}-byte header (it has {} bytes)",
                bytes.len()
            ),
        ));
    }
    if &bytes[0..3] != b"VOL" {
        return Err(fail(
            0,
            "not a Mitsuba volume: it does not start with 'VOL'".into(),
        ));
    }
    if bytes[3] != 3 {
        return Err(fail(
            3,
            format!("version {}: only version 3 is defined", bytes[3]),
        ));
    }
    let int =
        |at: usize| i32::from_le_bytes([bytes[at], bytes[at + 1], bytes[at + 2], bytes[at + 3]]);
    let float =
        |at: usize| f32::from_le_bytes([bytes[at], bytes[at + 1], bytes[at + 2], bytes[at + 3]]);
    let encoding = int(4);
    if encoding != 1 {
        return Err(fail(
            4,
            format!("encoding {encoding}: only 1 (float32) is defined"),
        ));
    }
    let mut res = [0usize; 3];
    for (axis, r) in res.iter_mut().enumerate() {
        let n = int(8 + 4 * axis);
        if n <= 0 {
            return Err(fail(
                8 + 4 * axis,
                format!(
                    "{n} cells along {}: must be positive",
                    ["x", "y", "z"][axis]
                ),
            ));
        }
        *r = n as usize;
    }
    let channels = int(20);
    if !matches!(channels, 1 | 3 | 6) {
        return Err(fail(
            20,
            format!("{channels} channels: a grid has 1, 3 or 6"),
        ));
    }
    let channels = channels as usize;
    let corner = |at: usize| Vec3::new(float(at), float(at + 4), float(at + 8));
    let (min, max) = (corner(24), corner(36));
    let finite = |v: Vec3| v.x.is_finite() && v.y.is_finite() && v.z.is_finite();
    if !(finite(min) && finite(max)) || min.x > max.x || min.y > max.y || min.z > max.z {
        return Err(fail(
            24,
            format!(
                "the box ({}, {}, {}) – ({}, {}, {}) must be finite with min ≤ max",
                min.x, min.y, min.z, max.x, max.y, max.z
            ),
        ));
    }
    let count = (res[0] as u64)
        .checked_mul(res[1] as u64)
        .and_then(|c| c.checked_mul(res[2] as u64))
        .and_then(|c| c.checked_mul(channels as u64));
    let count = scotopia_image::check_buffer("a volume grid", count, 4)
        .map_err(|e| fail(8, e.to_string()))?;
    let body = &bytes[HEADER..];
    let have = body.len() / 4;
    if have < count {
        return Err(fail(
            bytes.len(),
            format!(
                "{} × {} × {} cells of {channels} channels need {count} values ({} bytes after the header); the file has {} bytes there (truncated?)",
                res[0],
                res[1],
                res[2],
                count * 4,
                body.len()
            ),
        ));
    }
    if body.len() > count * 4 {
        return Err(fail(
            HEADER + count * 4,
            format!(
                "{} bytes follow the {count} values the header announces",
                body.len() - count * 4
            ),
        ));
    }
    let mut data = Vec::with_capacity(count);
    for (i, b) in body.chunks_exact(4).enumerate() {
        let v = f32::from_le_bytes([b[0], b[1], b[2], b[3]]);
        if !(v.is_finite() && v >= 0.0) {
            let cell = i / channels;
            let (x, y, z) = (
                cell % res[0],
                cell / res[0] % res[1],
                cell / (res[0] * res[1]),
            );
            return Err(fail(
                HEADER + 4 * i,
                format!("value {v} at cell ({x}, {y}, {z}), channel {}: must be finite and not negative", i % channels),
            ));
        }
        data.push(v);
    }
    Grid::new(res, channels, Aabb { min, max }, data).map_err(|m| fail(0, m))
}

#[cfg(test)]
mod tests;
