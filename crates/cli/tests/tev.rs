//! `scotopia render --tev`: a stand-in for tev on a local port reads and
//! decodes what the render sends (independently of the encoder, from
//! tev's protocol: a u32 length that counts itself, a type byte, then
//! the fields), and the render goes on whether or not tev is there.

use std::io::Read;
use std::net::{TcpListener, TcpStream};
use std::path::Path;
use std::process::Command;
use std::thread;

mod common;

use common::scenes;

/// One decoded packet.
#[derive(Debug)]
enum Packet {
    Create {
        focus: bool,
        name: String,
        width: i32,
        height: i32,
        channels: Vec<String>,
    },
    Update {
        name: String,
        channels: Vec<String>,
        rect: [i32; 4],
        /// Per channel, its pixels of `rect`, row by row.
        data: Vec<Vec<f32>>,
    },
}

/// A cursor over one packet's bytes.
struct Fields<'a>(&'a [u8]);

impl Fields<'_> {
    fn take(&mut self, n: usize) -> &[u8] {
        assert!(self.0.len() >= n, "packet too short");
        let (a, b) = self.0.split_at(n);
        self.0 = b;
        a
    }
    fn u8(&mut self) -> u8 {
        self.take(1)[0]
    }
    fn i32(&mut self) -> i32 {
        i32::from_le_bytes(self.take(4).try_into().unwrap())
    }
    fn i64(&mut self) -> i64 {
        i64::from_le_bytes(self.take(8).try_into().unwrap())
    }
    fn f32(&mut self) -> f32 {
        f32::from_le_bytes(self.take(4).try_into().unwrap())
    }
    fn string(&mut self) -> String {
        let end = self.0.iter().position(|&b| b == 0).expect("NUL");
        let s = String::from_utf8(self.0[..end].to_vec()).unwrap();
        self.0 = &self.0[end + 1..];
        s
    }
}

/// Splits a byte stream into packets and decodes them.
fn decode(mut bytes: &[u8]) -> Vec<Packet> {
    let mut out = Vec::new();
    while !bytes.is_empty() {
        assert!(bytes.len() >= 5, "a truncated packet");
        let len = u32::from_le_bytes(bytes[..4].try_into().unwrap()) as usize;
        assert!(
            len >= 5 && len <= bytes.len(),
            "length {len} of {}",
            bytes.len()
        );
        let mut f = Fields(&bytes[4..len]);
        bytes = &bytes[len..];
        match f.u8() {
            4 => {
                let focus = f.u8() == 1;
                let name = f.string();
                let (width, height, n) = (f.i32(), f.i32(), f.i32());
                let channels = (0..n).map(|_| f.string()).collect();
                assert!(f.0.is_empty(), "bytes after a CreateImage");
                out.push(Packet::Create {
                    focus,
                    name,
                    width,
                    height,
                    channels,
                });
            }
            6 => {
                let _focus = f.u8();
                let name = f.string();
                let n = f.i32() as usize;
                let channels: Vec<String> = (0..n).map(|_| f.string()).collect();
                let rect = [f.i32(), f.i32(), f.i32(), f.i32()];
                let offsets: Vec<i64> = (0..n).map(|_| f.i64()).collect();
                let strides: Vec<i64> = (0..n).map(|_| f.i64()).collect();
                let floats: Vec<f32> =
                    std::iter::from_fn(|| (!f.0.is_empty()).then(|| f.f32())).collect();
                let pixels = (rect[2] * rect[3]) as usize;
                let data = (0..n)
                    .map(|c| {
                        (0..pixels)
                            .map(|i| floats[(offsets[c] + i as i64 * strides[c]) as usize])
                            .collect()
                    })
                    .collect();
                out.push(Packet::Update {
                    name,
                    channels,
                    rect,
                    data,
                });
            }
            t => panic!("unexpected packet type {t}"),
        }
    }
    out
}

/// Renders the Cornell box at 16×16, 8 spp, to `dir/name` with `--tev
/// address`, showing the film at every pass: (exit code, stderr).
fn render_to(dir: &Path, name: &str, address: &str) -> (i32, String) {
    let scene = scenes().join("cornell-box.xml");
    let out = Command::new(env!("CARGO_BIN_EXE_scotopia"))
        .env("SCOTOPIA_TEV_EVERY", "0")
        .args([
            "render",
            scene.to_str().unwrap(),
            "-D",
            "res=16",
            "--spp",
            "8",
        ])
        .args(["--tev", address, "-o", dir.join(name).to_str().unwrap()])
        .output()
        .expect("run scotopia");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// Reads one connection to its end.
fn read_all(mut s: TcpStream) -> Vec<u8> {
    let mut bytes = Vec::new();
    s.read_to_end(&mut bytes).unwrap();
    bytes
}

#[test]
fn streams_the_film_and_the_seen_layer() {
    let dir = common::out_dir("tev", "stream");
    let listener = TcpListener::bind("127.0.0.1:0").unwrap();
    let address = listener.local_addr().unwrap().to_string();
    let viewer = thread::spawn(move || read_all(listener.accept().unwrap().0));
    let (code, err) = render_to(&dir, "tmp.exr", &address);
    assert_eq!(code, 0, "{err}");
    assert!(!err.contains("warning: tev"), "{err}");
    let packets = decode(&viewer.join().unwrap());

    // First the image, named as the output, with the film's size.
    let names = ["X", "Y", "Z", "V", "seen.R", "seen.G", "seen.B"];
    match &packets[0] {
        Packet::Create {
            focus,
            name,
            width,
            height,
            channels,
        } => {
            assert!(*focus);
            assert_eq!(name, "tmp.exr");
            assert_eq!((*width, *height), (16, 16));
            assert_eq!(channels, &names);
        }
        p => panic!("first packet {p:?}"),
    }
    assert!(packets[1..]
        .iter()
        .all(|p| matches!(p, Packet::Update { .. })));

    // Then the last value of every pixel of every channel.
    let mut last = vec![vec![f32::NAN; 256]; names.len()];
    let mut updates = 0;
    for p in &packets[1..] {
        let Packet::Update {
            name,
            channels,
            rect: [x, y, w, h],
            data,
        } = p
        else {
            unreachable!()
        };
        assert_eq!(name, "tmp.exr");
        assert!(*x >= 0 && *y >= 0 && x + w <= 16 && y + h <= 16);
        updates += 1;
        for (channel, values) in channels.iter().zip(data) {
            let c = names
                .iter()
                .position(|n| n == channel)
                .expect("a known channel");
            for (i, v) in values.iter().enumerate() {
                let (px, py) = (*x + i as i32 % w, *y + i as i32 / w);
                last[c][(py * 16 + px) as usize] = *v;
            }
        }
    }
    // Every pass (SCOTOPIA_TEV_EVERY=0) and the end: more than one frame
    // unless the newest replaced them all.
    assert!(updates >= 1);
    assert!(
        last.iter().flatten().all(|v| !v.is_nan()),
        "not every pixel of every channel sent"
    );

    // The last X, Y, Z, V are the EXR's, exactly; what is seen is in [0, 1].
    let exr = scotopia_image::read_xyzv(&dir.join("tmp.exr"), Default::default()).unwrap();
    assert_eq!((exr.width, exr.height), (16, 16));
    for (i, p) in exr.pixels.iter().enumerate() {
        for c in 0..4 {
            assert_eq!(
                last[c][i].to_bits(),
                p[c].to_bits(),
                "pixel {i} channel {}",
                names[c]
            );
        }
    }
    assert!(last[4..].iter().flatten().all(|v| (0.0..=1.0).contains(v)));
    assert!(
        last[4..].iter().flatten().any(|&v| v > 0.0),
        "a black seen layer"
    );
}

#[test]
fn renders_on_without_a_viewer() {
    let dir = common::out_dir("tev", "absent");
    // A port that was free a moment ago, with no one listening.
    let address = TcpListener::bind("127.0.0.1:0")
        .unwrap()
        .local_addr()
        .unwrap()
        .to_string();
    let (code, err) = render_to(&dir, "absent.exr", &address);
    assert_eq!(code, 0, "{err}");
    assert!(dir.join("absent.exr").exists());
    let warning = format!("scotopia: warning: tev at {address} is not reachable");
    assert_eq!(err.matches(&warning).count(), 1, "{err}");
    assert!(err.contains("rendering on, will retry"), "{err}");
}

#[test]
fn renders_on_when_the_viewer_hangs_up() {
    let dir = common::out_dir("tev", "hangup");
    let listener = TcpListener::bind("127.0.0.1:0").unwrap();
    let address = listener.local_addr().unwrap().to_string();
    // Takes the first connection, reads a little of it and closes it; any
    // later one (a reconnection) is read to its end.
    let viewer = thread::spawn(move || {
        let (mut first, _) = listener.accept().unwrap();
        let mut some = [0; 16];
        first.read_exact(&mut some).unwrap();
        drop(first);
        listener.set_nonblocking(true).unwrap();
        let mut later = Vec::new();
        for _ in 0..300 {
            match listener.accept() {
                Ok((s, _)) => {
                    s.set_nonblocking(false).unwrap();
                    later.push(read_all(s));
                }
                Err(_) => thread::sleep(std::time::Duration::from_millis(10)),
            }
        }
        later
    });
    let (code, err) = render_to(&dir, "hangup.exr", &address);
    assert_eq!(code, 0, "{err}");
    assert!(dir.join("hangup.exr").exists());
    // A reconnection, if any, starts by creating the image again.
    for bytes in viewer.join().unwrap() {
        if let Some(p) = decode(&bytes).first() {
            assert!(matches!(p, Packet::Create { .. }), "{p:?}");
        }
    }
}

#[test]
fn a_bad_address_is_an_error_before_rendering() {
    let dir = common::out_dir("tev", "bad");
    let (code, err) = render_to(&dir, "bad.exr", "127.0.0.1:notaport");
    assert_ne!(code, 0);
    assert!(err.contains("HOST:PORT"), "{err}");
    assert!(!dir.join("bad.exr").exists());
}
