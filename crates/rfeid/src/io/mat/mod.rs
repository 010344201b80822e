//! MATLAB Level 5 MAT-files (`save -v6` / `-v7`, scipy's `savemat`): numeric
//! vectors by variable name.
//!
//! The format (MathWorks, "MAT-File Format", Level 5): a 128-byte header —
//! 116 bytes of text, 8 bytes of subsystem-data offset, a `u16` version
//! (0x0100) and the endian indicator `IM` (little-endian file) or `MI`
//! (big-endian) — then data elements (tags: `mat/element.rs`). Each
//! variable is one `miMATRIX` element, or one `miCOMPRESSED` element whose
//! zlib stream inflates to an `miMATRIX` element (`-v7`, scipy's
//! `do_compression=True`); compressed elements are not padded.
//!
//! Every variable is read; classes double, single and int8 … uint64 are
//! converted to `f64` (int64/uint64 beyond 2⁵³ round), other classes (char,
//! cell, struct, logical, sparse, objects) are recorded by class only, so
//! asking for them as vectors gives a clear error. Level 4 files and v7.3
//! (HDF5) files are recognized and refused.
//!
//! Malformed input gives an error with the byte offset, never a panic;
//! memory grows only with the data actually present.
mod array;
mod element;
mod error;

pub use array::{MatClass, MatVariable};
pub use error::{Location, MatError};

use element::{Buf, Endian, MI_COMPRESSED, MI_MATRIX};
use std::io::Read;
use std::path::{Path, PathBuf};

/// The variables of a MAT-file.
#[derive(Debug, Clone, PartialEq)]
pub struct MatFile {
    path: PathBuf,
    variables: Vec<MatVariable>,
}

impl MatFile {
    /// The file read.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// All named variables, in file order.
    pub fn variables(&self) -> &[MatVariable] {
        &self.variables
    }

    /// The variable names, in file order.
    pub fn names(&self) -> Vec<&str> {
        self.variables.iter().map(|v| v.name.as_str()).collect()
    }

    /// The variable of this name.
    pub fn variable(&self, name: &str) -> Option<&MatVariable> {
        self.variables.iter().find(|v| v.name == name)
    }

    /// The values of a real numeric vector (1×N, N×1, 1×1 …); `None` if
    /// there is no such variable or it is not a real numeric vector.
    pub fn vector(&self, name: &str) -> Option<&[f64]> {
        self.require_vector(name).ok()
    }

    /// The values of a real numeric vector, or an error that says why not:
    /// unknown name (listing the variables), not numeric, complex, or a
    /// matrix.
    pub fn require_vector(&self, name: &str) -> Result<&[f64], MatError> {
        let path = self.path.clone();
        let v = self
            .variable(name)
            .ok_or_else(|| MatError::UnknownVariable {
                path: path.clone(),
                name: name.into(),
                available: if self.variables.is_empty() {
                    "none".into()
                } else {
                    self.names().join(", ")
                },
            })?;
        if !v.class.is_numeric() || v.logical {
            return Err(MatError::NotNumeric {
                path,
                name: name.into(),
                kind: v.describe(),
            });
        }
        if v.complex {
            return Err(MatError::Complex {
                path,
                name: name.into(),
            });
        }
        if !v.is_vector() {
            return Err(MatError::NotVector {
                path,
                name: name.into(),
                dims: v.dims_text(),
            });
        }
        Ok(&v.values)
    }
}

/// Reads a Level 5 MAT-file.
pub fn read_mat_vectors(path: &Path) -> Result<MatFile, MatError> {
    let bytes = std::fs::read(path).map_err(|source| MatError::Io {
        path: path.into(),
        source,
    })?;
    parse_mat(&bytes, path)
}

/// Parses the bytes of a Level 5 MAT-file; `path` names it in errors.
pub fn parse_mat(bytes: &[u8], path: &Path) -> Result<MatFile, MatError> {
    let endian = header(bytes, path)?;
    let file = Buf {
        bytes,
        endian,
        compressed_at: None,
        path,
    };
    let mut variables: Vec<MatVariable> = Vec::new();
    let mut pos = 128;
    while pos < bytes.len() {
        let el = file.element(pos, bytes.len(), "data element")?;
        let var = match el.kind {
            MI_MATRIX => array::parse_matrix(&file, &el)?,
            MI_COMPRESSED => {
                let inner = inflate(&file, el.data, el.offset)?;
                let buf = Buf {
                    bytes: &inner,
                    compressed_at: Some(el.offset as u64),
                    ..file
                };
                let iel = buf.element(0, inner.len(), "compressed data element")?;
                if iel.kind == MI_MATRIX {
                    array::parse_matrix(&buf, &iel)?
                } else {
                    None
                }
            }
            // Other top-level elements hold no variables.
            _ => None,
        };
        pos = if el.kind == MI_COMPRESSED {
            el.data_end
        } else {
            el.next
        };
        let Some(var) = var else { continue };
        if var.name.is_empty() {
            // The subsystem data (MATLAB objects' storage) has no name.
            continue;
        }
        if variables.iter().any(|v| v.name == var.name) {
            return Err(MatError::Duplicate {
                path: path.into(),
                name: var.name,
            });
        }
        variables.push(var);
    }
    Ok(MatFile {
        path: path.into(),
        variables,
    })
}

/// Checks the 128-byte header and returns the byte order.
fn header(bytes: &[u8], path: &Path) -> Result<Endian, MatError> {
    let not = |reason: &str| MatError::NotMat {
        path: path.into(),
        reason: reason.into(),
    };
    if bytes.starts_with(b"MATLAB 7.3") {
        return Err(not(
            "it is a v7.3 (HDF5) MAT-file; save it with '-v7' or '-v6' to read it here",
        ));
    }
    if bytes.len() < 128 {
        if bytes.starts_with(b"MATLAB") {
            return Err(MatError::Truncated {
                path: path.into(),
                at: Location {
                    offset: 0,
                    compressed_at: None,
                },
                what: "header".into(),
                needed: 128,
                available: bytes.len() as u64,
            });
        }
        return Err(not("the file is shorter than the 128-byte header"));
    }
    let endian = match &bytes[126..128] {
        b"IM" => Endian::Little,
        b"MI" => Endian::Big,
        _ => {
            return Err(not(
                "the endian indicator (bytes 126–127) is neither 'IM' nor 'MI' \
                 (Level 4 MAT-files are not supported)",
            ))
        }
    };
    let version = endian.u16([bytes[124], bytes[125]]);
    if version != 0x0100 {
        return Err(not(&format!(
            "header version 0x{version:04x} (Level 5 is 0x0100)"
        )));
    }
    Ok(endian)
}

/// Most bytes one compressed element may inflate to (1 GiB: 134 million
/// doubles, far beyond a measurement).
pub const MAX_INFLATED: usize = 1 << 30;

/// Most bytes deflate can produce per compressed byte (its longest match,
/// 258 bytes, costs at least 2 bits: 1032:1), plus a little for headers.
fn most_inflated(compressed: usize) -> usize {
    compressed.saturating_mul(1032).saturating_add(1024)
}

/// Inflates the zlib stream of the compressed element at file offset `at`:
/// the inner element's tag, then exactly the bytes it declares. A declared
/// size that `data` cannot hold (beyond deflate's 1032:1), or beyond
/// [`MAX_INFLATED`], is refused before inflating it.
fn inflate(file: &Buf<'_>, data: &[u8], at: usize) -> Result<Vec<u8>, MatError> {
    let inner = Buf {
        bytes: &[],
        compressed_at: Some(at as u64),
        ..*file
    };
    // `read_to_end` keeps what it read before an error, so `out.len()` is
    // what the stream gave.
    let fail = |e: std::io::Error, got: usize, what: &str, needed: usize| {
        if e.kind() == std::io::ErrorKind::UnexpectedEof {
            inner.truncated(0, what, needed, got)
        } else {
            inner.malformed(got, format!("cannot decompress: {e}"))
        }
    };
    let mut z = flate2::read::ZlibDecoder::new(data);
    let mut out = Vec::new();
    let tag_what = "compressed element (its tag)";
    if let Err(e) = (&mut z).take(8).read_to_end(&mut out) {
        return Err(fail(e, out.len(), tag_what, 8));
    }
    if out.len() < 8 {
        return Err(inner.truncated(0, tag_what, 8, out.len()));
    }
    let first = file.endian.u32([out[0], out[1], out[2], out[3]]);
    let size = if first >> 16 != 0 {
        0
    } else {
        file.endian.u32([out[4], out[5], out[6], out[7]]) as usize
    };
    let what = "compressed element";
    if size > most_inflated(data.len()) || size > MAX_INFLATED {
        return Err(inner.malformed(
            0,
            format!(
                "the compressed element declares {size} bytes, more than its {} compressed bytes \
                 can hold (deflate inflates at most 1032:1) or than the {MAX_INFLATED}-byte limit",
                data.len()
            ),
        ));
    }
    if let Err(e) = (&mut z).take(size as u64).read_to_end(&mut out) {
        return Err(fail(e, out.len(), what, size + 8));
    }
    if out.len() < size + 8 {
        return Err(inner.truncated(0, what, size + 8, out.len()));
    }
    Ok(out)
}
