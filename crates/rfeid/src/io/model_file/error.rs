//! Errors of reading a model file: each names the file, the entry and the
//! field, and carries the span for a snippet.
use std::ops::Range;
use std::path::PathBuf;
use std::sync::Arc;

/// A problem with a model file.
#[derive(Debug, Clone, thiserror::Error)]
#[error("{}: {}{}", path.display(), location(entry, field), message)]
pub struct ModelFileError {
    /// The file.
    pub path: PathBuf,
    /// The file's text, when it could be read (for a snippet).
    pub source_text: Option<Arc<str>>,
    /// Byte range of the offending text.
    pub span: Option<Range<usize>>,
    /// The entry, e.g. `element "slide1"`; empty for the file as a whole.
    pub entry: String,
    /// The field, e.g. `axes`; empty when not one field.
    pub field: String,
    /// What is wrong.
    pub message: String,
}

fn location(entry: &str, field: &str) -> String {
    match (entry.is_empty(), field.is_empty()) {
        (true, true) => String::new(),
        (false, true) => format!("{entry}: "),
        (true, false) => format!("{field}: "),
        (false, false) => format!("{entry}, field '{field}': "),
    }
}
