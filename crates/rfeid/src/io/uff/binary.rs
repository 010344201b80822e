//! The binary data block of a `58b` record (and of other binary datasets).
//!
//! The 58b header line (`I6,A1,I6,I6,I12,I12,I6,I6,I12,I12`) gives the byte
//! order (1 little-endian, 2 big-endian), the floating-point format (2 IEEE
//! 754; 1 DEC VMS and 3 IBM 370 are not supported), the number of ASCII
//! header lines (11 for dataset 58) and the number of bytes of binary data.
//! The data follow the header's last line ending at once, in the order the
//! ASCII format would list them, and the closing `    -1` follows the data
//! at once (some writers put a line ending between them; both are read).
//!
//! Writers disagree on two things, so the block's extent is checked against
//! that closing line rather than trusted: for uneven abscissa the abscissa
//! may be stored in the ordinate's precision or in single precision, and
//! some writers (pyuff 2.5) announce the size of the ordinates alone.
use super::error::Ctx;
use super::lines::Line;
use super::UffError;

/// The numbers of a binary header line that matter here.
#[derive(Debug, Clone, Copy)]
pub struct BinaryHeader {
    /// Little-endian data.
    pub little: bool,
    /// Floating-point format code (2 = IEEE 754).
    pub fp_format: i64,
    /// Number of ASCII header lines after this one.
    pub n_ascii: usize,
    /// Number of bytes of binary data.
    pub n_bytes: usize,
}

/// Parses the dataset header line of a binary dataset (`    58b     1     2 …`).
pub fn header(head: &Line<'_>, ctx: &Ctx<'_>) -> Result<BinaryHeader, UffError> {
    let f = super::fields::fixed(head.text, &[6, 1, 6, 6, 12, 12]);
    let mut v: Vec<Option<i64>> = f[2..6].iter().map(|s| super::fields::int(s)).collect();
    if v.iter().any(Option::is_none) {
        // Not in the columns: take the blank-separated numbers after the 'b'.
        let text = head.text.get(7..).unwrap_or_default();
        let t = super::fields::tokens(text);
        v = t.iter().take(4).map(|s| super::fields::int(s)).collect();
    }
    let get = |i: usize| v.get(i).copied().flatten();
    let (Some(order), Some(fp), Some(n_ascii), Some(n_bytes)) = (get(0), get(1), get(2), get(3))
    else {
        return Err(ctx.malformed(
            head,
            format!(
                "the binary dataset header needs byte order, floating-point format, \
                 ASCII line count and byte count, found '{}'",
                head.excerpt()
            ),
        ));
    };
    let little = match order {
        1 => true,
        2 => false,
        _ => {
            return Err(ctx.malformed(
                head,
                format!("byte ordering {order} (1 little-endian, 2 big-endian)"),
            ))
        }
    };
    let count = |n: i64, what: &str| {
        usize::try_from(n).map_err(|_| ctx.malformed(head, format!("negative {what} {n}")))
    };
    Ok(BinaryHeader {
        little,
        fp_format: fp,
        n_ascii: count(n_ascii, "ASCII line count")?,
        n_bytes: count(n_bytes, "byte count")?,
    })
}

/// Where the closing `-1` line after binary data at `p` ends, if it is
/// there (directly, or after one line ending).
pub fn delimiter_after(bytes: &[u8], p: usize) -> Option<usize> {
    let mut q = p;
    let rest = bytes.get(q..)?;
    if rest.starts_with(b"\r\n") {
        q += 2;
    } else if rest.starts_with(b"\n") {
        q += 1;
    }
    let rest = &bytes[q..];
    let (len, adv) = match rest.iter().position(|&b| b == b'\n') {
        Some(i) => (i, i + 1),
        None => (rest.len(), rest.len()),
    };
    (rest[..len].trim_ascii() == b"-1").then_some(q + adv)
}

/// The layout of one record's binary block.
#[derive(Debug, Clone, Copy)]
pub struct Layout {
    /// Points.
    pub n: usize,
    /// Bytes of one ordinate number (4 or 8).
    pub size: usize,
    /// Numbers per ordinate (1 real, 2 complex).
    pub per_point: usize,
    /// Bytes of an abscissa value: 0 for even spacing, else 4 or 8.
    pub x_size: usize,
}

/// Finds the layout whose data are followed by the closing `-1`, trying
/// the header's byte count first; returns it with the offset past the
/// closing line.
pub fn locate(
    bytes: &[u8],
    start: usize,
    n_bytes: usize,
    base: Layout,
    uneven: bool,
    ctx: &Ctx<'_>,
    at: &Line<'_>,
) -> Result<(Layout, usize), UffError> {
    let x_sizes: &[usize] = match (uneven, base.size) {
        (false, _) => &[0],
        (true, 8) => &[8, 4],
        (true, _) => &[4],
    };
    let mut candidates = Vec::new();
    for &x in x_sizes {
        let per = x + base.per_point * base.size;
        let len = base.n.checked_mul(per).ok_or_else(|| {
            ctx.malformed(at, format!("{} points overflow the data size", base.n))
        })?;
        candidates.push((Layout { x_size: x, ..base }, len));
    }
    candidates.sort_by_key(|&(_, len)| len != n_bytes);
    for &(layout, len) in &candidates {
        if let Some(end) = start
            .checked_add(len)
            .and_then(|p| delimiter_after(bytes, p))
        {
            return Ok((layout, end));
        }
    }
    let len = candidates[0].1;
    let left = bytes.len().saturating_sub(start);
    if len > left {
        return Err(ctx.truncated(
            bytes,
            bytes.len(),
            format!("the binary data need {len} bytes from byte {start}, the file has {left}"),
        ));
    }
    Err(ctx.malformed(
        at,
        format!(
            "no closing '    -1' right after the {len} bytes of binary data from byte {start} \
             (the header announces {n_bytes})"
        ),
    ))
}

/// Decodes the block at `start` in file order (per point: the abscissa if
/// stored, then the ordinate numbers), as `f64`.
pub fn decode(bytes: &[u8], start: usize, layout: Layout, little: bool) -> Vec<f64> {
    let num = |p: usize, size: usize| -> f64 {
        let b = &bytes[p..p + size];
        if size == 4 {
            let mut a = [0u8; 4];
            a.copy_from_slice(b);
            (if little {
                f32::from_le_bytes(a)
            } else {
                f32::from_be_bytes(a)
            }) as f64
        } else {
            let mut a = [0u8; 8];
            a.copy_from_slice(b);
            if little {
                f64::from_le_bytes(a)
            } else {
                f64::from_be_bytes(a)
            }
        }
    };
    let stride = usize::from(layout.x_size > 0) + layout.per_point;
    let mut out = Vec::with_capacity(layout.n * stride);
    let mut p = start;
    for _ in 0..layout.n {
        if layout.x_size > 0 {
            out.push(num(p, layout.x_size));
            p += layout.x_size;
        }
        for _ in 0..layout.per_point {
            out.push(num(p, layout.size));
            p += layout.size;
        }
    }
    out
}
