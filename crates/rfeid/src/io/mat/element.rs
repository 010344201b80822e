//! Data elements of a Level 5 MAT-file.
//!
//! Every element starts with a tag: either 8 bytes (`u32` data type, `u32`
//! byte count), the payload, then zero padding to the next multiple of 8;
//! or, for payloads of at most 4 bytes, the *small element* form: one `u32`
//! whose upper 16 bits hold the byte count and lower 16 bits the type,
//! followed by the payload in the next 4 bytes. A small tag is recognized
//! by its non-zero upper 16 bits. Numbers are in the byte order the header
//! declares.
use super::error::{Location, MatError};
use std::path::Path;

/// `miINT8`.
pub const MI_INT8: u32 = 1;
/// `miUINT8`.
pub const MI_UINT8: u32 = 2;
/// `miINT16`.
pub const MI_INT16: u32 = 3;
/// `miUINT16`.
pub const MI_UINT16: u32 = 4;
/// `miINT32`.
pub const MI_INT32: u32 = 5;
/// `miUINT32`.
pub const MI_UINT32: u32 = 6;
/// `miSINGLE`.
pub const MI_SINGLE: u32 = 7;
/// `miDOUBLE`.
pub const MI_DOUBLE: u32 = 9;
/// `miINT64`.
pub const MI_INT64: u32 = 12;
/// `miUINT64`.
pub const MI_UINT64: u32 = 13;
/// `miMATRIX`: a MATLAB array, made of sub-elements.
pub const MI_MATRIX: u32 = 14;
/// `miCOMPRESSED`: a zlib stream holding one data element.
pub const MI_COMPRESSED: u32 = 15;
/// `miUTF8`.
pub const MI_UTF8: u32 = 16;

/// The name of a data type, for messages.
pub fn type_name(kind: u32) -> String {
    let name = match kind {
        MI_INT8 => "miINT8",
        MI_UINT8 => "miUINT8",
        MI_INT16 => "miINT16",
        MI_UINT16 => "miUINT16",
        MI_INT32 => "miINT32",
        MI_UINT32 => "miUINT32",
        MI_SINGLE => "miSINGLE",
        MI_DOUBLE => "miDOUBLE",
        MI_INT64 => "miINT64",
        MI_UINT64 => "miUINT64",
        MI_MATRIX => "miMATRIX",
        MI_COMPRESSED => "miCOMPRESSED",
        MI_UTF8 => "miUTF8",
        17 => "miUTF16",
        18 => "miUTF32",
        _ => return format!("unknown data type {kind}"),
    };
    name.to_string()
}

/// Byte order of the file, from the header's endian indicator.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Endian {
    /// `IM` in the file: little-endian.
    Little,
    /// `MI` in the file: big-endian.
    Big,
}

impl Endian {
    /// A `u16` from its bytes.
    pub fn u16(self, b: [u8; 2]) -> u16 {
        match self {
            Endian::Little => u16::from_le_bytes(b),
            Endian::Big => u16::from_be_bytes(b),
        }
    }

    /// A `u32` from its bytes.
    pub fn u32(self, b: [u8; 4]) -> u32 {
        match self {
            Endian::Little => u32::from_le_bytes(b),
            Endian::Big => u32::from_be_bytes(b),
        }
    }

    /// Bytes in the file's order, so that `from_le_bytes` reads them.
    fn le<const N: usize>(self, c: &[u8]) -> [u8; N] {
        let mut a = [0u8; N];
        a.copy_from_slice(c);
        if self == Endian::Big {
            a.reverse();
        }
        a
    }
}

/// Converts one number of the file to `f64`.
type Conv = fn(Endian, &[u8]) -> f64;

/// One data element.
#[derive(Debug, Clone, Copy)]
pub struct Element<'a> {
    /// Data type (`MI_*`).
    pub kind: u32,
    /// The payload.
    pub data: &'a [u8],
    /// Offset of the tag in its buffer.
    pub offset: usize,
    /// Offset of the payload in its buffer.
    pub data_start: usize,
    /// Offset just past the payload.
    pub data_end: usize,
    /// Offset of the next element: past the padding to 8 bytes.
    pub next: usize,
}

/// A buffer being read: the file, or one decompressed element, with what
/// errors need to say where they are.
#[derive(Debug, Clone, Copy)]
pub struct Buf<'a> {
    /// The bytes.
    pub bytes: &'a [u8],
    /// Their byte order.
    pub endian: Endian,
    /// File offset of the compressed element these bytes came from.
    pub compressed_at: Option<u64>,
    /// The file, for errors.
    pub path: &'a Path,
}

impl<'a> Buf<'a> {
    /// The location of `offset` in this buffer.
    pub fn at(&self, offset: usize) -> Location {
        Location {
            offset: offset as u64,
            compressed_at: self.compressed_at,
        }
    }

    /// A truncation error.
    pub fn truncated(
        &self,
        offset: usize,
        what: &str,
        needed: usize,
        available: usize,
    ) -> MatError {
        MatError::Truncated {
            path: self.path.into(),
            at: self.at(offset),
            what: what.to_string(),
            needed: needed as u64,
            available: available as u64,
        }
    }

    /// A format error.
    pub fn malformed(&self, offset: usize, message: String) -> MatError {
        MatError::Malformed {
            path: self.path.into(),
            at: self.at(offset),
            message,
        }
    }

    /// A `u32` at `pos` (the caller has checked the bounds).
    fn u32_at(&self, pos: usize) -> u32 {
        let mut a = [0u8; 4];
        a.copy_from_slice(&self.bytes[pos..pos + 4]);
        self.endian.u32(a)
    }

    /// Reads the element whose tag starts at `pos`; `end` is the end of the
    /// enclosing element (or of the buffer); `what` names it in errors.
    pub fn element(&self, pos: usize, end: usize, what: &str) -> Result<Element<'a>, MatError> {
        let end = end.min(self.bytes.len());
        let left = end.saturating_sub(pos);
        if left < 8 {
            return Err(self.truncated(pos, &format!("{what} (its tag)"), 8, left));
        }
        let first = self.u32_at(pos);
        if first >> 16 != 0 {
            let (kind, size) = (first & 0xffff, (first >> 16) as usize);
            if size > 4 {
                return Err(self.malformed(
                    pos,
                    format!("{what}: a small data element cannot hold {size} bytes (at most 4)"),
                ));
            }
            return Ok(Element {
                kind,
                data: &self.bytes[pos + 4..pos + 4 + size],
                offset: pos,
                data_start: pos + 4,
                data_end: pos + 4 + size,
                next: pos + 8,
            });
        }
        let size = self.u32_at(pos + 4) as usize;
        let start = pos + 8;
        if size > end - start {
            return Err(self.truncated(
                pos,
                &format!("{what} ({})", type_name(first)),
                size + 8,
                left,
            ));
        }
        let data_end = start + size;
        Ok(Element {
            kind: first,
            data: &self.bytes[start..data_end],
            offset: pos,
            data_start: start,
            data_end,
            // Padding to 8 bytes; clamped to the enclosing element so that a
            // missing final padding is tolerated.
            next: (start + size.div_ceil(8) * 8).min(end),
        })
    }

    /// The numbers of a numeric element as `f64` (64-bit integers beyond
    /// 2⁵³ are rounded); `name` names the variable in errors.
    pub fn numbers(&self, el: &Element<'_>, name: &str) -> Result<Vec<f64>, MatError> {
        let e = self.endian;
        let conv: (usize, Conv) = match el.kind {
            MI_INT8 => (1, |_, c| c[0] as i8 as f64),
            MI_UINT8 => (1, |_, c| c[0] as f64),
            MI_INT16 => (2, |e, c| i16::from_le_bytes(e.le(c)) as f64),
            MI_UINT16 => (2, |e, c| u16::from_le_bytes(e.le(c)) as f64),
            MI_INT32 => (4, |e, c| i32::from_le_bytes(e.le(c)) as f64),
            MI_UINT32 => (4, |e, c| u32::from_le_bytes(e.le(c)) as f64),
            MI_SINGLE => (4, |e, c| f32::from_le_bytes(e.le(c)) as f64),
            MI_DOUBLE => (8, |e, c| f64::from_le_bytes(e.le(c))),
            MI_INT64 => (8, |e, c| i64::from_le_bytes(e.le(c)) as f64),
            MI_UINT64 => (8, |e, c| u64::from_le_bytes(e.le(c)) as f64),
            other => {
                return Err(self.malformed(
                    el.offset,
                    format!(
                        "variable '{name}': its data is of type {}, which holds no numbers",
                        type_name(other)
                    ),
                ))
            }
        };
        let (width, f) = conv;
        if el.data.len() % width != 0 {
            return Err(self.malformed(
                el.offset,
                format!(
                    "variable '{name}': {} bytes of {} are not a whole number of values",
                    el.data.len(),
                    type_name(el.kind)
                ),
            ));
        }
        Ok(el.data.chunks_exact(width).map(|c| f(e, c)).collect())
    }
}
