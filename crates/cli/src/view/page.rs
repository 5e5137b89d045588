//! The page, embedded in the binary: static HTML, CSS and script, no
//! bundler; it talks to the routes in `server.rs`.

pub const HTML: &str = include_str!("page.html");
