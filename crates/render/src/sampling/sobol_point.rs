//! Points of the scrambled Sobol sequence: the first 4 Sobol dimensions
//! (Joe & Kuo direction numbers, byte tables), the Laine–Karras and
//! hash-based Owen scrambles and the seed hashes of Burley 2020, and
//! `set_point`, one 4-dimensional set of one sample of one pixel. Below the
//! sampler (`sobol`) and its wide forms (`sobol_batch`, `sobol_pair`),
//! which all give these numbers bit for bit.

/// Sobol direction numbers of the first 4 dimensions, bit-reversed into
/// generator matrices (Joe & Kuo 2008: primitive polynomials 1, x + 1,
/// x² + x + 1, x³ + x + 1 with m = (1), (1, 3), (1, 3, 1)).
const fn directions() -> [[u32; 32]; 4] {
    let mut v = [[0u32; 32]; 4];
    let mut k = 0;
    while k < 32 {
        v[0][k] = 1 << (31 - k);
        k += 1;
    }
    // (degree s, coefficients a (without the leading and trailing 1), m).
    let polys: [(usize, u32, [u32; 3]); 3] =
        [(1, 0, [1, 0, 0]), (2, 1, [1, 3, 0]), (3, 1, [1, 3, 1])];
    let mut d = 0;
    while d < 3 {
        let (s, a, m) = polys[d];
        let dir = &mut v[d + 1];
        let mut k = 0;
        while k < s {
            dir[k] = m[k] << (31 - k);
            k += 1;
        }
        while k < 32 {
            let mut x = dir[k - s] ^ (dir[k - s] >> s);
            let mut j = 1;
            while j < s {
                if (a >> (s - 1 - j)) & 1 == 1 {
                    x ^= dir[k - j];
                }
                j += 1;
            }
            dir[k] = x;
            k += 1;
        }
        d += 1;
    }
    v
}

pub(super) const DIRECTIONS: [[u32; 32]; 4] = directions();

/// Per dimension and index byte, the XOR of the direction numbers of every
/// 8-bit pattern: a coordinate is then four lookups, not a loop over bits
/// (the shuffled indices of padded sampling use all 32). `reversed` builds
/// the bit-reversed form: indexed by the bytes of the reversed index, giving
/// the reversed coordinate. Owen scrambling works on reversed bits (Burley
/// 2020, §3), so the sampler stays in that domain and reverses once per
/// coordinate instead of three times.
const fn byte_tables(reversed: bool) -> [[[u32; 256]; 4]; 4] {
    let mut t = [[[0u32; 256]; 4]; 4];
    let mut d = 0;
    while d < 4 {
        let mut b = 0;
        while b < 4 {
            let mut pattern = 0;
            while pattern < 256 {
                let mut x = 0u32;
                let mut bit = 0;
                while bit < 8 {
                    if (pattern >> bit) & 1 == 1 {
                        x ^= if reversed {
                            DIRECTIONS[d][31 - (b * 8 + bit)].reverse_bits()
                        } else {
                            DIRECTIONS[d][b * 8 + bit]
                        };
                    }
                    bit += 1;
                }
                t[d][b][pattern] = x;
                pattern += 1;
            }
            b += 1;
        }
        d += 1;
    }
    t
}

static BYTE_TABLES: [[[u32; 256]; 4]; 4] = byte_tables(false);
static REVERSED_TABLES: [[[u32; 256]; 4]; 4] = byte_tables(true);

/// The XOR of one table entry per byte of `x`.
#[inline]
fn lookup(t: &[[u32; 256]; 4], x: u32) -> u32 {
    t[0][(x & 0xff) as usize]
        ^ t[1][((x >> 8) & 0xff) as usize]
        ^ t[2][((x >> 16) & 0xff) as usize]
        ^ t[3][(x >> 24) as usize]
}

/// `sobol(index, dim).reverse_bits()` from `index.reverse_bits()`.
#[inline]
pub(super) fn sobol_reversed(index_rev: u32, dim: usize) -> u32 {
    lookup(&REVERSED_TABLES[dim], index_rev)
}

/// The `index`-th point's coordinate in Sobol dimension `dim` < 4, as 32 bits.
#[inline]
pub fn sobol(index: u32, dim: usize) -> u32 {
    lookup(&BYTE_TABLES[dim], index)
}

/// The multipliers of [`laine_karras`] (Burley 2020, listing 3).
pub(super) const LK_MULS: [u32; 4] = [0x6c50_b47c, 0xb82f_1e52, 0xc7af_e638, 0x8d22_f6e6];

/// Laine & Karras's hash permutation as Burley 2020 (listing 3) improves it:
/// each bit is flipped depending only on the bits below it.
#[inline]
pub(super) fn laine_karras(mut x: u32, seed: u32) -> u32 {
    x = x.wrapping_add(seed);
    for m in LK_MULS {
        x ^= x.wrapping_mul(m);
    }
    x
}

/// Nested uniform (Owen) scramble of a 32-bit fraction: each bit flipped
/// depending on the bits above it (Burley 2020, listing 4).
#[inline]
pub fn owen_scramble(x: u32, seed: u32) -> u32 {
    laine_karras(x.reverse_bits(), seed).reverse_bits()
}

/// The constants of [`hash`] (murmur3's: Appleby 2011).
pub(super) mod murmur {
    pub const INIT: u32 = 0x9e37_79b9;
    pub const C1: u32 = 0xcc9e_2d51;
    pub const C2: u32 = 0x1b87_3593;
    pub const N: u32 = 0xe654_6b64;
    pub const F1: u32 = 0x85eb_ca6b;
    pub const F2: u32 = 0xc2b2_ae35;
}

/// A 32-bit hash of several words (a murmur3-style finaliser per word).
#[inline]
pub fn hash(words: &[u32]) -> u32 {
    let mut h: u32 = murmur::INIT;
    for &w in words {
        let mut k = w.wrapping_mul(murmur::C1);
        k = k.rotate_left(15).wrapping_mul(murmur::C2);
        h ^= k;
        h = h.rotate_left(13).wrapping_mul(5).wrapping_add(murmur::N);
    }
    h ^= h >> 16;
    h = h.wrapping_mul(murmur::F1);
    h ^= h >> 13;
    h = h.wrapping_mul(murmur::F2);
    h ^ (h >> 16)
}

/// The multipliers of [`mix`] (Wellons's lowbias32).
pub(super) const MIX_MULS: [u32; 2] = [0x7feb_352d, 0x846c_a68b];

/// A fast 32-bit integer mix (Wellons's "lowbias32", from his hash
/// prospector search), for per-set and per-dimension scramble seeds.
#[inline]
pub(super) fn mix(mut x: u32) -> u32 {
    x ^= x >> 16;
    x = x.wrapping_mul(MIX_MULS[0]);
    x ^= x >> 15;
    x = x.wrapping_mul(MIX_MULS[1]);
    x ^ (x >> 16)
}

/// What a set's number is multiplied by before it is mixed into the pixel
/// key, and what a dimension's number (from 1) is multiplied by before it
/// is added to the set's key.
pub(super) const SET_MUL: u32 = 0x9e37_79b9;
pub(super) const DIM_MUL: u32 = 0x85eb_ca6b;

/// 32 bits to [0, 1), never rounding up to 1.
#[inline]
fn to_unit(x: u32) -> f32 {
    ((x >> 8) as f32) * UNIT
}

/// 2⁻²⁴: the top 24 bits of a word, as a fraction.
pub(super) const UNIT: f32 = 1.0 / (1u32 << 24) as f32;

/// The root of every scramble seed of `pixel`'s samples under `seed`.
#[inline]
pub fn pixel_key(seed: u32, pixel: [u32; 2]) -> u32 {
    hash(&[seed, pixel[0], pixel[1]])
}

/// The 4 coordinates of 4-dimensional set `set` of the sample whose index,
/// bit-reversed, is `index_rev`, in the pixel with key `pixel_key`: what
/// [`Sampler`] draws, and the reference of the batched form
/// ([`super::sobol_batch`]).
#[inline]
pub fn set_point(pixel_key: u32, index_rev: u32, set: u32) -> [f32; 4] {
    let key = mix(pixel_key ^ set.wrapping_mul(SET_MUL));
    // owen_scramble(index, key), reversed; then each coordinate's own
    // scramble, reversed back once.
    let index_rev = laine_karras(index_rev, key);
    std::array::from_fn(|d| {
        let seed = mix(key.wrapping_add((d as u32 + 1).wrapping_mul(DIM_MUL)));
        to_unit(laine_karras(sobol_reversed(index_rev, d), seed).reverse_bits())
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Whether points form a (0, m, 2)-net: every elementary interval of
    /// area 2^−m holds exactly one point.
    fn is_net(points: &[[u32; 2]], m: u32) -> bool {
        (0..=m).all(|bits_x| {
            let bits_y = m - bits_x;
            let mut seen = vec![false; 1 << m];
            points.iter().all(|p| {
                let cell =
                    ((p[0] as u64 >> (32 - bits_x)) << bits_y) | (p[1] as u64 >> (32 - bits_y));
                !std::mem::replace(&mut seen[cell as usize], true)
            })
        })
    }

    #[test]
    fn sobol_is_stratified_and_scrambling_keeps_it() {
        let m = 8;
        let n = 1u32 << m;
        // The first two dimensions form a (0, 2)-sequence.
        let pts: Vec<[u32; 2]> = (0..n).map(|i| [sobol(i, 0), sobol(i, 1)]).collect();
        assert!(is_net(&pts, m));
        let scrambled: Vec<[u32; 2]> = pts
            .iter()
            .map(|p| [owen_scramble(p[0], 17), owen_scramble(p[1], 99)])
            .collect();
        assert!(is_net(&scrambled, m));
        // A random-looking set is not a net (the check can fail).
        let noise: Vec<[u32; 2]> = (0..n).map(|i| [hash(&[i]), hash(&[i, 1])]).collect();
        assert!(!is_net(&noise, m));
        // Every dimension alone puts one point in each 1/n interval.
        for d in 0..4 {
            let mut cells: Vec<u32> = (0..n)
                .map(|i| owen_scramble(sobol(i, d), 5) >> (32 - m))
                .collect();
            cells.sort_unstable();
            assert!(
                cells.iter().enumerate().all(|(i, &c)| c == i as u32),
                "dim {d}"
            );
        }
        // Known values of the second dimension: 0, ½, ¾, ¼.
        let v: Vec<u32> = (0..4).map(|i| sobol(i, 1)).collect();
        assert_eq!(v, [0, 1 << 31, 3 << 30, 1 << 30]);
    }

    #[test]
    fn reversed_tables_match_the_plain_ones() {
        for index in [0u32, 1, 2, 3, 255, 256, 0xdead_beef, u32::MAX, 0x0123_4567] {
            for dim in 0..4 {
                assert_eq!(
                    sobol_reversed(index.reverse_bits(), dim),
                    sobol(index, dim).reverse_bits()
                );
            }
        }
    }

    #[test]
    fn byte_tables_match_the_bitwise_definition() {
        for index in [0u32, 1, 2, 3, 255, 256, 0xdead_beef, u32::MAX] {
            for (dim, dirs) in DIRECTIONS.iter().enumerate() {
                let want = dirs
                    .iter()
                    .enumerate()
                    .filter(|(k, _)| (index >> k) & 1 == 1)
                    .fold(0, |x, (_, v)| x ^ v);
                assert_eq!(sobol(index, dim), want);
            }
        }
    }

    #[test]
    fn every_pair_of_dimensions_is_a_low_t_net() {
        // 2^10 points of any two of the four dimensions form a (t, 10, 2)-net
        // with t ≤ 2 (t = 0 for the first pair): wrong direction numbers
        // give far worse.
        let m = 10u32;
        for (a, b) in [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)] {
            let pts: Vec<[u32; 2]> = (0..1u32 << m).map(|i| [sobol(i, a), sobol(i, b)]).collect();
            let t = (0..=m)
                .find(|&t| {
                    (0..=m - t).all(|bx| {
                        let by = m - t - bx;
                        let mut count = vec![0u32; 1 << (m - t)];
                        for p in &pts {
                            count[(((p[0] as u64 >> (32 - bx)) << by) | (p[1] as u64 >> (32 - by)))
                                as usize] += 1;
                        }
                        count.iter().all(|&c| c == 1 << t)
                    })
                })
                .unwrap();
            assert!(
                t <= if (a, b) == (0, 1) { 0 } else { 2 },
                "dims {a}, {b}: t = {t}"
            );
        }
    }
}
