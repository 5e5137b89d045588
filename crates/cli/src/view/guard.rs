//! Who may ask what. The server listens on the loopback only, but any web
//! page the user opens can send requests to it, so:
//! - a request must name the served address and port in `Host`: a page of
//!   another site that rebinds its DNS name to 127.0.0.1 names its own;
//! - a request that changes anything (saving) must be the page's own: a
//!   POST of JSON (a cross-site form cannot send that without a CORS
//!   preflight, which is never granted), carrying this session's random
//!   token in `X-Scotopia-Token` (embedded in the page, which another site
//!   cannot read), and not from another origin (`Origin`,
//!   `Sec-Fetch-Site`).

use anyhow::{anyhow, Result};

use super::http::{Reply, Request};

/// The header that carries the token.
pub const TOKEN_HEADER: &str = "X-Scotopia-Token";

pub struct Session {
    port: u16,
    token: String,
}

impl Session {
    /// A session on `port` with a fresh 256-bit token.
    pub fn new(port: u16) -> Result<Self> {
        let mut bytes = [0u8; 32];
        getrandom::fill(&mut bytes)
            .map_err(|e| anyhow!("no random bytes for the page's token ({e})"))?;
        let token = bytes.iter().map(|b| format!("{b:02x}")).collect();
        Ok(Self { port, token })
    }

    /// What the page sends in `X-Scotopia-Token`.
    pub fn token(&self) -> &str {
        &self.token
    }

    /// `Host` names the served port on the loopback; else 421.
    pub fn check_host(&self, request: &Request) -> Result<(), Reply> {
        let host = request.header("host").unwrap_or("").to_ascii_lowercase();
        let port = self.port;
        let served = [
            format!("127.0.0.1:{port}"),
            format!("localhost:{port}"),
            format!("[::1]:{port}"),
        ];
        if served.contains(&host) {
            return Ok(());
        }
        Err(Reply::error(
            421,
            format!(
                "Host '{}' is not this viewer: use http://127.0.0.1:{port}/",
                host.escape_debug()
            ),
        ))
    }

    /// A request that changes something is the page's own: same origin
    /// (where the browser says), JSON, and the session's token.
    pub fn check_change(&self, request: &Request) -> Result<(), Reply> {
        let refuse = |status, message: &str| Err(Reply::error(status, message.into()));
        // The Host was checked on arrival: the page's origin is its own.
        let origin = format!("http://{}", request.header("host").unwrap_or(""));
        if let Some(o) = request.header("origin") {
            if !o.eq_ignore_ascii_case(&origin) {
                return refuse(403, "a request from another origin may not change anything");
            }
        }
        if let Some(site) = request.header("sec-fetch-site") {
            if !matches!(site, "same-origin" | "none") {
                return refuse(403, "a request from another site may not change anything");
            }
        }
        let kind = request.header("content-type").unwrap_or("");
        let media = kind.split(';').next().unwrap_or("").trim();
        if !media.eq_ignore_ascii_case("application/json") {
            return refuse(
                415,
                "send the settings as JSON (Content-Type: application/json)",
            );
        }
        let given = request.header(TOKEN_HEADER).unwrap_or("");
        if !same(given.as_bytes(), self.token.as_bytes()) {
            return refuse(
                403,
                "missing or wrong X-Scotopia-Token: changes come from the viewer's page",
            );
        }
        Ok(())
    }
}

/// Equal, in a time that does not depend on where they differ.
fn same(a: &[u8], b: &[u8]) -> bool {
    a.len() == b.len() && a.iter().zip(b).fold(0u8, |d, (x, y)| d | (x ^ y)) == 0
}

#[cfg(test)]
mod tests {
    use super::*;

    fn status(r: Result<(), Reply>) -> u16 {
        r.err().map_or(200, |r| r.status)
    }

    #[test]
    fn only_the_served_host_and_port_are_answered() {
        let s = Session::new(8650).unwrap();
        let host = |h: &str| status(s.check_host(&Request::new("GET", "/", &[("Host", h)], b"")));
        for ok in [
            "127.0.0.1:8650",
            "localhost:8650",
            "LOCALHOST:8650",
            "[::1]:8650",
        ] {
            assert_eq!(host(ok), 200, "{ok}");
        }
        for bad in [
            "evil.example:8650",
            "127.0.0.1",
            "127.0.0.1:8651",
            "localhost",
            "127.0.0.1:8650.evil.example",
            "",
        ] {
            assert_eq!(host(bad), 421, "{bad}");
        }
        let none = Request::new("GET", "/", &[], b"");
        assert_eq!(status(s.check_host(&none)), 421);
    }

    #[test]
    fn a_change_needs_the_token_json_and_no_foreign_origin() {
        let s = Session::new(8650).unwrap();
        let t = s.token().to_string();
        assert_eq!(t.len(), 64);
        assert_ne!(t, Session::new(8650).unwrap().token(), "tokens are random");
        let json = ("Content-Type", "application/json");
        let host = ("Host", "127.0.0.1:8650");
        let change = |headers: &[(&str, &str)]| {
            status(s.check_change(&Request::new("POST", "/save", headers, b"{}")))
        };
        assert_eq!(change(&[host, json, (TOKEN_HEADER, &t)]), 200);
        let page = ("Origin", "http://127.0.0.1:8650");
        let same_site = ("Sec-Fetch-Site", "same-origin");
        assert_eq!(
            change(&[host, json, (TOKEN_HEADER, &t), page, same_site]),
            200
        );
        // No token, a wrong one, one a character short.
        assert_eq!(change(&[host, json]), 403);
        assert_eq!(
            change(&[host, json, (TOKEN_HEADER, &t.replace('a', "b"))]),
            403
        );
        assert_eq!(change(&[host, json, (TOKEN_HEADER, &t[1..])]), 403);
        // Another origin or site, even with the token.
        for other in [
            ("Origin", "http://evil.example"),
            ("Origin", "null"),
            ("Origin", "http://127.0.0.1:8651"),
            ("Sec-Fetch-Site", "cross-site"),
            ("Sec-Fetch-Site", "same-site"),
        ] {
            assert_eq!(
                change(&[host, json, (TOKEN_HEADER, &t), other]),
                403,
                "{other:?}"
            );
        }
        // What a form can send.
        for kind in [
            "application/x-www-form-urlencoded",
            "multipart/form-data; boundary=x",
            "text/plain",
        ] {
            let form = ("Content-Type", kind);
            assert_eq!(change(&[host, form, (TOKEN_HEADER, &t)]), 415, "{kind}");
        }
    }
}
