//! A running `scotopia view` spoken to over plain sockets: shared by
//! view.rs (the routes) and view_guard.rs (who may ask what, and clients
//! that misbehave).

#![allow(dead_code)]

use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::process::{Child, Command, Stdio};
use std::sync::mpsc;
use std::time::{Duration, Instant};

/// How long a test waits for an answer before calling the server stuck.
pub const PATIENCE: Duration = Duration::from_secs(10);

/// A running `scotopia view` and its port.
pub struct Viewer {
    pub child: Child,
    pub port: u16,
    pub stderr: mpsc::Receiver<String>,
}

/// A reply: (status code, head in lower case, body).
pub type Answer = (u16, String, Vec<u8>);

impl Viewer {
    // The child is waited for in `Drop`.
    #[allow(clippy::zombie_processes)]
    pub fn start(args: &[&str]) -> Self {
        let mut child = Command::new(env!("CARGO_BIN_EXE_scotopia"))
            .arg("view")
            .args(args)
            .args(["--no-open", "--port", "0"])
            .stderr(Stdio::piped())
            .spawn()
            .expect("run scotopia view");
        let (tx, stderr) = mpsc::channel();
        let pipe = child.stderr.take().unwrap();
        std::thread::spawn(move || {
            for line in BufReader::new(pipe).lines().map_while(Result::ok) {
                let _ = tx.send(line);
            }
        });
        let deadline = Instant::now() + Duration::from_secs(60);
        loop {
            let line = stderr
                .recv_timeout(deadline.saturating_duration_since(Instant::now()))
                .expect("the viewer says where it listens");
            if let Some(rest) = line.split("view at http://127.0.0.1:").nth(1) {
                let port = rest.split('/').next().unwrap().parse().unwrap();
                return Self {
                    child,
                    port,
                    stderr,
                };
            }
        }
    }

    /// The served Host.
    pub fn host(&self) -> String {
        format!("127.0.0.1:{}", self.port)
    }

    /// A connection that gives up after [`PATIENCE`].
    pub fn connect(&self) -> TcpStream {
        let s = TcpStream::connect(("127.0.0.1", self.port)).unwrap();
        s.set_read_timeout(Some(PATIENCE)).unwrap();
        s.set_write_timeout(Some(PATIENCE)).unwrap();
        s
    }

    /// Sends `head` (request line and headers, without the empty line
    /// that ends them) and `body`; the reply.
    pub fn send(&self, head: &str, body: &[u8]) -> Answer {
        let mut s = self.connect();
        write!(
            s,
            "{head}\r\nConnection: close\r\nContent-Length: {}\r\n\r\n",
            body.len()
        )
        .unwrap();
        s.write_all(body).unwrap();
        read_reply(&mut s).expect("a reply")
    }

    /// `METHOD PATH` from the served Host.
    pub fn request(&self, method: &str, path: &str) -> Answer {
        let host = self.host();
        self.send(&format!("{method} {path} HTTP/1.1\r\nHost: {host}"), b"")
    }

    pub fn json(&self, path: &str) -> serde_json::Value {
        let (code, _, body) = self.request("GET", path);
        assert_eq!(code, 200, "{path}: {}", String::from_utf8_lossy(&body));
        serde_json::from_slice(&body).unwrap()
    }

    pub fn status(&self) -> serde_json::Value {
        self.json("/status")
    }

    /// The token the page holds.
    pub fn token(&self) -> String {
        let (code, _, page) = self.request("GET", "/");
        assert_eq!(code, 200);
        let page = String::from_utf8(page).unwrap();
        let slot = r#"<meta name="scotopia-token" content=""#;
        let at = page.find(slot).expect("the page holds a token") + slot.len();
        page[at..].split('"').next().unwrap().to_string()
    }

    /// `POST /save` as the page sends it: the settings as JSON, the token.
    pub fn save(&self, settings: serde_json::Value) -> Answer {
        let (host, token) = (self.host(), self.token());
        self.send(
            &format!(
                "POST /save HTTP/1.1\r\nHost: {host}\r\nOrigin: http://{host}\r\n\
                 Content-Type: application/json\r\nX-Scotopia-Token: {token}"
            ),
            settings.to_string().as_bytes(),
        )
    }

    pub fn wait_until_done(&self) -> serde_json::Value {
        let deadline = Instant::now() + Duration::from_secs(120);
        loop {
            let s = self.status();
            if s["phase"] == "done" {
                return s;
            }
            assert!(Instant::now() < deadline, "the render did not finish: {s}");
            std::thread::sleep(Duration::from_millis(50));
        }
    }

    /// Ctrl-C, then the exit code and everything it said.
    pub fn interrupt(mut self) -> (i32, String) {
        let pid = self.child.id().to_string();
        let sent = Command::new("kill").args(["-INT", &pid]).status().unwrap();
        assert!(sent.success());
        let code = self.child.wait().unwrap().code().unwrap_or(-1);
        // The reader thread may still hold the last lines after the exit:
        // read until it sees the pipe's end (its sender is dropped then).
        let mut said = Vec::new();
        while let Ok(line) = self.stderr.recv_timeout(PATIENCE) {
            said.push(line);
        }
        (code, said.join("\n"))
    }
}

impl Drop for Viewer {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// Reads a whole reply (the server closes after it).
pub fn read_reply(s: &mut TcpStream) -> std::io::Result<Answer> {
    let mut bytes = Vec::new();
    s.read_to_end(&mut bytes)?;
    let Some(split) = bytes.windows(4).position(|w| w == b"\r\n\r\n") else {
        return Err(std::io::Error::other(format!(
            "no reply head in {:?}",
            String::from_utf8_lossy(&bytes)
        )));
    };
    let head = String::from_utf8_lossy(&bytes[..split]).to_lowercase();
    let code = head.split(' ').nth(1).unwrap().parse().unwrap();
    Ok((code, head, bytes[split + 4..].to_vec()))
}

/// A PNG's width, height and 8-bit samples.
pub fn decode(bytes: &[u8]) -> (u32, u32, Vec<u8>) {
    let mut reader = png::Decoder::new(std::io::Cursor::new(bytes))
        .read_info()
        .unwrap();
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buf).unwrap();
    buf.truncate(info.buffer_size());
    (info.width, info.height, buf)
}
