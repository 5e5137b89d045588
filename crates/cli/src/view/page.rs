//! The page, embedded in the binary: static HTML, CSS and script, no
//! bundler; it talks to the routes in `respond.rs`.

const HTML: &str = include_str!("page.html");
/// Where the page holds the session's token (in a `<meta>`).
const TOKEN_SLOT: &str = "{{SCOTOPIA_TOKEN}}";

/// The page with the session's token in it: only a page served from here
/// (and read by the browser as this origin's) holds it.
pub fn html(token: &str) -> String {
    HTML.replacen(TOKEN_SLOT, token, 1)
}

#[cfg(test)]
mod tests {
    #[test]
    fn the_page_holds_the_token_once() {
        let page = super::html("0123abcd");
        assert!(page.contains(r#"<meta name="scotopia-token" content="0123abcd">"#));
        assert!(!page.contains(super::TOKEN_SLOT));
    }
}
