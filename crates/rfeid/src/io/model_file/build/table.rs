//! Table signals: a column of a CSV file or a variable of a MAT-file (by
//! the file's extension, as measured data), which must cover the simulated
//! time, interpolated linearly or as a band-limited signal (SPEC §1).
use super::ctx::*;
use super::signal::Sig;
use super::simulation::sampling;
use crate::io::data_file::{check_time_axis, mat_time_axis, DataFormat};
use crate::io::mat::read_mat_vectors;
use crate::io::model_file::raw::*;
use crate::io::timeseries::read_csv;
use crate::model::*;
use std::path::Path;
use toml::Spanned;

/// A table's samples as read, with the key that named them.
struct Samples<'a> {
    times: Vec<f64>,
    values: Vec<f64>,
    /// `column` or `variable`, with the name it gives.
    key: &'a Spanned<String>,
    field: &'static str,
    /// `column 'force'`, `variable 'V1'`: for messages.
    what: String,
}

/// A `table` signal's one term: the file's column or variable, checked
/// against the simulated time, with its `interpolation`.
pub(super) fn table(ctx: &mut Ctx, s: &Sig, raw: &RawFile) -> Result<Term> {
    let (rs, entry) = (s.raw(), s.entry);
    let band_limited = band_limited_key(ctx, s)?;
    let file = required(ctx, &rs.file, s.sig.span(), entry, "signal.file")?;
    let path = ctx.dir.join(file.get_ref());
    ctx.files.borrow_mut().push(path.clone());
    let sampling = sampling(ctx, raw)?;
    let read = if DataFormat::of(&path) == Some(DataFormat::Mat) {
        mat_samples(ctx, s, file, &path, sampling.sample_rate)?
    } else {
        csv_samples(ctx, s, file, &path)?
    };
    check_values(ctx, &read, &path, entry)?;
    if let Some(message) = table_gap(&read.times, &read.values, sampling) {
        return Err(ctx.err(
            Some(file.span()),
            entry,
            "signal.file",
            format!("{}: {}: {message}", path.display(), read.what),
        ));
    }
    let Samples {
        mut times,
        values,
        what,
        ..
    } = read;
    snap_ends(&mut times, sampling);
    let shape = match band_limited {
        None => Shape::linear_table(times, values),
        Some(key) => Shape::band_limited_table(times, values).map_err(|e| {
            ctx.err(
                Some(key.span()),
                entry,
                "signal.interpolation",
                format!("{}: {what}: {e}", path.display()),
            )
        })?,
    };
    Ok(Term {
        amplitude: s.amplitude(ctx, Some(1.0))?,
        shape,
    })
}

/// The key `interpolation` when it asks for `band-limited`; `None` for
/// `linear`, the default. Any other name is an error listing both.
fn band_limited_key<'a>(ctx: &Ctx, s: &'a Sig) -> Result<Option<&'a Spanned<String>>> {
    let Some(key) = &s.raw().interpolation else {
        return Ok(None);
    };
    match key.get_ref().trim() {
        "linear" => Ok(None),
        "band-limited" => Ok(Some(key)),
        other => Err(ctx.err(
            Some(key.span()),
            s.entry,
            "signal.interpolation",
            format!("unknown interpolation '{other}' (linear or band-limited)"),
        )),
    }
}

/// The key that names the signal (`column` of a CSV file, `variable` of a
/// MAT-file); the other one is an error.
fn name_key<'a>(
    ctx: &Ctx,
    s: &'a Sig,
    (key, field): (&'a Option<Spanned<String>>, &'static str),
    (other, other_field): (&Option<Spanned<String>>, &str),
    kind: &str,
) -> Result<&'a Spanned<String>> {
    if let Some(o) = other {
        return Err(ctx.err(
            Some(o.span()),
            s.entry,
            &format!("signal.{other_field}"),
            format!("'{other_field}' does not apply to a {kind}: write {field} = \"…\""),
        ));
    }
    required(ctx, key, s.sig.span(), s.entry, &format!("signal.{field}"))
}

/// A CSV table: its `time` column and the `column`.
fn csv_samples<'a>(
    ctx: &Ctx,
    s: &'a Sig,
    file: &Spanned<String>,
    path: &Path,
) -> Result<Samples<'a>> {
    let rs = s.raw();
    let column = name_key(
        ctx,
        s,
        (&rs.column, "column"),
        (&rs.variable, "variable"),
        "CSV file",
    )?;
    let ts = read_csv(path)
        .map_err(|e| ctx.err(Some(file.span()), s.entry, "signal.file", e.to_string()))?;
    let values = ts
        .column(column.get_ref())
        .ok_or_else(|| {
            ctx.err(
                Some(column.span()),
                s.entry,
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
    Ok(Samples {
        times: ts.time,
        values,
        key: column,
        field: "signal.column",
        what: format!("column '{}'", column.get_ref()),
    })
}

/// A MAT-file table: the `variable`, on the file's time axis (a `time`
/// vector, a `sample_rate`, or else the model's grid from t = 0, with a
/// note), as for measured data.
fn mat_samples<'a>(
    ctx: &Ctx,
    s: &'a Sig,
    file: &Spanned<String>,
    path: &Path,
    rate: f64,
) -> Result<Samples<'a>> {
    let rs = s.raw();
    let variable = name_key(
        ctx,
        s,
        (&rs.variable, "variable"),
        (&rs.column, "column"),
        "MAT-file",
    )?;
    let name = variable.get_ref().as_str();
    let file_err = |e: String| ctx.err(Some(file.span()), s.entry, "signal.file", e);
    let mat = read_mat_vectors(path).map_err(|e| file_err(e.to_string()))?;
    let values = mat
        .require_vector(name)
        .map_err(|e| {
            ctx.err(
                Some(variable.span()),
                s.entry,
                "signal.variable",
                e.to_string(),
            )
        })?
        .to_vec();
    let axis =
        mat_time_axis(&mat, values.len(), rate, &[name]).map_err(|e| file_err(e.to_string()))?;
    check_time_axis(path, &axis.axis, &axis.time).map_err(|e| file_err(e.to_string()))?;
    if axis.time.len() != values.len() {
        return Err(file_err(format!(
            "{}: variable '{name}' has {} samples, the time axis ({}) has {}",
            path.display(),
            values.len(),
            axis.axis,
            axis.time.len()
        )));
    }
    ctx.notes.borrow_mut().extend(axis.note);
    Ok(Samples {
        times: axis.time,
        values,
        key: variable,
        field: "signal.variable",
        what: format!("variable '{name}'"),
    })
}

/// The table must have samples, each finite and below the data limit.
fn check_values(ctx: &Ctx, read: &Samples, path: &Path, entry: &str) -> Result<()> {
    let err = |message: String| {
        ctx.err(
            Some(read.key.span()),
            entry,
            read.field,
            format!("{}: {}{message}", path.display(), read.what),
        )
    };
    if read.values.is_empty() {
        return Err(err(" has no samples".into()));
    }
    let limit = crate::io::data_file::MAX_DATA_MAGNITUDE;
    if let Some(k) = read.values.iter().position(|v| !v.is_finite()) {
        return Err(err(format!(
            ", sample {k} is {}, not a finite number",
            read.values[k]
        )));
    }
    if let Some(k) = read.values.iter().position(|v| v.abs() > limit) {
        return Err(err(format!(
            ", sample {k} is {:e}; table values must be below {limit:e} in magnitude",
            read.values[k]
        )));
    }
    Ok(())
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

#[cfg(test)]
mod tests {
    use crate::io::model_file::parse_model;
    use crate::model::Model;

    /// A unit mass on a spring driven by the table `force.csv` (t, push),
    /// 10 samples at 100 Hz, its signal given `extra` keys; the error's text
    /// if it fails.
    fn model(name: &str, rows: &[(f64, f64)], extra: &str) -> Result<Model, String> {
        let dir =
            std::env::temp_dir().join(format!("rfeid-band-limited-{}-{name}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let csv: String = rows.iter().map(|(t, v)| format!("{t},{v}\n")).collect();
        std::fs::write(dir.join("force.csv"), format!("time,push\n{csv}")).unwrap();
        let text = format!(
            r#"
[simulation]
duration = 0.1
sample_rate = 100.0

[[body]]
name = "mass"
mass = 1.0
inertia = [1.0, 1.0, 1.0]
com = [0.0, 0.0, 0.0]

[[element]]
name = "spring"
body = "mass"
to = "ground"
at = [0.0, 0.0, 0.0]
ux = {{ k = 1.0e4 }}

[[excitation]]
name = "shaker"
body = "mass"
at = [0.0, 0.0, 0.0]
direction = [1, 0, 0]
signal = {{ type = "table", file = "force.csv", column = "push"{extra} }}

[[sensor]]
name = "x"
body = "mass"
at = [0.0, 0.0, 0.0]
direction = [1, 0, 0]
quantity = "displacement"
"#
        );
        let result = parse_model(&text, &dir.join("model.toml")).map_err(|e| e.to_string());
        std::fs::remove_dir_all(&dir).unwrap();
        result
    }

    fn even() -> Vec<(f64, f64)> {
        (0..16)
            .map(|k| (k as f64 / 100.0, (k as f64 * 0.7).sin()))
            .collect()
    }

    #[test]
    fn band_limited_is_read_and_linear_stays_the_default() {
        let band = model("read", &even(), r#", interpolation = "band-limited""#).unwrap();
        let shape = &band.excitations[0].signal.terms[0].shape;
        assert_eq!(shape.breakpoints(), vec![0.0, 0.15]);
        for extra in ["", r#", interpolation = "linear""#] {
            let linear = model("linear", &even(), extra).unwrap();
            assert_eq!(
                linear.excitations[0].signal.terms[0]
                    .shape
                    .breakpoints()
                    .len(),
                16
            );
        }
    }

    #[test]
    fn band_limited_errors_name_the_file_the_entry_and_the_field() {
        let mut rows = even();
        rows[5].0 = 0.052;
        let uneven = model("uneven", &rows, r#", interpolation = "band-limited""#).unwrap_err();
        for part in [
            "model.toml",
            "excitation \"shaker\"",
            "signal.interpolation",
            "force.csv",
            "column 'push'",
            "sample 5 is at t = 0.052 s",
            "evenly spaced",
        ] {
            assert!(uneven.contains(part), "{part}: {uneven}");
        }
        // Unevenly spaced samples remain fine for linear interpolation.
        assert!(model("uneven-linear", &rows, "").is_ok());
        let unknown = model("unknown", &even(), r#", interpolation = "cubic""#).unwrap_err();
        for part in ["signal.interpolation", "'cubic'", "linear or band-limited"] {
            assert!(unknown.contains(part), "{part}: {unknown}");
        }
    }
}
