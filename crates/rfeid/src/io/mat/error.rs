//! Errors of reading a MAT-file: each names the file, and the byte offset or
//! the variable.
use std::fmt;
use std::path::PathBuf;

/// Where in a MAT-file something is: a byte offset in the file, or in the
/// decompressed data of an `miCOMPRESSED` element.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Location {
    /// Byte offset: in the file, or in the decompressed data when
    /// `compressed_at` is set.
    pub offset: u64,
    /// File offset of the enclosing `miCOMPRESSED` element, if any.
    pub compressed_at: Option<u64>,
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.compressed_at {
            None => write!(f, "byte {}", self.offset),
            Some(at) => write!(
                f,
                "byte {} of the decompressed data of the compressed element at byte {at}",
                self.offset
            ),
        }
    }
}

/// A problem with a MAT-file or with a variable asked of it.
#[derive(Debug, thiserror::Error)]
pub enum MatError {
    /// The file could not be read.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// Not a Level 5 MAT-file (no header, Level 4, or v7.3/HDF5).
    #[error("{}: not a MATLAB Level 5 MAT-file: {reason}", path.display())]
    NotMat {
        /// The file.
        path: PathBuf,
        /// Why not.
        reason: String,
    },
    /// An element runs past the end of the file (or of its parent element).
    #[error("{}: {at}: truncated {what}: it needs {needed} bytes, only {available} are left", path.display())]
    Truncated {
        /// The file.
        path: PathBuf,
        /// Where the truncated element starts.
        at: Location,
        /// What was being read.
        what: String,
        /// Bytes the element needs.
        needed: u64,
        /// Bytes left.
        available: u64,
    },
    /// An element that breaks the format (wrong type, bad size, bad
    /// dimensions, corrupt compressed data).
    #[error("{}: {at}: {message}", path.display())]
    Malformed {
        /// The file.
        path: PathBuf,
        /// Where.
        at: Location,
        /// What is wrong.
        message: String,
    },
    /// Two variables of the same name.
    #[error("{}: variable '{name}' appears twice", path.display())]
    Duplicate {
        /// The file.
        path: PathBuf,
        /// The name.
        name: String,
    },
    /// No variable of that name.
    #[error("{}: no variable '{name}' (variables: {available})", path.display())]
    UnknownVariable {
        /// The file.
        path: PathBuf,
        /// The name asked for.
        name: String,
        /// The variables present, comma-separated, or `none`.
        available: String,
    },
    /// The variable is not numeric (char, cell, struct, logical, sparse …).
    #[error("{}: variable '{name}' is {kind}, not a numeric vector", path.display())]
    NotNumeric {
        /// The file.
        path: PathBuf,
        /// The variable.
        name: String,
        /// What it is, e.g. `a char array`.
        kind: String,
    },
    /// The variable is complex.
    #[error("{}: variable '{name}' is complex; only real vectors can be read", path.display())]
    Complex {
        /// The file.
        path: PathBuf,
        /// The variable.
        name: String,
    },
    /// The variable is a matrix, not a vector.
    #[error("{}: variable '{name}' is a {dims} matrix, not a vector (1×N or N×1)", path.display())]
    NotVector {
        /// The file.
        path: PathBuf,
        /// The variable.
        name: String,
        /// Its dimensions, e.g. `2×3`.
        dims: String,
    },
}
