//! Scene errors: every one names the file, line and column, and the element.

use std::fmt;
use std::sync::Arc;

/// Where in which file.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Location {
    pub file: String,
    pub line: u32,
    pub column: u32,
    /// For an element of an included file: the `<include>` that brought
    /// the file in (itself possibly in an included file).
    pub via: Option<Arc<Location>>,
}

impl Location {
    /// " (included from a.xml:3:5, included from …)", or nothing.
    pub fn included_from(&self) -> String {
        let mut out = String::new();
        let mut at = self.via.as_deref();
        while let Some(site) = at {
            out.push_str(&format!(", included from {site}"));
            at = site.via.as_deref();
        }
        if out.is_empty() {
            out
        } else {
            format!(" ({})", &out[2..])
        }
    }
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        // Line 0: the file as a whole (it could not be read).
        if self.line == 0 {
            write!(f, "{}", self.file)
        } else {
            write!(f, "{}:{}:{}", self.file, self.line, self.column)
        }
    }
}

/// A scene that cannot be read, or would render wrongly.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{location}: <{element}>: {message}{}", location.included_from())]
pub struct SceneError {
    pub location: Location,
    pub element: String,
    pub message: String,
}

impl SceneError {
    pub fn new(location: &Location, element: &str, message: impl Into<String>) -> Self {
        Self {
            location: location.clone(),
            element: element.to_string(),
            message: message.into(),
        }
    }
}

/// Every error a scene has (up to [`SceneErrors::LIMIT`]), with the
/// warnings collected before loading stopped: a user fixes them in one go.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneErrors {
    pub errors: Vec<SceneError>,
    pub warnings: Vec<String>,
    /// More errors were found than are listed.
    pub truncated: bool,
}

impl SceneErrors {
    /// Errors reported at most; loading stops at the next one.
    pub const LIMIT: usize = 20;

    /// The first error (every `SceneErrors` has at least one).
    pub fn first(&self) -> Option<&SceneError> {
        self.errors.first()
    }
}

impl From<SceneError> for SceneErrors {
    fn from(e: SceneError) -> Self {
        Self {
            errors: vec![e],
            warnings: Vec::new(),
            truncated: false,
        }
    }
}

impl fmt::Display for SceneErrors {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let n = self.errors.len();
        if n > 1 {
            let more = if self.truncated { " (the first)" } else { "" };
            writeln!(f, "{n} errors{more}:")?;
        }
        for (i, e) in self.errors.iter().enumerate() {
            if i > 0 {
                writeln!(f)?;
            }
            write!(f, "{e}")?;
        }
        if self.truncated {
            write!(f, "\n… loading stopped after {} errors", Self::LIMIT)?;
        }
        for w in &self.warnings {
            write!(f, "\nwarning: {w}")?;
        }
        Ok(())
    }
}

impl std::error::Error for SceneErrors {}
