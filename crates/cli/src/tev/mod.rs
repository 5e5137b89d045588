//! `render --tev [HOST:PORT]`: the film, streamed to the tev image viewer
//! (github.com/Tom94/tev) while it renders, over tev's TCP protocol.
//!
//! tev shows one image named as the output file, with channels X, Y, Z,
//! V (the film's means, cd/m², as in the EXR) and a layer `seen` (R, G, B:
//! what the eye sees, from the vision pipeline, linear). The render hands
//! a copy of its film over about once a second; a thread of its own runs
//! the pipeline and the socket, so the render neither waits for tev nor
//! fails because of it.

mod client;
mod protocol;

use std::time::Duration;

pub use client::{address, Address, Image, Viewer, DEFAULT};

/// How often the render shows its film: every second, or every
/// `SCOTOPIA_TEV_EVERY` seconds (for tests: 0 is every pass).
pub fn every() -> Duration {
    std::env::var("SCOTOPIA_TEV_EVERY")
        .ok()
        .and_then(|s| s.parse::<f64>().ok())
        .filter(|s| s.is_finite() && (0.0..=3600.0).contains(s))
        .map_or(Duration::from_secs(1), Duration::from_secs_f64)
}
