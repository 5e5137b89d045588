//! Errors of the colour crate. Every error that comes from a file names it,
//! with the line where the line is known.

/// What can go wrong building a spectrum or a colour.
#[derive(Debug, thiserror::Error)]
pub enum ColorError {
    /// A spectrum file (or embedded table) is malformed at a given line.
    #[error("{path}:{line}: {message}")]
    SpectrumFile {
        path: String,
        line: usize,
        message: String,
    },
    /// A spectrum file holds no data rows.
    #[error("{path}: no spectral data (expected lines of 'wavelength,value')")]
    EmptySpectrumFile { path: String },
    /// A spectrum file could not be read at all.
    /// (The I/O error is part of the message, not a separate cause, so
    /// reports do not print it twice.)
    #[error("{path}: {cause}")]
    Io { path: String, cause: std::io::Error },
    /// Spectrum data given directly (not from a file) is invalid.
    #[error("invalid spectrum: {0}")]
    InvalidSpectrum(String),
    /// A name that is not one of a known set.
    #[error("unknown {what} '{name}' (known: {known})")]
    UnknownName {
        what: &'static str,
        name: String,
        known: String,
    },
    /// A parameter outside the range where its model is defined.
    #[error("{0}")]
    OutOfRange(String),
    /// An RGB colour that cannot be turned into the requested kind of spectrum.
    #[error("{0}")]
    InvalidRgb(String),
    /// A coefficient table that is corrupt or of the wrong version.
    #[error("RGB-to-spectrum table: {0}")]
    Table(String),
}
