//! Scene errors: every one names the file, line and column, and the element.

use std::fmt;

/// Where in which file.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Location {
    pub file: String,
    pub line: u32,
    pub column: u32,
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
#[error("{location}: <{element}>: {message}")]
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
