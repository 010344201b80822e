//! Fixed-column fields of universal-file records (Fortran formats such as
//! `3I10,3E13.5`), with a fallback to blank-separated fields for writers
//! that do not keep the columns.

/// The fields of `text` cut at the given widths, each trimmed; missing
/// columns give empty fields.
pub fn fixed(text: &[u8], widths: &[usize]) -> Vec<String> {
    let mut out = Vec::with_capacity(widths.len());
    let mut pos = 0;
    for &w in widths {
        let a = pos.min(text.len());
        let b = (pos + w).min(text.len());
        out.push(String::from_utf8_lossy(&text[a..b]).trim().to_string());
        pos += w;
    }
    out
}

/// The blank-separated tokens of `text`.
pub fn tokens(text: &[u8]) -> Vec<String> {
    String::from_utf8_lossy(text)
        .split_ascii_whitespace()
        .map(str::to_string)
        .collect()
}

/// An integer field; blank is `None`.
pub fn int(s: &str) -> Option<i64> {
    s.trim().parse().ok()
}

/// A real field in Fortran notation (`1.5E+00`, `1.5D+00`, `15`).
pub fn real(s: &str) -> Option<f64> {
    let s = s.trim();
    if s.is_empty() {
        return None;
    }
    if s.contains(['D', 'd']) {
        s.replace(['D', 'd'], "E").parse().ok()
    } else {
        s.parse().ok()
    }
}

/// Parses the numbers of one data line: fields of the given widths in
/// turn (repeating the pattern), blank trailing fields ignored; if a field
/// is not a number, the line is read as blank-separated numbers instead.
/// `Err` holds the first text that is not a number.
pub fn data_line(text: &[u8], widths: &[usize]) -> Result<Vec<f64>, String> {
    let mut out = Vec::new();
    let mut pos = 0;
    let mut i = 0;
    let mut fixed_ok = true;
    while pos < text.len() {
        let w = widths[i % widths.len()];
        let end = (pos + w).min(text.len());
        let field = String::from_utf8_lossy(&text[pos..end]);
        let field = field.trim();
        if !field.is_empty() {
            match real(field) {
                Some(v) => out.push(v),
                None => {
                    fixed_ok = false;
                    break;
                }
            }
        }
        pos = end;
        i += 1;
    }
    if fixed_ok {
        return Ok(out);
    }
    tokens(text)
        .iter()
        .map(|t| real(t).ok_or_else(|| t.clone()))
        .collect()
}
