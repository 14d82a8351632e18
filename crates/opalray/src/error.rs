//! The one error type of the core library.
//!
//! Every failure a user can cause names the thing at fault (a scene field path, a file, a
//! flag) and says how to fix it, on one line.

use std::path::PathBuf;

/// Errors of the opalray core.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A scene value is out of range or inconsistent. `field` is the dotted path
    /// (`structure.void_ratio`), `message` says what is wrong and how to fix it.
    #[error("scene field `{field}`: {message}")]
    InvalidField {
        /// Dotted path of the offending field, e.g. `crystal.sphere_diameter_nm`.
        field: String,
        /// What is wrong and the fix, e.g. "must be in (0, 1), got 1.5; try 0.2".
        message: String,
    },
    /// A scene file could not be parsed (syntax error, unknown field, wrong type).
    #[error("{origin}: {message}")]
    SceneParse {
        /// Where the text came from: a file path or `preset NAME`.
        origin: String,
        /// The parser's message, with the field path where known.
        message: String,
    },
    /// An input data file (CSV, table) is malformed.
    #[error("{path}: {message}")]
    InvalidData {
        /// The file at fault.
        path: PathBuf,
        /// What is wrong and the fix.
        message: String,
    },
    /// An argument to a library function is out of range.
    #[error("{name}: {message}")]
    InvalidArgument {
        /// The argument (or CLI flag) at fault, e.g. `--diameter`.
        name: String,
        /// What is wrong and the fix.
        message: String,
    },
    /// Reading or writing a file failed.
    #[error("{path}: {source}")]
    Io {
        /// The file that could not be read or written.
        path: PathBuf,
        /// The operating system's error.
        #[source]
        source: std::io::Error,
    },
    /// Encoding an image failed.
    #[error("{path}: cannot encode image: {message}")]
    Encode {
        /// The file being written.
        path: PathBuf,
        /// The encoder's message.
        message: String,
    },
    /// The caller stopped the work (a time limit passed, or an interrupt): nothing was made.
    #[error("cancelled: the work was stopped before it ended")]
    Cancelled,
}

/// Result with the core [`Error`].
pub type Result<T, E = Error> = std::result::Result<T, E>;

impl Error {
    /// Shorthand for [`Error::InvalidField`].
    pub fn field(field: impl Into<String>, message: impl Into<String>) -> Self {
        Error::InvalidField {
            field: field.into(),
            message: message.into(),
        }
    }

    /// Shorthand for [`Error::InvalidArgument`].
    pub fn argument(name: impl Into<String>, message: impl Into<String>) -> Self {
        Error::InvalidArgument {
            name: name.into(),
            message: message.into(),
        }
    }

    /// Shorthand for [`Error::Io`].
    pub fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        Error::Io {
            path: path.into(),
            source,
        }
    }
}
