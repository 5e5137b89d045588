use super::*;

/// A 3 × 2 film with 5 bands after 3 samples per pixel, one of pixel 0's
/// dropped (so the counts agree).
fn sample() -> Checkpoint {
    let mut film = Film::new(3, 2, Some(Bands(5)));
    for (i, p) in film.pixels.iter_mut().enumerate() {
        for _ in 0..if i == 0 { 2 } else { 3 } {
            // A splatted sample's weight is not 1: the checkpoint keeps it.
            p.add_weighted([i as f32, 0.1, -2.5, 1e30], 0.75);
            p.samples += 1;
        }
    }
    for (i, v) in film.spectral.iter_mut().enumerate() {
        *v = i as f64 * 0.37;
    }
    Checkpoint {
        key: 0xdead_beef_1234,
        done: 3,
        counts: SampleCounts {
            dropped: 1,
            dropped_splats: 2,
            rays: 3,
            collapsed: 4,
        },
        film,
    }
}

fn sources() -> Vec<Source> {
    vec![
        Source {
            path: "scene.xml".into(),
            hash: 7,
        },
        Source {
            path: "lamps/é.ies".into(),
            hash: u64::MAX,
        },
    ]
}

fn scratch(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("scotopia-ckpt-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
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
    let dir = scratch("rt");
    let path = dir.join("a.ckpt");
    let c = sample();
    c.write_with(&path, &sources()).unwrap();
    assert_eq!(
        Checkpoint::read_with(&path).unwrap(),
        (c.clone(), sources())
    );
    c.write(&path).unwrap();
    assert_eq!(Checkpoint::read_with(&path).unwrap(), (c, vec![]));
    // Nothing but the checkpoint is left in the folder.
    assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 1);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Every bit of every byte flipped, and every shorter length: all refused,
/// each error naming the checkpoint (decoded from memory, for speed; the
/// command line's tests do the same through files).
#[test]
fn every_flipped_bit_and_every_truncation_is_refused() {
    let dir = scratch("flip");
    let path = dir.join("a.ckpt");
    sample().write_with(&path, &sources()).unwrap();
    let bytes = std::fs::read(&path).unwrap();
    let refused = |b: &[u8], what: &str| match Checkpoint::decode(b, b.len() as u64, "a.ckpt") {
        Ok(_) => panic!("{what}: read as a checkpoint"),
        Err(e) => assert!(e.starts_with("a.ckpt: "), "{what}: {e}"),
    };
    assert!(Checkpoint::decode(&bytes[..], bytes.len() as u64, "a.ckpt").is_ok());
    for at in 0..bytes.len() {
        for bit in 0..8 {
            let mut b = bytes.clone();
            b[at] ^= 1 << bit;
            refused(&b, &format!("byte {at} bit {bit}"));
        }
    }
    for len in 0..bytes.len() {
        refused(&bytes[..len], &format!("cut to {len} bytes"));
    }
    let mut longer = bytes.clone();
    longer.push(0);
    refused(&longer, "a byte more");
    // Through the file too, once.
    std::fs::write(&path, &bytes[..bytes.len() - 3]).unwrap();
    assert!(Checkpoint::read(&path).unwrap_err().contains("a.ckpt"));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn damaged_checkpoints_are_errors_saying_what_is_wrong() {
    let dir = scratch("bad");
    let path = dir.join("a.ckpt");
    sample().write(&path).unwrap();
    let bytes = std::fs::read(&path).unwrap();
    let e = |b: &[u8]| {
        std::fs::write(&path, b).unwrap();
        Checkpoint::read(&path).unwrap_err()
    };
    assert!(e(&bytes[..bytes.len() - 1]).contains("bytes"));
    let mut huge = bytes.clone();
    huge[24..28].copy_from_slice(&u32::MAX.to_le_bytes());
    huge[28..32].copy_from_slice(&u32::MAX.to_le_bytes());
    assert!(e(&huge).contains("film needs"));
    let mut flipped = bytes.clone();
    flipped[100] ^= 4;
    assert!(e(&flipped).contains("checksum"));
    assert!(e(b"hello").contains("not a usable scotopia checkpoint"));
    // The format before checksums: refused, saying what to do.
    let mut old = bytes.clone();
    old[8..12].copy_from_slice(&1u32.to_le_bytes());
    let m = e(&old);
    assert!(m.contains("version 1") && m.contains("delete it"), "{m}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Written whole with a good checksum, but its numbers disagree (as a bug
/// or another program could leave it): refused.
#[test]
fn checkpoints_whose_numbers_disagree_are_refused() {
    let dir = scratch("agree");
    let path = dir.join("a.ckpt");
    let refused = |c: Checkpoint, what: &str| {
        c.write(&path).unwrap();
        let e = Checkpoint::read(&path).unwrap_err();
        assert!(e.contains(what), "{e}");
    };
    let mut c = sample();
    c.done = 2;
    refused(c, "more than the 2 done");
    let mut c = sample();
    c.counts.dropped = 0;
    refused(c, "1 samples are missing");
    let mut c = sample();
    c.film.pixels[4].xyzv[2] = f64::NAN;
    refused(c, "pixel (1, 1)");
    let mut c = sample();
    c.film.spectral[3] = f64::INFINITY;
    refused(c, "band sum");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_fifo_is_no_checkpoint_and_never_waited_on() {
    let dir = scratch("fifo");
    let path = dir.join("a.ckpt");
    let made = std::process::Command::new("mkfifo").arg(&path).status();
    assert!(made.unwrap().success());
    // No one writes or reads the FIFO: waiting on it would hang here.
    let e = Checkpoint::read(&path).unwrap_err();
    assert!(e.contains("a.ckpt") && e.contains("FIFO"), "{e}");
    let e = sample().write(&path).unwrap_err();
    assert!(e.contains("a.ckpt") && e.contains("FIFO"), "{e}");
    std::fs::remove_dir_all(&dir).unwrap();
}
