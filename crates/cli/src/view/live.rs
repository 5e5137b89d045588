//! What the server shows: the latest look at the film, shared between the
//! render (which publishes) and the request threads (which read).

use std::path::PathBuf;
use std::sync::{Arc, Mutex, RwLock};

use scotopia_image::{Meta, XyzvImage};

use super::query::Pairs;

/// One look at the film.
pub struct Frame {
    /// Its means; `fov_horizontal` and `quantity` as an EXR would carry.
    pub image: XyzvImage,
    pub spp: u32,
    pub seconds: f64,
    /// The EXR header a save writes.
    pub meta: Vec<(&'static str, Meta)>,
}

/// Where the render is.
#[derive(Clone, Copy, PartialEq, Eq)]
pub enum Phase {
    Rendering,
    Done,
    Interrupted,
    /// Not a render: an image file being looked at.
    Image,
}

impl Phase {
    pub fn name(self) -> &'static str {
        match self {
            Phase::Rendering => "rendering",
            Phase::Done => "done",
            Phase::Interrupted => "interrupted",
            Phase::Image => "image",
        }
    }
}

pub struct Live {
    frame: RwLock<Arc<Frame>>,
    phase: Mutex<Phase>,
    /// The command line's settings: what every request's own are laid
    /// over (no request changes them).
    pub start: Pairs,
    /// The samples per pixel aimed at (0: until the time is up).
    pub target_spp: u32,
    /// What the page calls the input: its file name (the page is told no
    /// folders).
    pub name: String,
    /// Where saving writes the EXR (and the PNG beside it).
    pub output: PathBuf,
}

impl Live {
    pub fn new(
        frame: Frame,
        phase: Phase,
        start: Pairs,
        target_spp: u32,
        name: String,
        output: PathBuf,
    ) -> Self {
        Self {
            frame: RwLock::new(Arc::new(frame)),
            phase: Mutex::new(phase),
            start,
            target_spp,
            name,
            output,
        }
    }

    pub fn frame(&self) -> Arc<Frame> {
        self.frame
            .read()
            .map(|f| f.clone())
            .unwrap_or_else(|e| e.into_inner().clone())
    }

    pub fn publish(&self, frame: Frame) {
        let mut slot = self.frame.write().unwrap_or_else(|e| e.into_inner());
        *slot = Arc::new(frame);
    }

    pub fn phase(&self) -> Phase {
        *self.phase.lock().unwrap_or_else(|e| e.into_inner())
    }

    pub fn set_phase(&self, phase: Phase) {
        *self.phase.lock().unwrap_or_else(|e| e.into_inner()) = phase;
    }
}
