//! Jakob & Hanika 2019 RGB → spectrum: a coefficient table per colour space,
//! computed offline by `scotopia-rgb2spec` (see `fit`) and embedded here.

pub mod fit;
mod table;

use std::sync::OnceLock;

pub use table::{xy_nodes, z_nodes, SigmoidTable};

use crate::error::ColorError;
use crate::space::RgbSpace;

/// Resolution of the shipped tables (per axis).
pub const TABLE_RES: usize = 64;

/// The embedded table files, in `RgbSpace::ALL` order.
const TABLE_FILES: [&[u8]; 4] = [
    include_bytes!("../../../../../data/rgb2spec/srgb.sig"),
    include_bytes!("../../../../../data/rgb2spec/p3.sig"),
    include_bytes!("../../../../../data/rgb2spec/rec2020.sig"),
    include_bytes!("../../../../../data/rgb2spec/acescg.sig"),
];

/// The table for `space`, decoded on first use.
pub fn table(space: RgbSpace) -> Result<&'static SigmoidTable, ColorError> {
    static TABLES: [OnceLock<Result<SigmoidTable, String>>; 4] = [
        OnceLock::new(),
        OnceLock::new(),
        OnceLock::new(),
        OnceLock::new(),
    ];
    let i = space as usize;
    TABLES[i]
        .get_or_init(|| SigmoidTable::decode(TABLE_FILES[i]).map_err(|e| e.to_string()))
        .as_ref()
        .map_err(|e| ColorError::Table(format!("{}: {e}", space.name())))
}

/// Sigmoid coefficients of the reflectance with colour `rgb` ∈ [0, 1]³ in
/// `space`; black has none (the caller returns a zero spectrum).
pub fn coefficients(rgb: [f32; 3], space: RgbSpace) -> Result<[f32; 3], ColorError> {
    Ok(table(space)?.lookup(rgb))
}
