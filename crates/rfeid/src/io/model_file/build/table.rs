//! Table signals: a column of a CSV file, which must cover the simulated time.
use super::ctx::*;
use super::signal::Sig;
use super::simulation::sampling;
use crate::io::model_file::raw::*;
use crate::io::timeseries::{read_csv, TimeSeries};
use crate::model::*;
use std::path::Path;
use toml::Spanned;

/// A `table` signal's one term: the file's column, checked against the simulated time.
pub(super) fn table(ctx: &mut Ctx, s: &Sig, raw: &RawFile) -> Result<Term> {
    let (rs, entry) = (s.raw(), s.entry);
    let file = required(ctx, &rs.file, s.sig.span(), entry, "signal.file")?;
    let column = required(ctx, &rs.column, s.sig.span(), entry, "signal.column")?;
    let path = ctx.dir.join(file.get_ref());
    ctx.files.borrow_mut().push(path.clone());
    let ts = read_csv(&path)
        .map_err(|e| ctx.err(Some(file.span()), entry, "signal.file", e.to_string()))?;
    let values = table_column(ctx, &ts, column, &path, entry)?;
    let sampling = sampling(ctx, raw)?;
    if let Some(message) = table_gap(&ts.time, &values, sampling) {
        return Err(ctx.err(
            Some(file.span()),
            entry,
            "signal.file",
            format!(
                "{}: column '{}': {message}",
                path.display(),
                column.get_ref()
            ),
        ));
    }
    let mut times = ts.time;
    snap_ends(&mut times, sampling);
    Ok(Term {
        amplitude: s.amplitude(ctx, Some(1.0))?,
        shape: Shape::Table { times, values },
    })
}

/// The table's `column`, which must exist and hold values below the data limit.
fn table_column(
    ctx: &Ctx,
    ts: &TimeSeries,
    column: &Spanned<String>,
    path: &Path,
    entry: &str,
) -> Result<Vec<f64>> {
    let values = ts
        .column(column.get_ref())
        .ok_or_else(|| {
            ctx.err(
                Some(column.span()),
                entry,
                "signal.column",
                format!(
                    "no column '{}' in {} (columns: {})",
                    column.get_ref(),
                    path.display(),
                    ts.names.join(", ")
                ),
            )
        })?
        .to_vec();
    let limit = crate::io::data_file::MAX_DATA_MAGNITUDE;
    if let Some(k) = values.iter().position(|v| v.abs() > limit) {
        return Err(ctx.err(
            Some(column.span()),
            entry,
            "signal.column",
            format!(
                "{}: column '{}', sample {k} is {:e}; table values must be below {limit:e} in magnitude",
                path.display(),
                column.get_ref(),
                values[k]
            ),
        ));
    }
    Ok(values)
}

/// Why a force table does not cover the simulated samples t = 0 … (n−1)/rate,
/// if it does not: outside its span a table gives 0, so a table that stops
/// (or starts) inside the simulated time at a nonzero value makes the force
/// jump to 0 there — a short record or a time column in ms. Both spans are
/// named. A table whose value at such an end is 0 is taken as meaning "0
/// from there on", as SPEC §1 says. The ends may miss by the grid tolerance
/// of measured records ([`GRID_TOLERANCE`](crate::measurement::GRID_TOLERANCE)
/// of a sample interval, plus float32 rounding).
fn table_gap(times: &[f64], values: &[f64], sampling: Sampling) -> Option<String> {
    let (&first, &last) = (times.first()?, times.last()?);
    let (&v_first, &v_last) = (values.first()?, values.last()?);
    let dt = 1.0 / sampling.sample_rate;
    let end = sampling.time(sampling.n_samples().saturating_sub(1));
    let slack = |t: f64| crate::measurement::GRID_TOLERANCE * dt + t.abs() / 16_777_216.0;
    let late = first > slack(first) && v_first != 0.0;
    let early = last < end - slack(end) && v_last != 0.0;
    if !late && !early {
        return None;
    }
    let (at, value) = if late {
        ("starts", v_first)
    } else {
        ("ends", v_last)
    };
    Some(format!(
        "the table spans t = {first} … {last} s, but the simulation samples t = 0 … {end} s; \
         it {at} at the value {value}, and a table gives 0 outside its span, so the force \
         would jump to 0: extend the table over the simulated time (check that its time is \
         in seconds), or shorten [simulation] duration"
    ))
}

/// Moves a table's first instant to t = 0 and its last to the last
/// simulated sample when they miss them by no more than [`table_gap`]
/// accepts (float32 stamps: 0.048999998 for 0.049): otherwise the table,
/// 0 outside its span, would give 0 at that sample. The change is below
/// 10⁻³ of a sample interval plus float32 rounding.
fn snap_ends(times: &mut [f64], sampling: Sampling) {
    let dt = 1.0 / sampling.sample_rate;
    let end = sampling.time(sampling.n_samples().saturating_sub(1));
    let slack = |t: f64| crate::measurement::GRID_TOLERANCE * dt + t.abs() / 16_777_216.0;
    let n = times.len();
    if n >= 2 {
        if times[0] > 0.0 && times[0] <= slack(times[0]) && times[1] > 0.0 {
            times[0] = 0.0;
        }
        if times[n - 1] < end && times[n - 1] >= end - slack(end) && times[n - 2] < end {
            times[n - 1] = end;
        }
    }
}
