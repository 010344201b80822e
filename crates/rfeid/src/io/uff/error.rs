//! Errors of reading a universal file: each names the file, the dataset or
//! function record, and the line and byte offset.
use super::lines::Line;
use std::fmt;
use std::path::{Path, PathBuf};

/// The dataset an error is in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Context {
    /// The dataset type, e.g. 58 or 151.
    pub dataset: i64,
    /// For dataset 58: the 1-based function record number.
    pub record: Option<usize>,
    /// Line of the dataset's opening `-1`.
    pub start_line: usize,
}

impl fmt::Display for Context {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.record {
            Some(n) => write!(f, "record {n} (dataset 58 from line {})", self.start_line),
            None => write!(f, "dataset {} from line {}", self.dataset, self.start_line),
        }
    }
}

/// A problem with a universal file, or with a record asked of it.
#[derive(Debug, thiserror::Error)]
pub enum UffError {
    /// The file could not be read.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// The file does not start like a universal file.
    #[error("{}: not a universal file: line {line}: {message}", path.display())]
    NotUff {
        /// The file.
        path: PathBuf,
        /// 1-based line.
        line: usize,
        /// What was found.
        message: String,
    },
    /// Something between datasets that is not a dataset.
    #[error("{}: line {line} (byte {offset}): {message}", path.display())]
    Structure {
        /// The file.
        path: PathBuf,
        /// 1-based line.
        line: usize,
        /// Byte offset of the line.
        offset: usize,
        /// What is wrong.
        message: String,
    },
    /// A dataset that ends early (end of file, or its closing `-1` before
    /// all its values).
    #[error("{}: {context}: truncated at line {line} (byte {offset}): {message}", path.display())]
    Truncated {
        /// The file.
        path: PathBuf,
        /// The dataset.
        context: Context,
        /// 1-based line where it ends.
        line: usize,
        /// Byte offset where it ends.
        offset: usize,
        /// What is missing.
        message: String,
    },
    /// A field that breaks the format.
    #[error("{}: {context}: line {line} (byte {offset}): {message}", path.display())]
    Malformed {
        /// The file.
        path: PathBuf,
        /// The dataset.
        context: Context,
        /// 1-based line.
        line: usize,
        /// Byte offset of the line.
        offset: usize,
        /// What is wrong.
        message: String,
    },
    /// A valid but unsupported encoding (e.g. a non-IEEE binary format).
    #[error("{}: {context}: line {line}: unsupported: {message}", path.display())]
    Unsupported {
        /// The file.
        path: PathBuf,
        /// The dataset.
        context: Context,
        /// 1-based line.
        line: usize,
        /// What is not supported.
        message: String,
    },
    /// No function record with that number or name.
    #[error("{}: no function record {wanted} (records: {available})", path.display())]
    UnknownRecord {
        /// The file.
        path: PathBuf,
        /// The number or quoted name asked for.
        wanted: String,
        /// The records present (`1 'name', 2 'name' …`), or `none`.
        available: String,
    },
    /// Several records carry the name asked for.
    #[error("{}: records {records} are all named '{name}'; choose one by number (record = N)", path.display())]
    Ambiguous {
        /// The file.
        path: PathBuf,
        /// The name.
        name: String,
        /// Their numbers, comma-separated.
        records: String,
    },
    /// The record holds complex data (an FRF, a spectrum …).
    #[error("{}: record {record} ('{name}') holds complex data ({ordinate}); only real functions can be read", path.display())]
    Complex {
        /// The file.
        path: PathBuf,
        /// The record number.
        record: usize,
        /// Its ID line 1.
        name: String,
        /// The ordinate data type, e.g. `complex double (6)`.
        ordinate: String,
    },
}

/// What errors in one dataset need: the file and the dataset.
#[derive(Debug, Clone, Copy)]
pub(super) struct Ctx<'p> {
    /// The file.
    pub path: &'p Path,
    /// The dataset.
    pub context: Context,
}

impl Ctx<'_> {
    /// A format error at a line.
    pub fn malformed(&self, line: &Line<'_>, message: String) -> UffError {
        UffError::Malformed {
            path: self.path.into(),
            context: self.context,
            line: line.number,
            offset: line.offset,
            message,
        }
    }

    /// A truncation error at byte `offset` of the file `bytes` (the line
    /// is counted).
    pub fn truncated(&self, bytes: &[u8], offset: usize, message: String) -> UffError {
        let end = offset.min(bytes.len());
        let line = 1 + bytes[..end].iter().filter(|&&b| b == b'\n').count();
        self.truncated_at(line, offset, message)
    }

    /// A truncation error at a line.
    pub fn truncated_at(&self, line: usize, offset: usize, message: String) -> UffError {
        UffError::Truncated {
            path: self.path.into(),
            context: self.context,
            line,
            offset,
            message,
        }
    }
}
