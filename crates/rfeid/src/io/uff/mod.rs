//! Universal File Format (UFF, "universal files", `.uff`/`.unv`) dataset 58,
//! function at nodal DOF: the format vibration test systems export time
//! signals and spectra in, ASCII or binary (`58b`).
//!
//! A universal file is a sequence of datasets, each between two lines
//! holding `-1` in columns 1–6; the line after the opening `-1` holds the
//! dataset number (`    58`, or `    58b` followed by the binary layout).
//! Datasets other than 58 (units 164, header 151, geometry 15/2411 …) are
//! skipped. See [`record`] for the layout of a dataset-58 record and
//! [`binary`] for the 58b data block.
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
pub mod binary;
mod error;
mod fields;
mod lines;
pub mod record;

pub use error::{Context, UffError};

use lines::Cursor;
use record::Ctx;
use serde::de::{self, Deserializer, Visitor};
use std::fmt;
use std::path::{Path, PathBuf};

/// A function record, by its 1-based number among the file's dataset-58
/// records, or by its name (ID line 1).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum RecordRef {
    /// The n-th function record, counting from 1.
    Index(usize),
    /// The record whose ID line 1 is this (trimmed).
    Name(String),
}

impl fmt::Display for RecordRef {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            RecordRef::Index(n) => write!(f, "{n}"),
            RecordRef::Name(s) => write!(f, "'{s}'"),
        }
    }
}

impl<'de> serde::Deserialize<'de> for RecordRef {
    /// From an integer ≥ 1 (`record = 3`) or a string (`record = "acc_x"`).
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl Visitor<'_> for V {
            type Value = RecordRef;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str("a record number (1, 2, …) or a record name (ID line 1)")
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<RecordRef, E> {
                if v < 1 {
                    return Err(E::custom(format!(
                        "record {v}: records are numbered from 1"
                    )));
                }
                self.visit_u64(v as u64)
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<RecordRef, E> {
                match usize::try_from(v) {
                    Ok(n) if n >= 1 => Ok(RecordRef::Index(n)),
                    _ => Err(E::custom(format!(
                        "record {v}: records are numbered from 1"
                    ))),
                }
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<RecordRef, E> {
                if v.trim().is_empty() {
                    return Err(E::custom("an empty record name"));
                }
                Ok(RecordRef::Name(v.to_string()))
            }
        }
        d.deserialize_any(V)
    }
}

/// The ordinate data type of record 7.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OrdinateType {
    /// 2: real, single precision.
    RealSingle,
    /// 4: real, double precision.
    RealDouble,
    /// 5: complex, single precision.
    ComplexSingle,
    /// 6: complex, double precision.
    ComplexDouble,
}

impl OrdinateType {
    /// From the code in record 7.
    pub fn from_code(code: i64) -> Option<Self> {
        Some(match code {
            2 => OrdinateType::RealSingle,
            4 => OrdinateType::RealDouble,
            5 => OrdinateType::ComplexSingle,
            6 => OrdinateType::ComplexDouble,
            _ => return None,
        })
    }

    /// The code in record 7.
    pub fn code(self) -> i64 {
        match self {
            OrdinateType::RealSingle => 2,
            OrdinateType::RealDouble => 4,
            OrdinateType::ComplexSingle => 5,
            OrdinateType::ComplexDouble => 6,
        }
    }

    /// Types 5 and 6.
    pub fn is_complex(self) -> bool {
        matches!(
            self,
            OrdinateType::ComplexSingle | OrdinateType::ComplexDouble
        )
    }
}

impl fmt::Display for OrdinateType {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let s = match self {
            OrdinateType::RealSingle => "real single",
            OrdinateType::RealDouble => "real double",
            OrdinateType::ComplexSingle => "complex single",
            OrdinateType::ComplexDouble => "complex double",
        };
        write!(f, "{s} ({})", self.code())
    }
}

/// The abscissa (time, frequency …) of a record.
#[derive(Debug, Clone, PartialEq)]
pub enum Abscissa {
    /// Even spacing: x_k = min + k · increment, k = 0 … count − 1.
    Even {
        /// Abscissa minimum.
        min: f64,
        /// Abscissa increment.
        increment: f64,
        /// Number of points.
        count: usize,
    },
    /// Uneven spacing: the values as stored.
    Uneven(Vec<f64>),
}

impl Abscissa {
    /// The abscissa values.
    pub fn values(&self) -> Vec<f64> {
        match self {
            Abscissa::Even {
                min,
                increment,
                count,
            } => (0..*count).map(|k| min + k as f64 * increment).collect(),
            Abscissa::Uneven(x) => x.clone(),
        }
    }
}

/// One dataset-58 function record.
#[derive(Debug, Clone, PartialEq)]
pub struct UffRecord {
    /// 1-based number among the file's dataset-58 records.
    pub number: usize,
    /// Line of the record's opening `-1`.
    pub line: usize,
    /// Stored as binary `58b`.
    pub binary: bool,
    /// ID lines 1–5, trimmed; line 1 is the record's name.
    pub id_lines: [String; 5],
    /// Function type (record 6 field 1): 0 general, 1 time response, 4 FRF …
    pub function_type: i64,
    /// Response node.
    pub response_node: i64,
    /// Response direction: ±1 … ±3 translation X, Y, Z; ±4 … ±6 rotation; 0 scalar.
    pub response_direction: i64,
    /// Reference node.
    pub reference_node: i64,
    /// Reference direction.
    pub reference_direction: i64,
    /// Ordinate data type.
    pub ordinate_type: OrdinateType,
    /// Number of points.
    pub num_points: usize,
    /// Abscissa specific data type (record 8 field 1): 17 time, 18 frequency …
    pub abscissa_data_type: i64,
    /// Ordinate specific data type (record 9 field 1): 8 displacement, 11
    /// velocity, 12 acceleration …
    pub ordinate_data_type: i64,
    /// The abscissa (for complex records with uneven spacing, as read).
    pub abscissa: Abscissa,
    /// The real ordinates; empty for complex records.
    pub values: Vec<f64>,
}

impl UffRecord {
    /// ID line 1, the record's name.
    pub fn name(&self) -> &str {
        &self.id_lines[0]
    }
}

/// The function records of a universal file.
#[derive(Debug, Clone, PartialEq)]
pub struct UffFile {
    path: PathBuf,
    records: Vec<UffRecord>,
}

impl UffFile {
    /// The file read.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The dataset-58 records in file order.
    pub fn records(&self) -> &[UffRecord] {
        &self.records
    }

    /// The record with this 1-based number.
    pub fn record(&self, number: usize) -> Option<&UffRecord> {
        number.checked_sub(1).and_then(|i| self.records.get(i))
    }

    /// The first record named `name` (ID line 1, trimmed).
    pub fn by_name(&self, name: &str) -> Option<&UffRecord> {
        self.records.iter().find(|r| r.name() == name)
    }

    /// The record `r` refers to, or an error: no such record (listing them),
    /// or a name that several records carry.
    pub fn find(&self, r: &RecordRef) -> Result<&UffRecord, UffError> {
        let found = match r {
            RecordRef::Index(n) => self.record(*n),
            RecordRef::Name(name) => {
                let all: Vec<&UffRecord> =
                    self.records.iter().filter(|x| x.name() == name).collect();
                if all.len() > 1 {
                    let nums: Vec<String> = all.iter().map(|x| x.number.to_string()).collect();
                    return Err(UffError::Ambiguous {
                        path: self.path.clone(),
                        name: name.clone(),
                        records: nums.join(", "),
                    });
                }
                all.first().copied()
            }
        };
        found.ok_or_else(|| UffError::UnknownRecord {
            path: self.path.clone(),
            wanted: r.to_string(),
            available: if self.records.is_empty() {
                "none".into()
            } else {
                let list: Vec<String> = self
                    .records
                    .iter()
                    .map(|x| format!("{} '{}'", x.number, x.name()))
                    .collect();
                list.join(", ")
            },
        })
    }

    /// As [`find`](Self::find), and the record must hold real data.
    pub fn real_record(&self, r: &RecordRef) -> Result<&UffRecord, UffError> {
        let rec = self.find(r)?;
        if rec.ordinate_type.is_complex() {
            return Err(UffError::Complex {
                path: self.path.clone(),
                record: rec.number,
                name: rec.name().to_string(),
                ordinate: rec.ordinate_type.to_string(),
            });
        }
        Ok(rec)
    }
}

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
            record::skip(&mut cur, &head, is_binary, &ctx)?;
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
