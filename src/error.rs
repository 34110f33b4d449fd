//! Errors a person can act on: every variant names the file (when there is one) and what is wrong.

use std::path::PathBuf;

/// Result alias of the library.
pub type Result<T, E = Error> = std::result::Result<T, E>;

/// What can go wrong between a scan on disk and its equilibria.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// The file could not be read or written.
    #[error("{path}: {error}")]
    Io { path: PathBuf, error: std::io::Error },
    /// The file is not a mesh we can parse (format, truncation, bad numbers...).
    #[error("{path}: {what}")]
    Parse { path: PathBuf, what: String },
    /// The mesh parsed but is not a closed, manifold, consistently oriented solid.
    #[error("{path}: {what}")]
    InvalidMesh { path: PathBuf, what: String },
    /// The geometry is degenerate (flat, empty, zero volume, all points coplanar...).
    #[error("{path}: degenerate geometry: {what}")]
    Degenerate { path: PathBuf, what: String },
    /// A theorem that must hold failed (e.g. Poincaré–Hopf); this is a bug or a degenerate input.
    #[error("{path}: internal check failed: {what}")]
    Check { path: PathBuf, what: String },
    /// A plot could not be drawn into the file.
    #[error("{path}: cannot draw the plot: {what}")]
    Plot { path: PathBuf, what: String },
    /// Bad user input that is not a file (an option value, a generator parameter...).
    #[error("{0}")]
    Usage(String),
}

/// Any error of a writer's inner steps (CSV, JSON, I/O, plotters), before it is given its file.
pub type BoxError = Box<dyn std::error::Error + Send + Sync>;

impl Error {
    /// Attach a file name to an error that was produced without one (path `<memory>`).
    pub fn with_path(self, p: impl Into<PathBuf>) -> Self {
        let p = p.into();
        let fix = |old: PathBuf| if old.as_os_str() == MEMORY { p.clone() } else { old };
        match self {
            Error::Io { path, error } => Error::Io { path: fix(path), error },
            Error::Parse { path, what } => Error::Parse { path: fix(path), what },
            Error::InvalidMesh { path, what } => Error::InvalidMesh { path: fix(path), what },
            Error::Degenerate { path, what } => Error::Degenerate { path: fix(path), what },
            Error::Check { path, what } => Error::Check { path: fix(path), what },
            Error::Plot { path, what } => Error::Plot { path: fix(path), what },
            e @ Error::Usage(_) => e,
        }
    }

    /// A failure while writing file `path` (CSV, JSON or I/O), as [`Error::Io`] naming the file;
    /// `path` = [`MEMORY`] for a writer into a stream, to be named with [`Error::with_path`].
    pub fn write(path: impl Into<PathBuf>, e: impl Into<BoxError>) -> Self {
        let error = match e.into().downcast::<std::io::Error>() {
            Ok(io) => *io,
            Err(other) => std::io::Error::other(other),
        };
        Error::Io { path: path.into(), error }
    }

    /// Shorthand for an in-memory degenerate-geometry error.
    pub fn degenerate(what: impl Into<String>) -> Self {
        Error::Degenerate { path: MEMORY.into(), what: what.into() }
    }

    /// Shorthand for an in-memory invalid-mesh error.
    pub fn invalid(what: impl Into<String>) -> Self {
        Error::InvalidMesh { path: MEMORY.into(), what: what.into() }
    }

    /// Shorthand for an in-memory failed internal check.
    pub fn check(what: impl Into<String>) -> Self {
        Error::Check { path: MEMORY.into(), what: what.into() }
    }
}

/// Placeholder path of meshes that live only in memory.
pub const MEMORY: &str = "<memory>";
