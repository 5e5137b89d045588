//! The connection to tev: a background thread that takes the newest
//! frame, runs the vision pipeline on it and sends it, connecting and
//! reconnecting as the viewer comes and goes. Nothing here waits the
//! render or fails it.

use std::io::Write;
use std::net::{SocketAddr, TcpStream, ToSocketAddrs};
use std::sync::{Arc, Condvar, Mutex};
use std::thread::JoinHandle;
use std::time::Duration;

use scotopia_render::film::Film;
use scotopia_vision::DisplayParams;

use super::protocol::{create_image, update_image, Rect};

/// tev's default port, where it listens unless told otherwise.
pub const DEFAULT: &str = "127.0.0.1:14158";
/// How long a connection attempt may take.
const CONNECT_TIMEOUT: Duration = Duration::from_millis(200);
/// How long one write may block before the connection is given up.
const WRITE_TIMEOUT: Duration = Duration::from_secs(2);
/// The floats per UpdateImage packet, about 4 MiB (tev grows its 1 MiB
/// receive buffer to fit a packet).
const FLOATS_PER_PACKET: usize = 1 << 20;

/// The film's channels, as in the EXR, then what the eye sees.
const CHANNELS: [&str; 7] = ["X", "Y", "Z", "V", "seen.R", "seen.G", "seen.B"];

/// Where tev listens: `HOST:PORT` as given, and what it resolved to.
#[derive(Clone, Debug)]
pub struct Address {
    pub text: String,
    addrs: Vec<SocketAddr>,
}

/// Parses and resolves `HOST:PORT` (clap's value parser for `--tev`).
pub fn address(text: &str) -> Result<Address, String> {
    let bad = |why: &str| format!("{text}: {why}; give HOST:PORT, e.g. {DEFAULT}");
    let (host, port) = text.rsplit_once(':').ok_or_else(|| bad("no port"))?;
    let port: u16 = port.parse().map_err(|_| bad("the port is not 0–65535"))?;
    let host = host.trim_start_matches('[').trim_end_matches(']');
    if host.is_empty() {
        return Err(bad("no host"));
    }
    let addrs: Vec<SocketAddr> = (host, port)
        .to_socket_addrs()
        .map_err(|e| bad(&format!("cannot resolve the host ({e})")))?
        .collect();
    if addrs.is_empty() {
        return Err(bad("the host resolves to no address"));
    }
    Ok(Address {
        text: text.to_string(),
        addrs,
    })
}

/// The image tev shows: its name and size.
pub struct Image {
    pub name: String,
    pub width: u32,
    pub height: u32,
}

/// The newest frame not yet sent, whether the render has ended, and
/// whether the sender has.
#[derive(Default)]
struct Slot {
    frame: Option<Vec<[f32; 4]>>,
    closed: bool,
    finished: bool,
}

/// What the render and the sender thread share: a channel of capacity 1
/// in which a newer frame replaces a stale one.
#[derive(Default)]
struct Shared {
    slot: Mutex<Slot>,
    ready: Condvar,
}

impl Shared {
    fn close(&self) {
        if let Ok(mut slot) = self.slot.lock() {
            slot.closed = true;
        }
        self.ready.notify_all();
    }

    fn set_finished(&self) {
        if let Ok(mut slot) = self.slot.lock() {
            slot.finished = true;
        }
        self.ready.notify_all();
    }
}

/// A live view of a render in tev.
pub struct Viewer {
    shared: Arc<Shared>,
    thread: Option<JoinHandle<()>>,
}

impl Viewer {
    /// Starts the sender thread; `vision`: the pipeline's parameters for
    /// the seen layer (none: X, Y, Z, V only).
    pub fn start(address: Address, image: Image, vision: Option<DisplayParams>) -> Viewer {
        let shared = Arc::new(Shared::default());
        let theirs = shared.clone();
        let thread = std::thread::Builder::new()
            .name("tev".into())
            .spawn(move || {
                Sender {
                    address,
                    image,
                    vision,
                    stream: None,
                    said_away: false,
                }
                .run(&theirs);
                theirs.set_finished();
            })
            .ok();
        if thread.is_none() {
            eprintln!("scotopia: warning: cannot start the tev thread; rendering on without it");
        }
        Viewer { shared, thread }
    }

    /// Called on the rendering thread: copies the film's means and hands
    /// them over, replacing a frame not yet sent. Never waits for tev.
    pub fn see(&self, film: &Film) {
        if self.thread.is_none() {
            return;
        }
        let xyzv = film.xyzv();
        if let Ok(mut slot) = self.shared.slot.lock() {
            slot.frame = Some(xyzv);
        }
        self.shared.ready.notify_all();
    }

    /// The render is over: lets the last frame go out, waiting for it at
    /// most `bound`.
    pub fn finish(mut self, bound: Duration) {
        self.shared.close();
        if let Some(thread) = self.thread.take() {
            let finished = self.shared.slot.lock().ok().and_then(|slot| {
                let waited = self
                    .shared
                    .ready
                    .wait_timeout_while(slot, bound, |s| !s.finished);
                waited.ok().map(|(slot, _)| slot.finished)
            });
            if finished == Some(true) {
                let _ = thread.join();
            } else {
                eprintln!("scotopia: warning: tev did not take the last frame in time");
            }
        }
    }
}

impl Drop for Viewer {
    fn drop(&mut self) {
        // Without `finish` (an error): the thread ends after its frame.
        self.shared.close();
    }
}

/// The sender thread's state.
struct Sender {
    address: Address,
    image: Image,
    vision: Option<DisplayParams>,
    stream: Option<TcpStream>,
    /// Whether the user was told that tev is away since it last was there.
    said_away: bool,
}

impl Sender {
    fn run(&mut self, shared: &Shared) {
        while let Some(frame) = next_frame(shared) {
            if self.stream.is_none() && !self.connect() {
                continue;
            }
            let packets = self.packets(frame);
            if let Err(e) = self.send(&packets) {
                self.stream = None;
                eprintln!(
                    "scotopia: warning: lost tev at {} ({e}); rendering on, will retry",
                    self.address.text
                );
                self.said_away = true;
            }
        }
    }

    /// Connects and creates the image (on every new connection: tev may
    /// have been restarted). False, with one warning, when tev is away.
    fn connect(&mut self) -> bool {
        match open(&self.address.addrs).and_then(|mut s| {
            let names = self.channels();
            let im = &self.image;
            s.write_all(&create_image(&im.name, im.width, im.height, names))?;
            Ok(s)
        }) {
            Ok(s) => {
                self.stream = Some(s);
                self.said_away = false;
                true
            }
            Err(e) => {
                if !self.said_away {
                    eprintln!(
                        "scotopia: warning: tev at {} is not reachable ({e}); rendering on, will retry",
                        self.address.text
                    );
                    self.said_away = true;
                }
                false
            }
        }
    }

    fn channels(&self) -> &'static [&'static str] {
        if self.vision.is_some() {
            &CHANNELS
        } else {
            &CHANNELS[..4]
        }
    }

    fn send(&mut self, packets: &[Vec<u8>]) -> std::io::Result<()> {
        let Some(stream) = &mut self.stream else {
            return Ok(());
        };
        for p in packets {
            stream.write_all(p)?;
        }
        stream.flush()
    }

    /// A frame as UpdateImage packets: bands of whole rows, each with
    /// every channel.
    fn packets(&self, xyzv: Vec<[f32; 4]>) -> Vec<Vec<u8>> {
        let (w, h) = (self.image.width as usize, self.image.height as usize);
        let seen = self.vision.as_ref().map(|p| seen_rgb(&xyzv, w, h, p));
        let names = self.channels();
        let mut planes: Vec<Vec<f32>> = (0..4)
            .map(|c| xyzv.iter().map(|p| p[c]).collect())
            .collect();
        if let Some(rgb) = &seen {
            planes.extend((0..3).map(|c| rgb.iter().map(|p| p[c]).collect()));
        }
        let rows = (FLOATS_PER_PACKET / (w * names.len()).max(1)).clamp(1, h.max(1));
        (0..h)
            .step_by(rows)
            .map(|y| {
                let n = rows.min(h - y);
                let band: Vec<&[f32]> = planes.iter().map(|p| &p[y * w..(y + n) * w]).collect();
                let rect = Rect {
                    x: 0,
                    y: y as u32,
                    width: w as u32,
                    height: n as u32,
                };
                update_image(&self.image.name, names, rect, &band)
            })
            .collect()
    }
}

/// Waits for a frame; none once the render has ended and all are sent.
fn next_frame(shared: &Shared) -> Option<Vec<[f32; 4]>> {
    let mut slot = shared.slot.lock().ok()?;
    loop {
        if let Some(frame) = slot.frame.take() {
            return Some(frame);
        }
        if slot.closed {
            return None;
        }
        slot = shared.ready.wait(slot).ok()?;
    }
}

/// A connection to the first address that answers in time.
fn open(addrs: &[SocketAddr]) -> std::io::Result<TcpStream> {
    let mut last = std::io::Error::new(std::io::ErrorKind::NotFound, "no address");
    for a in addrs {
        match TcpStream::connect_timeout(a, CONNECT_TIMEOUT) {
            Ok(s) => {
                s.set_write_timeout(Some(WRITE_TIMEOUT))?;
                return Ok(s);
            }
            Err(e) => last = e,
        }
    }
    Err(last)
}

/// What the eye sees, as linear display RGB in [0, 1] for tev, which
/// applies the sRGB curve itself when it shows an image. The pipeline's
/// output is already linear and display-referred (1 = the display's
/// peak, in the chosen gamut), so it is only clamped to what the display
/// shows, as the PNG encoder does; a non-finite value becomes 0.
pub fn seen_rgb(xyzv: &[[f32; 4]], w: usize, h: usize, p: &DisplayParams) -> Vec<[f32; 3]> {
    let shown = scotopia_vision::display(xyzv, w, h, p);
    shown
        .rgb
        .into_iter()
        .map(|c| {
            c.map(|v| {
                if v.is_finite() {
                    v.clamp(0.0, 1.0)
                } else {
                    0.0
                }
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn addresses() {
        let a = address("127.0.0.1:14158").unwrap();
        assert_eq!(a.addrs, vec!["127.0.0.1:14158".parse().unwrap()]);
        assert_eq!(
            address("[::1]:9").unwrap().addrs,
            vec!["[::1]:9".parse().unwrap()]
        );
        assert!(address("localhost:80").is_ok());
        for bad in [
            "14158",
            "127.0.0.1",
            "127.0.0.1:",
            ":14158",
            "127.0.0.1:70000",
            "h:x",
        ] {
            assert!(address(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn the_seen_layer_is_in_range() {
        let px = vec![[10.0, 12.0, 9.0, 20.0]; 64];
        let rgb = seen_rgb(&px, 8, 8, &DisplayParams::default());
        assert!(rgb.iter().flatten().all(|v| (0.0..=1.0).contains(v)));
    }
}
