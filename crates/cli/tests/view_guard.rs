//! `scotopia view` as a local server should be (issue 38), over real
//! sockets against the binary: only its own Host is answered; only its
//! page (JSON, its token, no foreign Origin) can save; a GET changes
//! nothing; an endless header is cut off with bounded memory; hundreds of
//! idle connections and a client that pipelines requests and never reads
//! do not keep another client from being answered.

use std::io::Write;
use std::net::TcpStream;
use std::path::{Path, PathBuf};

mod common;
mod viewer;

use common::{out_dir, scenes, scotopia};
use viewer::{read_reply, Viewer};

/// A small film to look at (nothing renders while the tests run, so
/// nothing but a save writes the output).
fn film(dir: &Path) -> PathBuf {
    let exr = dir.join("film.exr");
    let scene = scenes().join("cornell-box.xml");
    let (code, _, err) = scotopia(&[
        "render",
        scene.to_str().unwrap(),
        "-D",
        "res=16",
        "--spp",
        "2",
        "-o",
        exr.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    exr
}

/// A viewer of a film, saving to `out.exr` beside it.
fn viewer(suite: &str) -> (Viewer, PathBuf) {
    let dir = out_dir("view-guard", suite);
    let exr = film(&dir);
    let out = dir.join("out.exr");
    let v = Viewer::start(&[exr.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    (v, out)
}

fn text(body: &[u8]) -> String {
    String::from_utf8_lossy(body).into_owned()
}

#[test]
fn only_the_served_host_is_answered_and_status_names_no_folders() {
    let (v, out) = viewer("host");
    let port = v.port;
    for host in [
        format!("evil.example:{port}"),
        format!("127.0.0.1:{port}.evil.example"),
        "127.0.0.1".into(),
        format!("127.0.0.1:{}", port.wrapping_add(1)),
    ] {
        for path in ["/", "/status", "/image.png", "/pixel?x=0&y=0"] {
            let (code, _, body) = v.send(&format!("GET {path} HTTP/1.1\r\nHost: {host}"), b"");
            assert_eq!(code, 421, "{host} {path}: {}", text(&body));
            assert!(!text(&body).contains(&*out.parent().unwrap().to_string_lossy()));
        }
    }
    // No Host at all (HTTP/1.0 allows it; a rebinding page always sends one).
    let (code, _, _) = v.send("GET /status HTTP/1.0", b"");
    assert_eq!(code, 421);
    // The names the page may use, and no folder in what it is told.
    for host in [format!("localhost:{port}"), format!("[::1]:{port}")] {
        let (code, _, body) = v.send(&format!("GET /status HTTP/1.1\r\nHost: {host}"), b"");
        assert_eq!(code, 200, "{host}");
        let status: serde_json::Value = serde_json::from_slice(&body).unwrap();
        assert_eq!(status["name"], "film.exr");
        assert_eq!(status["output"], "out.exr");
        assert!(!text(&body).contains('/'), "{}", text(&body));
    }
}

#[test]
fn only_the_page_can_save() {
    let (v, out) = viewer("save");
    let host = v.host();
    let token = v.token();
    let json = "Content-Type: application/json";
    let refused = [
        // A cross-site form, as a browser sends it.
        format!(
            "POST /save HTTP/1.1\r\nHost: {host}\r\nOrigin: http://evil.example\r\n\
             Sec-Fetch-Site: cross-site\r\nContent-Type: application/x-www-form-urlencoded"
        ),
        // A form without Origin (older browsers, other tools).
        format!("POST /save HTTP/1.1\r\nHost: {host}\r\nContent-Type: application/x-www-form-urlencoded"),
        format!("POST /save HTTP/1.1\r\nHost: {host}\r\nContent-Type: text/plain"),
        // JSON from the right origin, with no token or a wrong one.
        format!("POST /save HTTP/1.1\r\nHost: {host}\r\nOrigin: http://{host}\r\n{json}"),
        format!(
            "POST /save HTTP/1.1\r\nHost: {host}\r\nOrigin: http://{host}\r\n{json}\r\n\
             X-Scotopia-Token: {}",
            "0".repeat(token.len())
        ),
        // The token, but from another origin.
        format!(
            "POST /save HTTP/1.1\r\nHost: {host}\r\nOrigin: http://evil.example\r\n{json}\r\n\
             X-Scotopia-Token: {token}"
        ),
    ];
    for head in &refused {
        let body = if head.contains("form") {
            &b"scale=1"[..]
        } else {
            &b"{\"scale\": 1}"[..]
        };
        let (code, _, said) = v.send(head, body);
        assert!([403, 415].contains(&code), "{head}: {code} {}", text(&said));
        assert!(
            !out.exists() && !out.with_extension("png").exists(),
            "{head}"
        );
    }
    // Saving is a POST: a GET (an <img>, a link) is not.
    let (code, _, _) = v.request("GET", "/save?scale=1");
    assert_eq!(code, 405);
    assert!(!out.exists());
    // Settings go in the body, not the query; bad ones are named.
    let (code, _, said) = v.save(serde_json::json!({"scale": -1}));
    assert_eq!(code, 400, "{}", text(&said));
    assert!(text(&said).contains("--scale"), "{}", text(&said));
    assert!(!out.exists());
    // The page's own request saves.
    let (code, _, said) = v.save(serde_json::json!({"scale": 2}));
    assert_eq!(code, 200, "{}", text(&said));
    assert!(out.exists() && out.with_extension("png").exists());
    let reply: serde_json::Value = serde_json::from_slice(&said).unwrap();
    assert_eq!(
        (reply["exr"].as_str(), reply["png"].as_str()),
        (Some("out.exr"), Some("out.png"))
    );
}

#[test]
fn a_get_changes_nothing_and_save_writes_the_settings_it_is_given() {
    let (v, out) = viewer("get");
    let png = out.with_extension("png");
    // What a cross-site <img> could ask for.
    let (code, _, _) = v.request("GET", "/image.png?scale=0.0001&display-peak=1");
    assert_eq!(code, 200);
    assert_eq!(v.status()["settings"]["scale"], "1");
    // A save with no settings writes the command line's picture…
    let (code, _, said) = v.save(serde_json::json!({}));
    assert_eq!(code, 200, "{}", text(&said));
    let (_, _, plain) = v.request("GET", "/image.png");
    assert_eq!(std::fs::read(&png).unwrap(), plain);
    // …and one with settings writes exactly those.
    let (code, _, _) = v.save(serde_json::json!({"scale": "1000", "glare": false}));
    assert_eq!(code, 200);
    let (_, _, bright) = v.request("GET", "/image.png?scale=1000&glare=off");
    assert_eq!(std::fs::read(&png).unwrap(), bright);
    assert_ne!(plain, bright);
}

/// The process's peak resident memory in KiB (Linux).
fn peak_kib(pid: u32) -> u64 {
    let status = std::fs::read_to_string(format!("/proc/{pid}/status")).unwrap();
    let line = status.lines().find(|l| l.starts_with("VmHWM:")).unwrap();
    line.split_whitespace().nth(1).unwrap().parse().unwrap()
}

#[test]
#[cfg(target_os = "linux")]
fn an_endless_header_is_cut_off_with_bounded_memory() {
    let (v, _) = viewer("flood");
    // Everything the viewer allocates for a request, once, before measuring.
    let (code, _, _) = v.request("GET", "/image.png");
    assert_eq!(code, 200);
    let before = peak_kib(v.child.id());
    // 16 MiB of one header line.
    const FLOOD: usize = 16 << 20;
    let mut s = v.connect();
    write!(s, "GET / HTTP/1.1\r\nHost: {}\r\nX-Flood: ", v.host()).unwrap();
    let chunk = vec![b'a'; 64 << 10];
    let mut sent = 0;
    while sent < FLOOD {
        match s.write(&chunk) {
            Ok(n) => sent += n,
            // Cut off: the server closed the connection.
            Err(_) => break,
        }
    }
    // A 431 if it arrived before the connection was reset.
    if let Ok((code, _, _)) = read_reply(&mut s) {
        assert_eq!(code, 431);
    }
    let after = peak_kib(v.child.id());
    assert!(
        sent < FLOOD,
        "the server read all {FLOOD} bytes of one header line"
    );
    assert!(
        after < before + 4096,
        "the peak memory grew from {before} to {after} KiB"
    );
    // The server answers others afterwards.
    assert_eq!(v.status()["phase"], "image");
}

#[test]
fn idle_and_non_reading_clients_do_not_hold_up_others() {
    let (v, _) = viewer("idle");
    // More idle connections than the server keeps (512): some send half a
    // request, most nothing. 1500 were tried by hand too (with `ulimit -n`
    // raised): the same.
    let idle: Vec<TcpStream> = (0..600)
        .map(|i| {
            let mut s = v.connect();
            if i % 3 == 0 {
                let _ = write!(s, "GET /status HTTP/1.1\r\nHost: {}\r\n", v.host());
            }
            s
        })
        .collect();
    // A client that pipelines requests for the page and never reads.
    let mut greedy = v.connect();
    let one = format!("GET / HTTP/1.1\r\nHost: {}\r\n\r\n", v.host());
    for _ in 0..5000 {
        if greedy.write_all(one.as_bytes()).is_err() {
            break;
        }
    }
    // Another client is answered (or the connection would time out after
    // viewer::PATIENCE and fail the test).
    let (code, _, body) = v.request("GET", "/status");
    assert_eq!(code, 200, "{}", text(&body));
    let (code, _, _) = v.request("GET", "/image.png");
    assert_eq!(code, 200);
    drop(idle);
    drop(greedy);
}
