//! HTTP/1.1 as far as the page needs it: one request per connection, read
//! whole within fixed limits (httparse parses its head), and one reply
//! that closes the connection.

/// The most a request's head (request line and headers) may take. Browsers
/// send under 2 KiB; the limit is what stops an endless header line.
pub const MAX_HEAD: usize = 16 * 1024;
/// The most a request's body may take (the page's saves send ~300 bytes).
pub const MAX_BODY: usize = 64 * 1024;
/// The most headers a request may have.
const MAX_HEADERS: usize = 64;
/// Headers that decide what a request may do: one of each at most, so that
/// no check reads one copy and the answer another.
const SINGLE: [&str; 6] = [
    "host",
    "origin",
    "content-length",
    "content-type",
    "x-scotopia-token",
    "sec-fetch-site",
];

/// A request received whole.
pub struct Request {
    pub method: String,
    /// The target's path (`/image.png`) and query (`scale=2`, or empty).
    pub path: String,
    pub query: String,
    /// Names in lower case.
    headers: Vec<(String, String)>,
    pub body: Vec<u8>,
}

impl Request {
    /// The header's value (names are case-insensitive).
    pub fn header(&self, name: &str) -> Option<&str> {
        self.headers
            .iter()
            .find(|(n, _)| n.eq_ignore_ascii_case(name))
            .map(|(_, v)| v.as_str())
    }

    /// A request for tests.
    #[cfg(test)]
    pub fn new(method: &str, target: &str, headers: &[(&str, &str)], body: &[u8]) -> Self {
        let (path, query) = target.split_once('?').unwrap_or((target, ""));
        Self {
            method: method.into(),
            path: path.into(),
            query: query.into(),
            headers: headers
                .iter()
                .map(|(n, v)| (n.to_ascii_lowercase(), v.to_string()))
                .collect(),
            body: body.to_vec(),
        }
    }
}

/// What the bytes received on a connection so far amount to.
pub enum Received {
    /// Not a whole request yet (and within the limits).
    More,
    Whole(Request),
    /// A request that breaks the rules or the limits: this is the answer.
    Refused(Reply),
}

/// A request arriving: its bytes so far, and its head once read (so that
/// neither is looked through again for each new piece).
#[derive(Default)]
pub struct Incoming {
    bytes: Vec<u8>,
    /// How far the search for the head's end has looked.
    scanned: usize,
    /// The head read: the request without its body, where the body starts
    /// and its length.
    head: Option<(Request, usize, usize)>,
}

impl Incoming {
    /// Takes the next bytes the connection sent.
    pub fn push(&mut self, data: &[u8]) -> Received {
        self.bytes.extend_from_slice(data);
        if self.head.is_none() {
            let too_long = || {
                Received::Refused(Reply::error(
                    431,
                    format!("the request's head is over {MAX_HEAD} bytes"),
                ))
            };
            // The end (a line break, then CRLF or LF) may straddle pieces.
            let Some(end) = head_end(&self.bytes, self.scanned.saturating_sub(2)) else {
                self.scanned = self.bytes.len();
                return if self.bytes.len() > MAX_HEAD {
                    too_long()
                } else {
                    Received::More
                };
            };
            if end > MAX_HEAD {
                return too_long();
            }
            match parse_head(&self.bytes[..end]) {
                Err(reply) => return Received::Refused(reply),
                Ok((request, length)) => self.head = Some((request, end, length)),
            }
        }
        match self.head.take() {
            Some((mut request, end, length)) if self.bytes.len() >= end + length => {
                request.body = self.bytes[end..end + length].to_vec();
                Received::Whole(request)
            }
            head => {
                self.head = head;
                Received::More
            }
        }
    }

    /// The bytes held (never more than a head, a body and a last piece).
    pub fn held(&self) -> usize {
        self.bytes.len()
    }
}

/// Where the head ends, looking from `from`: after the first empty line
/// (CRLF, or LF alone as httparse also reads).
fn head_end(bytes: &[u8], mut from: usize) -> Option<usize> {
    while let Some(i) = bytes.get(from..)?.iter().position(|&b| b == b'\n') {
        let at = from + i;
        match bytes.get(at + 1..) {
            Some([b'\n', ..]) => return Some(at + 2),
            Some([b'\r', b'\n', ..]) => return Some(at + 3),
            _ => from = at + 1,
        }
    }
    None
}

/// The request a head describes (without its body) and its body's length.
fn parse_head(head: &[u8]) -> Result<(Request, usize), Reply> {
    let bad = |message: String| Reply::error(400, message);
    let mut slots = [httparse::EMPTY_HEADER; MAX_HEADERS];
    let mut parsed = httparse::Request::new(&mut slots);
    match parsed.parse(head) {
        Ok(httparse::Status::Complete(_)) => {}
        Ok(httparse::Status::Partial) => return Err(bad("an incomplete request head".into())),
        Err(httparse::Error::TooManyHeaders) => {
            return Err(Reply::error(
                431,
                format!("more than {MAX_HEADERS} headers"),
            ))
        }
        Err(e) => return Err(bad(format!("not an HTTP request ({e})"))),
    }
    let (Some(method), Some(target)) = (parsed.method, parsed.path) else {
        return Err(bad("no request line".into()));
    };
    let mut headers = Vec::with_capacity(parsed.headers.len());
    for h in parsed.headers.iter() {
        let name = h.name.to_ascii_lowercase();
        // Not UTF-8 (a stray cookie): kept readable; no check accepts it.
        let value = String::from_utf8_lossy(h.value);
        if SINGLE.contains(&name.as_str()) && headers.iter().any(|(n, _)| *n == name) {
            return Err(bad(format!("header {name} given twice")));
        }
        headers.push((name, value.trim().to_string()));
    }
    let find = |name: &str| headers.iter().find(|(n, _)| n == name).map(|(_, v)| v);
    if find("transfer-encoding").is_some() {
        return Err(Reply::error(
            411,
            "bodies are read by Content-Length only".into(),
        ));
    }
    let length = match find("content-length") {
        None => 0,
        Some(v) => match v.parse::<usize>() {
            Ok(n) if n <= MAX_BODY => n,
            Ok(_) => {
                return Err(Reply::error(
                    413,
                    format!("the body is over {MAX_BODY} bytes"),
                ))
            }
            Err(_) => return Err(bad(format!("Content-Length {v}: not a length"))),
        },
    };
    let (path, query) = target.split_once('?').unwrap_or((target, ""));
    let request = Request {
        method: method.to_string(),
        path: path.to_string(),
        query: query.to_string(),
        headers,
        body: Vec::new(),
    };
    Ok((request, length))
}

/// A response: status, content type, body and extra headers.
pub struct Reply {
    pub status: u16,
    kind: &'static str,
    body: Vec<u8>,
    headers: Vec<(&'static str, String)>,
}

impl Reply {
    pub fn html(text: String) -> Self {
        Self {
            status: 200,
            kind: "text/html; charset=utf-8",
            body: text.into_bytes(),
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

    /// With an extra header.
    pub fn with(mut self, name: &'static str, value: String) -> Self {
        self.headers.push((name, value));
        self
    }

    /// The bytes sent: status line, headers, body.
    pub fn bytes(self) -> Vec<u8> {
        let mut head = format!("HTTP/1.1 {} {}\r\n", self.status, reason(self.status));
        let fixed = [
            ("Content-Type", self.kind.to_string()),
            ("Content-Length", self.body.len().to_string()),
            // One request per connection: nothing waits on an open one.
            ("Connection", "close".into()),
            // Every answer is of the moment: never cached.
            ("Cache-Control", "no-store".into()),
            ("X-Content-Type-Options", "nosniff".into()),
            // No other site may frame the page (a click on Save there
            // would be the user's own).
            ("Content-Security-Policy", "frame-ancestors 'none'".into()),
            ("X-Frame-Options", "DENY".into()),
        ];
        for (name, value) in fixed.into_iter().chain(self.headers) {
            // A value that could end the header (a line break) is left
            // out, as it cannot be sent as it is.
            if value
                .bytes()
                .all(|b| b == b'\t' || (b >= 0x20 && b != 0x7f))
            {
                head.push_str(&format!("{name}: {value}\r\n"));
            }
        }
        head.push_str("\r\n");
        let mut bytes = head.into_bytes();
        bytes.extend_from_slice(&self.body);
        bytes
    }
}

fn reason(status: u16) -> &'static str {
    match status {
        200 => "OK",
        400 => "Bad Request",
        403 => "Forbidden",
        404 => "Not Found",
        405 => "Method Not Allowed",
        408 => "Request Timeout",
        411 => "Length Required",
        413 => "Content Too Large",
        415 => "Unsupported Media Type",
        421 => "Misdirected Request",
        431 => "Request Header Fields Too Large",
        503 => "Service Unavailable",
        _ => "Internal Server Error",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn receive(bytes: &[u8]) -> Received {
        Incoming::default().push(bytes)
    }

    fn status(bytes: &[u8]) -> Option<u16> {
        match receive(bytes) {
            Received::More => None,
            Received::Whole(_) => Some(200),
            Received::Refused(r) => Some(r.status),
        }
    }

    #[test]
    fn a_request_is_read_whole_with_its_body() {
        let text = b"POST /save?a=1 HTTP/1.1\r\nHost: x\r\nContent-Length: 4\r\n\r\nab";
        assert!(matches!(receive(text), Received::More));
        let mut whole = text.to_vec();
        whole.extend_from_slice(b"cdEXTRA");
        let Received::Whole(r) = receive(&whole) else {
            panic!("not whole")
        };
        assert_eq!((r.method.as_str(), r.path.as_str()), ("POST", "/save"));
        assert_eq!((r.query.as_str(), r.body.as_slice()), ("a=1", &b"abcd"[..]));
        assert_eq!(r.header("HOST"), Some("x"));
        // LF alone ends lines too.
        assert_eq!(status(b"GET / HTTP/1.0\n\n"), Some(200));
    }

    #[test]
    fn a_request_sent_a_byte_at_a_time_is_the_same() {
        for text in [
            &b"POST /save HTTP/1.1\r\nHost: x\r\nContent-Length: 3\r\n\r\nabcdef"[..],
            b"POST /save HTTP/1.1\nHost: x\nContent-Length: 3\n\nabcdef",
        ] {
            let mut incoming = Incoming::default();
            let whole = text.len() - 3;
            for (i, b) in text.iter().enumerate() {
                match incoming.push(&[*b]) {
                    Received::More => assert!(i + 1 < whole, "byte {i}"),
                    Received::Whole(r) => {
                        assert_eq!((i + 1, r.body.as_slice()), (whole, &b"abc"[..]));
                        assert_eq!(r.header("host"), Some("x"));
                        break;
                    }
                    Received::Refused(r) => panic!("refused: {}", r.status),
                }
            }
        }
    }

    #[test]
    fn the_limits_and_rules_are_refusals() {
        // A head that never ends: refused once over the limit.
        let mut endless = b"GET / HTTP/1.1\r\nX: ".to_vec();
        endless.resize(MAX_HEAD, b'a');
        assert_eq!(status(&endless), None);
        endless.push(b'a');
        assert_eq!(status(&endless), Some(431));
        let big = format!(
            "POST / HTTP/1.1\r\nContent-Length: {}\r\n\r\n",
            MAX_BODY + 1
        );
        assert_eq!(status(big.as_bytes()), Some(413));
        let chunked = b"POST / HTTP/1.1\r\nTransfer-Encoding: chunked\r\n\r\n";
        assert_eq!(status(chunked), Some(411));
        let twice = b"GET / HTTP/1.1\r\nHost: a\r\nHost: b\r\n\r\n";
        assert_eq!(status(twice), Some(400));
        assert_eq!(status(b"\x00\x01 nonsense\r\n\r\n"), Some(400));
        let many: String = (0..100).map(|i| format!("X{i}: 1\r\n")).collect();
        let many = format!("GET / HTTP/1.1\r\n{many}\r\n");
        assert_eq!(status(many.as_bytes()), Some(431));
    }

    #[test]
    fn a_reply_closes_and_leaves_out_a_header_that_would_break_it() {
        let r = Reply::error(421, "no".into()).with("X-Bad", "a\r\nSet-Cookie: x".into());
        let text = String::from_utf8(r.bytes()).unwrap();
        assert!(
            text.starts_with("HTTP/1.1 421 Misdirected Request\r\n"),
            "{text}"
        );
        assert!(text.contains("Connection: close\r\n"), "{text}");
        assert!(!text.contains("Set-Cookie"), "{text}");
        assert!(text.ends_with("\r\n\r\n{\"error\":\"no\"}"), "{text}");
    }
}
