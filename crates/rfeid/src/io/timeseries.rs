//! Time series files (SPEC §3): CSV with a header row, a `time` column (s),
//! then one column per sensor, SI units.
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
    /// No `time` column first.
    #[error("{}: the first column must be 'time' (found '{found}')", path.display())]
    NoTime {
        /// The file.
        path: PathBuf,
        /// The first header.
        found: String,
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

/// Reads a time-series CSV. Every value must be a finite number and time
/// must increase strictly.
pub fn read_csv(path: &Path) -> Result<TimeSeries, DataError> {
    let file = std::fs::File::open(path).map_err(|source| DataError::Io {
        path: path.into(),
        source,
    })?;
    let mut rdr = csv::ReaderBuilder::new()
        .trim(csv::Trim::All)
        .from_reader(std::io::BufReader::new(file));
    let csv_err = |e: csv::Error| DataError::Csv {
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
    };
    let headers = rdr.headers().map_err(csv_err)?.clone();
    let first = headers.get(0).unwrap_or("").to_string();
    if first != "time" {
        return Err(DataError::NoTime {
            path: path.into(),
            found: first,
        });
    }
    let names: Vec<String> = headers.iter().skip(1).map(str::to_string).collect();
    for (i, n) in names.iter().enumerate() {
        if n == "time" || names[..i].contains(n) {
            return Err(DataError::DuplicateColumn {
                path: path.into(),
                column: n.clone(),
            });
        }
    }
    let mut ts = TimeSeries {
        time: Vec::new(),
        columns: vec![Vec::new(); names.len()],
        names,
    };
    for rec in rdr.records() {
        let rec = rec.map_err(csv_err)?;
        let line = rec.position().map(|p| p.line()).unwrap_or(0);
        for (j, field) in rec.iter().enumerate() {
            let v: f64 = field
                .parse()
                .ok()
                .filter(|v: &f64| v.is_finite())
                .ok_or_else(|| DataError::BadValue {
                    path: path.into(),
                    line,
                    column: headers.get(j).unwrap_or("").to_string(),
                    text: field.to_string(),
                })?;
            if j == 0 {
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
                ts.columns[j - 1].push(v);
            }
        }
    }
    if ts.time.is_empty() {
        return Err(DataError::Empty { path: path.into() });
    }
    Ok(ts)
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
