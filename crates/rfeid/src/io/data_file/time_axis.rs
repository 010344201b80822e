//! The time axis of a MAT-file, shared by measured data
//! ([`read_measurement`](super::read_measurement)) and `table` excitation
//! signals of a model file.
//!
//! In order: a `time` (or `t`) vector; else t_k = k / rate from a
//! `sample_rate` (or `fs`) scalar; else, when nothing in the file could be
//! a time axis under another name, the model's grid t_k = k / sample_rate
//! from t = 0, with a note saying so (records such as the Silverbox
//! benchmark's store only their signals). A vector of the signals' length
//! that is not read as a signal and strictly increases looks like a time
//! axis under another name: then the samples' instants are ambiguous and
//! the file is refused ([`DataFileError::NoTimeAxis`]).
use super::DataFileError;
use crate::io::mat::MatFile;
use std::path::Path;

/// A MAT-file's time axis and where it came from.
#[derive(Debug, Clone, PartialEq)]
pub struct MatTimeAxis {
    /// Sample instants, s.
    pub time: Vec<f64>,
    /// Where they come from, for messages (`variable 'time'`, …).
    pub axis: String,
    /// A note for the user when the instants were assumed (no time axis in
    /// the file), naming the file.
    pub note: Option<String>,
}

/// The time axis of `file`, whose signals (the variables `signals`) have
/// `n` samples; `rate` is the model's sample rate, used only when the file
/// has no time axis of its own.
pub fn mat_time_axis(
    file: &MatFile,
    n: usize,
    rate: f64,
    signals: &[&str],
) -> Result<MatTimeAxis, DataFileError> {
    let path = file.path();
    if let Some(name) = ["time", "t"]
        .into_iter()
        .find(|v| file.variable(v).is_some())
    {
        return Ok(MatTimeAxis {
            time: file.require_vector(name)?.to_vec(),
            axis: format!("variable '{name}'"),
            note: None,
        });
    }
    if let Some(name) = ["sample_rate", "fs"]
        .into_iter()
        .find(|v| file.variable(v).is_some())
    {
        let v = file.require_vector(name)?;
        let r = match v {
            [r] if r.is_finite() && *r > 0.0 => *r,
            _ => {
                return Err(DataFileError::BadSampleRate {
                    path: path.into(),
                    name: name.into(),
                    found: format!("{v:?}"),
                })
            }
        };
        return Ok(MatTimeAxis {
            time: grid(n, r),
            axis: format!("{r} Hz from variable '{name}'"),
            note: None,
        });
    }
    if let Some(candidate) = time_like(file, n, signals) {
        return Err(DataFileError::NoTimeAxis {
            path: path.into(),
            candidate: candidate.into(),
            variables: file.names().join(", "),
        });
    }
    Ok(MatTimeAxis {
        time: grid(n, rate),
        axis: format!("the model's grid at {rate} Hz from t = 0"),
        note: Some(grid_note(path, rate)),
    })
}

/// t_k = k / rate, k = 0 … n − 1 (the model's own formula, so the samples
/// lie on its grid exactly).
fn grid(n: usize, rate: f64) -> Vec<f64> {
    (0..n).map(|k| k as f64 / rate).collect()
}

/// The note of an assumed time axis.
fn grid_note(path: &Path, rate: f64) -> String {
    format!(
        "{}: no time axis (no 'time', 't', 'sample_rate' or 'fs' variable): sample k is \
         taken at t = k / {rate} Hz, on the model's grid from t = 0",
        path.display()
    )
}

/// A variable that is not one of the `signals`, has `n` ≥ 2 samples and
/// strictly increases: a time axis under another name, if there is one.
fn time_like<'f>(file: &'f MatFile, n: usize, signals: &[&str]) -> Option<&'f str> {
    file.variables()
        .iter()
        .filter(|v| !signals.contains(&v.name.as_str()))
        .find(|v| {
            let x = file.vector(&v.name).unwrap_or_default();
            n >= 2 && x.len() == n && x.windows(2).all(|w| w[1] > w[0])
        })
        .map(|v| v.name.as_str())
}

/// Checks that a time axis is finite and strictly increasing; `axis` says
/// where it came from.
pub(crate) fn check_time_axis(path: &Path, axis: &str, time: &[f64]) -> Result<(), DataFileError> {
    let bad_time = |index: usize, message: String| DataFileError::BadTime {
        path: path.into(),
        axis: axis.into(),
        index,
        message,
    };
    for (k, &t) in time.iter().enumerate() {
        if !t.is_finite() {
            return Err(bad_time(k, format!("t = {t} is not a finite number")));
        }
        if k > 0 && !(t > time[k - 1]) {
            return Err(bad_time(k, format!("t = {t} s does not increase")));
        }
    }
    Ok(())
}
