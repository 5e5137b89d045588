//! The local web server: the loopback interface only, a few threads, one
//! route per thing the page needs.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

use anyhow::{bail, Result};
use tiny_http::{Header, Method, Request, Response, Server};

use super::live::Live;
use super::respond;

/// The port tried first when none is given.
pub const DEFAULT_PORT: u16 = 8650;
/// How many ports after it are tried when it is busy.
const PORTS_TRIED: u16 = 20;

/// A server on 127.0.0.1: on `port` (0: one the system picks; busy: an
/// error), or on 8650 or the next free port.
pub fn bind(port: Option<u16>) -> Result<(Server, u16)> {
    let open = |p: u16| Server::http(("127.0.0.1", p));
    let server = match port {
        Some(p) => match open(p) {
            Ok(s) => s,
            Err(e) => bail!("--port {p}: cannot listen on 127.0.0.1:{p} ({e}); give another port, or 0 for any free one"),
        },
        None => {
            let mut tried = DEFAULT_PORT..DEFAULT_PORT + PORTS_TRIED;
            loop {
                let Some(p) = tried.next() else {
                    bail!(
                        "ports {DEFAULT_PORT}–{} on 127.0.0.1 are all busy: give --port",
                        DEFAULT_PORT + PORTS_TRIED - 1
                    );
                };
                if let Ok(s) = open(p) {
                    break s;
                }
            }
        }
    };
    let port = match server.server_addr().to_ip() {
        Some(a) => a.port(),
        None => bail!("the server is not on an IP address"),
    };
    Ok((server, port))
}

/// The server's threads, answering until closed.
pub struct Serving {
    server: Arc<Server>,
    closing: Arc<AtomicBool>,
    threads: Vec<std::thread::JoinHandle<()>>,
}

impl Serving {
    /// Stops answering and closes the port.
    pub fn close(self) {
        self.closing.store(true, Ordering::Relaxed);
        for _ in &self.threads {
            self.server.unblock();
        }
        for t in self.threads {
            let _ = t.join();
        }
    }
}

/// Answers requests on `threads` threads until closed.
pub fn spawn(server: Server, live: Arc<Live>, threads: usize) -> Serving {
    let server = Arc::new(server);
    let closing = Arc::new(AtomicBool::new(false));
    let threads = (0..threads)
        .map(|_| {
            let (server, live, closing) = (server.clone(), live.clone(), closing.clone());
            std::thread::spawn(move || loop {
                match server.recv() {
                    Ok(request) => answer(&live, request),
                    Err(_) if closing.load(Ordering::Relaxed) => break,
                    // A connection that failed is that connection's end.
                    Err(_) => continue,
                }
            })
        })
        .collect();
    Serving {
        server,
        closing,
        threads,
    }
}

fn answer(live: &Live, request: Request) {
    let url = request.url().to_string();
    let (path, query) = url.split_once('?').unwrap_or((&url, ""));
    let reply = match (request.method(), path) {
        (Method::Get, "/") => Reply::page(),
        (Method::Get, "/status") => Reply::json(respond::status(live)),
        (Method::Get, "/image.png") => respond::image(live, query),
        (Method::Get, "/pixel") => respond::pixel(live, query),
        (Method::Post, "/save") => respond::save(live, query),
        (_, "/" | "/status" | "/image.png" | "/pixel" | "/save") => {
            Reply::error(405, "method not allowed".into())
        }
        _ => Reply::error(
            404,
            format!("no page {path}: try /, /status, /image.png, /pixel or /save"),
        ),
    };
    // A client that went away is not the server's problem.
    let _ = request.respond(reply.response());
}

/// A response: status, content type, body and extra headers.
pub struct Reply {
    status: u16,
    kind: &'static str,
    body: Vec<u8>,
    headers: Vec<(&'static str, String)>,
}

impl Reply {
    fn page() -> Self {
        Self {
            status: 200,
            kind: "text/html; charset=utf-8",
            body: super::page::HTML.as_bytes().to_vec(),
            headers: Vec::new(),
        }
    }

    pub fn json(value: serde_json::Value) -> Self {
        Self {
            status: 200,
            kind: "application/json",
            body: value.to_string().into_bytes(),
            headers: Vec::new(),
        }
    }

    pub fn png(bytes: Vec<u8>, headers: Vec<(&'static str, String)>) -> Self {
        Self {
            status: 200,
            kind: "image/png",
            body: bytes,
            headers,
        }
    }

    /// An error as JSON: `{"error": message}`.
    pub fn error(status: u16, message: String) -> Self {
        Self {
            status,
            ..Self::json(serde_json::json!({ "error": message }))
        }
    }

    fn response(self) -> Response<std::io::Cursor<Vec<u8>>> {
        let mut r = Response::from_data(self.body).with_status_code(self.status);
        let headers = [
            ("Content-Type", self.kind.to_string()),
            // Every answer is of the moment: never cached.
            ("Cache-Control", "no-store".into()),
        ];
        for (name, value) in headers.into_iter().chain(self.headers) {
            if let Ok(h) = Header::from_bytes(name.as_bytes(), value.as_bytes()) {
                r.add_header(h);
            }
        }
        r
    }
}
