//! Lines of text as they were written: LF (Unix), CRLF (Windows) or CR
//! alone (classic Mac OS, and some photometric software still writes it).

/// The lines of `text`, each without its ending (`\n`, `\r\n` or `\r`);
/// as [`str::lines`], a final ending does not start an empty line.
pub fn lines(text: &str) -> impl Iterator<Item = &str> {
    let mut rest = Some(text);
    std::iter::from_fn(move || {
        let t = rest?;
        match t.find(['\n', '\r']) {
            Some(i) => {
                let after = if t[i..].starts_with("\r\n") {
                    i + 2
                } else {
                    i + 1
                };
                rest = (after < t.len()).then(|| &t[after..]);
                Some(&t[..i])
            }
            None => {
                rest = None;
                (!t.is_empty()).then_some(t)
            }
        }
    })
}

#[cfg(test)]
mod tests {
    use super::lines;

    #[test]
    fn every_ending_splits_once() {
        fn all(t: &str) -> Vec<&str> {
            lines(t).collect()
        }
        assert_eq!(all("a\nb\n"), ["a", "b"]);
        assert_eq!(all("a\r\nb\r\n"), ["a", "b"]);
        assert_eq!(all("a\rb\r"), ["a", "b"]);
        assert_eq!(all("a\r\rb"), ["a", "", "b"]);
        assert_eq!(all("a\n\r\nb\rc"), ["a", "", "b", "c"]);
        assert_eq!(all(""), Vec::<&str>::new());
        assert_eq!(all("\n"), [""]);
        for t in ["x\ny\n\nz", "one", "\n\nq\n"] {
            assert_eq!(all(t), t.lines().collect::<Vec<_>>(), "{t:?}");
        }
    }
}
