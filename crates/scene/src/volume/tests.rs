use super::*;

/// A `.vol` file of `res` cells and `channels` holding `values`.
fn vol(res: [i32; 3], channels: i32, bbox: [f32; 6], values: &[f32]) -> Vec<u8> {
    let mut b = b"VOL\x03".to_vec();
    b.extend(1i32.to_le_bytes());
    for v in res.into_iter().chain([channels]) {
        b.extend(v.to_le_bytes());
    }
    for v in bbox.into_iter().chain(values.iter().copied()) {
        b.extend(v.to_le_bytes());
    }
    b
}

const BOX: [f32; 6] = [-1.0, 0.0, 0.0, 1.0, 2.0, 0.5];

#[test]
fn a_grid_is_read_in_mitsubas_order() {
    // 3 × 2 × 2 cells, one channel: value = x + 10 y + 100 z.
    let values: Vec<f32> = (0..12)
        .map(|i| (i % 3 + 10 * (i / 3 % 2) + 100 * (i / 6)) as f32)
        .collect();
    let g = parse_vol(&vol([3, 2, 2], 1, BOX, &values), "g.vol").unwrap();
    assert_eq!(g.resolution(), [3, 2, 2]);
    assert_eq!(g.channels(), 1);
    assert_eq!(g.bounds.min, Vec3::new(-1.0, 0.0, 0.0));
    assert_eq!(g.bounds.max, Vec3::new(1.0, 2.0, 0.5));
    // The centre of cell (2, 1, 0) holds 2 + 10.
    assert_eq!(g.lookup(Vec3::new(2.5 / 3.0, 0.75, 0.25), 0), 12.0);
    assert_eq!(g.max(0), 112.0);
}

#[test]
fn every_fault_is_an_error_naming_the_file_and_byte() {
    let good = vol([2, 2, 1], 3, BOX, &[0.5; 12]);
    assert!(parse_vol(&good, "v.vol").is_ok());
    let with = |at: usize, bytes: &[u8]| {
        let mut b = good.clone();
        b[at..at + bytes.len()].copy_from_slice(bytes);
        b
    };
    let cases: Vec<(Vec<u8>, &str, &str)> = vec![
        (good[..30].to_vec(), "byte 30", "inside its 48-byte header"),
        (with(0, b"VOX"), "byte 0", "does not start with 'VOL'"),
        (with(3, &[2]), "byte 3", "version 2"),
        (with(4, &2i32.to_le_bytes()), "byte 4", "encoding 2"),
        (with(12, &0i32.to_le_bytes()), "byte 12", "0 cells along y"),
        (
            with(16, &(-4i32).to_le_bytes()),
            "byte 16",
            "-4 cells along z",
        ),
        (with(20, &4i32.to_le_bytes()), "byte 20", "4 channels"),
        (
            with(24, &f32::NAN.to_le_bytes()),
            "byte 24",
            "must be finite",
        ),
        (with(36, &(-2.0f32).to_le_bytes()), "byte 24", "min ≤ max"),
        (good[..good.len() - 6].to_vec(), "byte 90", "truncated"),
        (
            [good.clone(), vec![0; 8]].concat(),
            "byte 96",
            "8 bytes follow",
        ),
        (
            with(48 + 4 * 7, &(-0.1f32).to_le_bytes()),
            "byte 76",
            "cell (0, 1, 0), channel 1",
        ),
        (
            with(48, &f32::INFINITY.to_le_bytes()),
            "byte 48",
            "must be finite",
        ),
        (with(8, &i32::MAX.to_le_bytes()), "v.vol: byte", ""),
    ];
    for (bytes, at, what) in cases {
        let e = parse_vol(&bytes, "v.vol").unwrap_err().to_string();
        assert!(
            e.starts_with("v.vol: ") && e.contains(at) && e.contains(what),
            "{at} {what}: {e}"
        );
    }
}

#[test]
fn mutated_files_never_panic() {
    // Seeded byte flips, truncations and extensions of a valid file.
    let good = vol([3, 2, 2], 6, BOX, &[0.25; 72]);
    let mut state = 0x5eed_u64;
    let mut next = || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 33) as usize
    };
    for _ in 0..5000 {
        let mut b = good.clone();
        match next() % 3 {
            0 => {
                let i = next() % b.len();
                b[i] ^= 1 << (next() % 8);
            }
            1 => b.truncate(next() % b.len()),
            _ => b.extend(std::iter::repeat_n(0xff, next() % 9)),
        }
        let _ = parse_vol(&b, "m.vol");
    }
}
