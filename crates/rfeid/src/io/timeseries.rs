//! Time series files (SPEC §3): CSV with a header row, a `time` column (s)
//! and one column per signal, SI units. Files are written with commas and
//! `time` first; files read may also be separated by semicolons or tabs, as
//! acquisition systems write them, with the columns in any order.
use super::atomic::{format_number, write_atomically};
use std::path::{Path, PathBuf};

/// Sampled signals sharing one time axis.
#[derive(Debug, Clone, PartialEq)]
pub struct TimeSeries {
    /// Sample instants, s.
    pub time: Vec<f64>,
    /// Column names, without `time`.
    pub names: Vec<String>,
    /// One vector per name, each as long as `time`.
    pub columns: Vec<Vec<f64>>,
}

impl TimeSeries {
    /// The column with this name.
    pub fn column(&self, name: &str) -> Option<&[f64]> {
        self.names
            .iter()
            .position(|n| n == name)
            .map(|i| self.columns[i].as_slice())
    }
}

/// A problem with a data file; names the file, the line and the column.
#[derive(Debug, thiserror::Error)]
pub enum DataError {
    /// The file could not be read or written.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// Malformed CSV.
    #[error("{}: line {line}: {message}", path.display())]
    Csv {
        /// The file.
        path: PathBuf,
        /// 1-based line.
        line: u64,
        /// What is wrong.
        message: String,
    },
    /// No `time` column.
    #[error("{}: no column 'time' (columns: {found}); the separator may be ',', ';' or a tab", path.display())]
    NoTime {
        /// The file.
        path: PathBuf,
        /// The header's columns.
        found: String,
    },
    /// A number written with a decimal comma.
    #[error("{}: line {line}, column '{column}': '{text}' has a decimal comma; rfeid reads numbers with a decimal point: export the file with '.' as the decimal separator", path.display())]
    DecimalComma {
        /// The file.
        path: PathBuf,
        /// 1-based line.
        line: u64,
        /// Column name.
        column: String,
        /// The text found.
        text: String,
    },
    /// A value that is not a finite number.
    #[error("{}: line {line}, column '{column}': '{text}' is not a finite number", path.display())]
    BadValue {
        /// The file.
        path: PathBuf,
        /// 1-based line.
        line: u64,
        /// Column name.
        column: String,
        /// The text found.
        text: String,
    },
    /// Two columns of the same name.
    #[error("{}: column '{column}' appears twice", path.display())]
    DuplicateColumn {
        /// The file.
        path: PathBuf,
        /// Column name.
        column: String,
    },
    /// Time not strictly increasing.
    #[error("{}: line {line}: time {time} does not increase", path.display())]
    TimeNotIncreasing {
        /// The file.
        path: PathBuf,
        /// 1-based line.
        line: u64,
        /// The time value.
        time: f64,
    },
    /// No data rows.
    #[error("{}: no data rows", path.display())]
    Empty {
        /// The file.
        path: PathBuf,
    },
}

/// The field separators [`read_csv`] recognises.
pub const SEPARATORS: [u8; 3] = [b',', b';', b'\t'];

/// The separator of a CSV file, from its header line: the one of `,`, `;`
/// and tab that occurs most often in it (a comma on a tie, or when none
/// occurs: a file with one column).
pub fn detect_separator(header: &str) -> u8 {
    let mut best = b',';
    let mut most = header.bytes().filter(|&b| b == b',').count();
    for sep in [b';', b'\t'] {
        let n = header.bytes().filter(|&b| b == sep).count();
        if n > most {
            best = sep;
            most = n;
        }
    }
    best
}

/// Reads a time-series CSV. The separator (`,`, `;` or tab) is detected
/// from the header line ([`detect_separator`]); the `time` column may be
/// anywhere, the other columns in any order. Every value must be a finite
/// number with a decimal point, and time must increase strictly.
pub fn read_csv(path: &Path) -> Result<TimeSeries, DataError> {
    let text = std::fs::read(path).map_err(|source| DataError::Io {
        path: path.into(),
        source,
    })?;
    let header = text.split(|&b| b == b'\n').next().unwrap_or_default();
    let separator = detect_separator(&String::from_utf8_lossy(header));
    let mut rdr = csv::ReaderBuilder::new()
        .delimiter(separator)
        .trim(csv::Trim::All)
        .from_reader(text.as_slice());
    let headers = rdr.headers().map_err(|e| csv_error(path, e))?.clone();
    let (time_col, names) = column_names(path, &headers)?;
    let mut ts = TimeSeries {
        time: Vec::new(),
        columns: vec![Vec::new(); names.len()],
        names,
    };
    for rec in rdr.records() {
        let rec = rec.map_err(|e| csv_error(path, e))?;
        push_record(path, &mut ts, &rec, &headers, time_col)?;
    }
    if ts.time.is_empty() {
        return Err(DataError::Empty { path: path.into() });
    }
    Ok(ts)
}

/// A CSV reader's error as a [`DataError::Csv`] with its line.
fn csv_error(path: &Path, e: csv::Error) -> DataError {
    DataError::Csv {
        path: path.into(),
        line: e.position().map(|p| p.line()).unwrap_or(0),
        message: match e.kind() {
            csv::ErrorKind::UnequalLengths {
                expected_len, len, ..
            } => {
                format!("{len} fields where the header has {expected_len}")
            }
            _ => e.to_string(),
        },
    }
}

/// The `time` column's index and the other columns' names, which must be distinct.
fn column_names(
    path: &Path,
    headers: &csv::StringRecord,
) -> Result<(usize, Vec<String>), DataError> {
    let Some(time_col) = headers.iter().position(|h| h == "time") else {
        return Err(DataError::NoTime {
            path: path.into(),
            found: headers.iter().collect::<Vec<_>>().join(", "),
        });
    };
    let names: Vec<String> = headers
        .iter()
        .enumerate()
        .filter(|&(j, _)| j != time_col)
        .map(|(_, h)| h.to_string())
        .collect();
    for (i, n) in names.iter().enumerate() {
        if n == "time" || names[..i].contains(n) {
            return Err(DataError::DuplicateColumn {
                path: path.into(),
                column: n.clone(),
            });
        }
    }
    Ok((time_col, names))
}

/// Appends one data row to `ts`; its time must exceed the previous row's.
fn push_record(
    path: &Path,
    ts: &mut TimeSeries,
    rec: &csv::StringRecord,
    headers: &csv::StringRecord,
    time_col: usize,
) -> Result<(), DataError> {
    let line = rec.position().map(|p| p.line()).unwrap_or(0);
    for (j, field) in rec.iter().enumerate() {
        let v = parse_value(path, line, headers.get(j).unwrap_or(""), field)?;
        if j == time_col {
            if let Some(&last) = ts.time.last() {
                if v <= last {
                    return Err(DataError::TimeNotIncreasing {
                        path: path.into(),
                        line,
                        time: v,
                    });
                }
            }
            ts.time.push(v);
        } else {
            ts.columns[j - usize::from(j > time_col)].push(v);
        }
    }
    Ok(())
}

/// One field as a finite number; a decimal comma gets its own error.
fn parse_value(path: &Path, line: u64, column: &str, field: &str) -> Result<f64, DataError> {
    match field.parse().ok().filter(|v: &f64| v.is_finite()) {
        Some(v) => Ok(v),
        None if decimal_comma(field) => Err(DataError::DecimalComma {
            path: path.into(),
            line,
            column: column.to_string(),
            text: field.to_string(),
        }),
        None => Err(DataError::BadValue {
            path: path.into(),
            line,
            column: column.to_string(),
            text: field.to_string(),
        }),
    }
}

/// Whether `field` is a finite number written with a decimal comma
/// (`0,0024`, `-1,5e-3`).
fn decimal_comma(field: &str) -> bool {
    field.matches(',').count() == 1
        && field
            .replace(',', ".")
            .parse::<f64>()
            .is_ok_and(f64::is_finite)
}

/// Writes a time series as CSV text: a `time` column, then one column per
/// series, numbers that read back exactly.
pub fn write_csv_to(w: &mut dyn std::io::Write, ts: &TimeSeries) -> std::io::Result<()> {
    write!(w, "time")?;
    for n in &ts.names {
        write!(w, ",{n}")?;
    }
    writeln!(w)?;
    for (k, t) in ts.time.iter().enumerate() {
        write!(w, "{}", format_number(*t))?;
        for c in &ts.columns {
            write!(w, ",{}", format_number(c[k]))?;
        }
        writeln!(w)?;
    }
    Ok(())
}

/// Writes a time-series CSV atomically.
pub fn write_csv(path: &Path, ts: &TimeSeries) -> Result<(), DataError> {
    write_atomically(path, |w| write_csv_to(w, ts)).map_err(|source| DataError::Io {
        path: path.into(),
        source,
    })
}
