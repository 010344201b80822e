//! Universal File Format (UFF, "universal files", `.uff`/`.unv`) dataset 58,
//! function at nodal DOF: the format vibration test systems export time
//! signals and spectra in, ASCII or binary (`58b`).
//!
//! A universal file is a sequence of datasets, each between two lines
//! holding `-1` in columns 1–6; the line after the opening `-1` holds the
//! dataset number (`    58`, or `    58b` followed by the binary layout).
//! Datasets other than 58 (units 164, header 151, geometry 15/2411 …) are
//! skipped. The layout of a dataset-58 record is described in
//! `uff/record.rs` and `uff/header.rs`, the 58b data block in
//! `uff/binary.rs`.
//!
//! Records are numbered 1, 2, … in the order of the dataset-58 records in
//! the file (other datasets are not counted), and named by ID line 1. Real
//! data (ordinate types 2 and 4) are read as `f64`; complex records
//! (types 5, 6) are recognized and skipped, and asking for one is an error.
//! ASCII values are read as the decimal text says (a single-precision
//! record's `E13.5` text is not rounded to `f32`); binary single-precision
//! values are widened to `f64` exactly.
//!
//! Malformed input gives an error naming the file, the record or dataset
//! and the line and byte offset, never a panic.
mod binary;
mod error;
mod fields;
mod file;
mod header;
mod lines;
mod record;
mod skip;
mod types;

pub use error::{Context, UffError};
pub use file::UffFile;
pub use types::{Abscissa, OrdinateType, UffRecord};

use error::Ctx;
use lines::Cursor;
use std::path::Path;

/// Reads the dataset-58 records of a universal file.
pub fn read_uff58(path: &Path) -> Result<UffFile, UffError> {
    let bytes = std::fs::read(path).map_err(|source| UffError::Io {
        path: path.into(),
        source,
    })?;
    parse_uff58(&bytes, path)
}

/// Parses the bytes of a universal file; `path` names it in errors.
pub fn parse_uff58(bytes: &[u8], path: &Path) -> Result<UffFile, UffError> {
    let mut cur = Cursor::new(bytes);
    let mut records = Vec::new();
    let mut datasets = 0usize;
    while let Some(start) = cur.next_nonblank() {
        if !start.is_delimiter() {
            let message = format!(
                "expected '    -1' (the start of a dataset), found '{}'",
                start.excerpt()
            );
            return Err(if datasets == 0 {
                UffError::NotUff {
                    path: path.into(),
                    line: start.number,
                    message,
                }
            } else {
                UffError::Structure {
                    path: path.into(),
                    line: start.number,
                    offset: start.offset,
                    message,
                }
            });
        }
        let Some(head) = cur.next_line() else {
            return Err(UffError::Structure {
                path: path.into(),
                line: start.number,
                offset: start.offset,
                message: "the file ends after a dataset's opening '-1'".into(),
            });
        };
        if !head.complete && head.text.trim_ascii().is_empty() {
            return Err(UffError::Structure {
                path: path.into(),
                line: start.number,
                offset: start.offset,
                message: "the file ends after a dataset's opening '-1'".into(),
            });
        }
        let id = fields::fixed(head.text, &[6, 1]);
        let number = fields::int(&id[0]).ok_or_else(|| UffError::Structure {
            path: path.into(),
            line: head.number,
            offset: head.offset,
            message: format!("expected a dataset number, found '{}'", head.excerpt()),
        })?;
        let is_binary = id[1].eq_ignore_ascii_case("b");
        datasets += 1;
        let ctx = Ctx {
            path,
            context: Context {
                dataset: number,
                record: (number == 58).then_some(records.len() + 1),
                start_line: start.number,
            },
        };
        if number == 58 {
            records.push(record::parse_58(&mut cur, &head, is_binary, &ctx)?);
        } else {
            skip::skip(&mut cur, &head, is_binary, &ctx)?;
        }
    }
    if datasets == 0 {
        return Err(UffError::NotUff {
            path: path.into(),
            line: 1,
            message: "the file holds no dataset".into(),
        });
    }
    Ok(UffFile {
        path: path.into(),
        records,
    })
}
