//! The coefficient table of Jakob & Hanika 2019 and its compact file format.
//!
//! For each of the three "largest component" blocks l, the grid is indexed by
//! z = the largest component (`z_nodes`) and by the other two components
//! divided by z (`xy_nodes`), as in the paper §4.2, with node spacings chosen
//! by measuring the round-trip error (documented at each). Each node holds
//! (c₀, c₁, c₂) of S(c₀t² + c₁t + c₂), t the normalised wavelength.
//!
//! File: `SCOTSIG1`, resolution (u32 LE), then a zlib stream of the z nodes
//! and the coefficients as little-endian f32, byte-plane shuffled (all first
//! bytes, then all second bytes, …) so that the smooth exponents compress.

use std::io::{Read, Write};

use crate::error::ColorError;

const MAGIC: &[u8; 8] = b"SCOTSIG1";

/// Nodes halving the distance to z = 1 at the top of the table.
const TAIL: usize = 6;
/// Where the halving tail starts.
const TAIL_START: f64 = 0.97;

/// The n values of z (the largest component) at the table's nodes.
///
/// Below 0.97: ½(u² + smoothstep(smoothstep(u))) scaled to end at 0.97 —
/// dense near black, where CIELAB is most sensitive. The paper's plain
/// smoothstep(smoothstep(u)) leaves the dark and middle range sparse (mean
/// ΔE₀₀ 0.0104 on the sRGB 32³ round trip, over the 0.01 target).
/// Above 0.97: nodes halving the distance to 1. Bright colours near a
/// component of 1 need reflectances near 1, so their coefficients grow like
/// 1/(1 − z); linear interpolation across one wide top interval gave ΔE₀₀ of
/// 3 for near-whites in Rec.2020. Halving intervals keep each step's growth
/// to about 2×.
pub fn z_nodes(n: usize) -> Vec<f64> {
    let body = n - TAIL;
    let ss = |t: f64| t * t * (3.0 - 2.0 * t);
    let mut z: Vec<f64> = (0..body)
        .map(|k| {
            let u = k as f64 / (body - 1) as f64;
            TAIL_START * 0.5 * (u * u + ss(ss(u)))
        })
        .collect();
    z.extend((1..TAIL).map(|m| 1.0 - (1.0 - TAIL_START) * 0.5f64.powi(m as i32)));
    z.push(1.0);
    z
}

/// The n values of x (a smaller component over the largest) at the nodes:
/// smoothstep(i/(n−1)), dense near 0 (saturated colours, where the
/// coefficients change fastest) and near 1 (near-greys, whose bright end
/// needs reflectances near 1). Against uniform spacing this lowers the
/// sRGB-in-Rec.2020 round trip's worst ΔE₀₀ from 1.9 to 0.35.
pub fn xy_nodes(n: usize) -> Vec<f64> {
    (0..n)
        .map(|i| xy_spacing(i as f64 / (n - 1) as f64))
        .collect()
}

fn xy_spacing(u: f64) -> f64 {
    u * u * (3.0 - 2.0 * u)
}

/// The interval of sorted `nodes` holding `v`, and the position in it.
#[inline]
fn locate(nodes: &[f32], v: f32) -> (usize, f32) {
    let i = (nodes.partition_point(|&x| x <= v).max(1) - 1).min(nodes.len() - 2);
    let f = (v - nodes[i]) / (nodes[i + 1] - nodes[i]);
    (i, f.clamp(0.0, 1.0))
}

/// A Jakob–Hanika coefficient table at resolution `res`³ × 3 blocks.
#[derive(Debug, Clone, PartialEq)]
pub struct SigmoidTable {
    res: usize,
    z_nodes: Vec<f32>,
    xy_nodes: Vec<f32>,
    coeffs: Vec<[f32; 3]>,
}

impl SigmoidTable {
    pub fn empty(res: usize, z_nodes: Vec<f32>) -> Self {
        Self {
            res,
            z_nodes,
            xy_nodes: xy_nodes(res).iter().map(|&x| x as f32).collect(),
            coeffs: vec![[0.0; 3]; 3 * res * res * res],
        }
    }

    pub fn resolution(&self) -> usize {
        self.res
    }

    #[inline]
    fn index(&self, l: usize, k: usize, j: usize, i: usize) -> usize {
        ((l * self.res + k) * self.res + j) * self.res + i
    }

    pub fn set(&mut self, l: usize, k: usize, j: usize, i: usize, c: [f32; 3]) {
        let idx = self.index(l, k, j, i);
        self.coeffs[idx] = c;
    }

    pub fn get(&self, l: usize, k: usize, j: usize, i: usize) -> [f32; 3] {
        self.coeffs[self.index(l, k, j, i)]
    }

    /// z of node k.
    pub fn z(&self, k: usize) -> f32 {
        self.z_nodes[k]
    }

    /// Coefficients for a reflectance RGB in [0, 1]³ (not all zero), by
    /// trilinear interpolation between the eight surrounding nodes.
    #[inline]
    pub fn lookup(&self, rgb: [f32; 3]) -> [f32; 3] {
        // Which component is largest selects the block.
        let l = if rgb[0] >= rgb[1] && rgb[0] >= rgb[2] {
            0
        } else if rgb[1] >= rgb[2] {
            1
        } else {
            2
        };
        let z = rgb[l];
        let (xi, fx) = locate(&self.xy_nodes, rgb[(l + 1) % 3] / z);
        let (yi, fy) = locate(&self.xy_nodes, rgb[(l + 2) % 3] / z);
        let (zi, fz) = locate(&self.z_nodes, z);
        let mut out = [0.0f32; 3];
        for (dz, wz) in [(0, 1.0 - fz), (1, fz)] {
            for (dy, wy) in [(0, 1.0 - fy), (1, fy)] {
                for (dx, wx) in [(0, 1.0 - fx), (1, fx)] {
                    let w = wz * wy * wx;
                    let c = self.coeffs[self.index(l, zi + dz, yi + dy, xi + dx)];
                    for k in 0..3 {
                        out[k] += w * c[k];
                    }
                }
            }
        }
        out
    }

    /// The compact file form (see the module comment).
    pub fn encode(&self) -> Vec<u8> {
        let floats: Vec<f32> = self
            .z_nodes
            .iter()
            .copied()
            .chain(self.coeffs.iter().flatten().copied())
            .collect();
        let n = floats.len();
        let mut shuffled = vec![0u8; n * 4];
        for (i, f) in floats.iter().enumerate() {
            for (b, byte) in f.to_le_bytes().iter().enumerate() {
                shuffled[b * n + i] = *byte;
            }
        }
        let mut out = Vec::new();
        out.extend_from_slice(MAGIC);
        out.extend_from_slice(&(self.res as u32).to_le_bytes());
        let mut enc = flate2::write::ZlibEncoder::new(out, flate2::Compression::best());
        // Writing to a Vec cannot fail.
        enc.write_all(&shuffled).expect("in-memory write");
        enc.finish().expect("in-memory write")
    }

    /// Reads the compact file form.
    pub fn decode(bytes: &[u8]) -> Result<Self, ColorError> {
        let bad = |m: &str| ColorError::Table(m.to_string());
        if bytes.len() < 12 || &bytes[..8] != MAGIC {
            return Err(bad("not a scotopia coefficient table (run `make tables`)"));
        }
        let res = u32::from_le_bytes([bytes[8], bytes[9], bytes[10], bytes[11]]) as usize;
        if !(2..=1024).contains(&res) {
            return Err(bad("implausible resolution"));
        }
        let n = res + 3 * 3 * res * res * res;
        let mut shuffled = Vec::with_capacity(n * 4);
        flate2::read::ZlibDecoder::new(&bytes[12..])
            .read_to_end(&mut shuffled)
            .map_err(|e| bad(&format!("corrupt data: {e}")))?;
        if shuffled.len() != n * 4 {
            return Err(bad("truncated data"));
        }
        let floats: Vec<f32> = (0..n)
            .map(|i| f32::from_le_bytes(std::array::from_fn(|b| shuffled[b * n + i])))
            .collect();
        if floats.iter().any(|f| !f.is_finite()) {
            return Err(bad("non-finite coefficient"));
        }
        let mut table = Self::empty(res, floats[..res].to_vec());
        table.coeffs = floats[res..]
            .chunks_exact(3)
            .map(|c| [c[0], c[1], c[2]])
            .collect();
        Ok(table)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn encode_decode_round_trip() {
        let res = 12;
        let mut t = SigmoidTable::empty(res, z_nodes(12).iter().map(|&z| z as f32).collect());
        for l in 0..3 {
            for k in 0..res {
                t.set(l, k, 1, 2, [l as f32, k as f32 * 0.5, -1.25]);
            }
        }
        let bytes = t.encode();
        assert_eq!(SigmoidTable::decode(&bytes).unwrap(), t);
        assert!(SigmoidTable::decode(b"").is_err());
        assert!(SigmoidTable::decode(&bytes[..bytes.len() - 10]).is_err());
    }

    #[test]
    fn lookup_at_a_node_returns_it() {
        let res = 12;
        let mut t = SigmoidTable::empty(res, z_nodes(12).iter().map(|&z| z as f32).collect());
        t.set(1, 11, 0, 11, [1.0, 2.0, 3.0]);
        // Block 1 (green largest) at z = green = 1; i indexes blue/green = 1,
        // j indexes red/green = 0.
        assert_eq!(t.lookup([0.0, 1.0, 1.0]), [1.0, 2.0, 3.0]);
        // Halfway in x between nodes 10 and 11 is half the value.
        let x = xy_nodes(12);
        let half = t.lookup([0.0, 1.0, (0.5 * (x[10] + x[11])) as f32]);
        assert!((half[2] - 1.5).abs() < 1e-5, "{half:?}");
    }
}
