//! Excitation signals and the `[simulation]` table.
use super::ctx::*;
use crate::io::model_file::raw::*;
use crate::io::timeseries::read_csv;
use crate::model::*;
use crate::units::Dimension;
use std::ops::Range;
use toml::Spanned;

pub(super) fn signal(
    ctx: &mut Ctx,
    sig: &Spanned<RawSignal>,
    entry: &str,
    raw: &RawFile,
) -> Result<Signal> {
    let rs = sig.get_ref();
    let kind_raw = required(ctx, &rs.kind, sig.span(), entry, "signal.type")?;
    let kind: &'static str = match kind_raw.get_ref().trim() {
        "sine" => "sine",
        "multisine" => "multisine",
        "chirp" => "chirp",
        "impulse" => "impulse",
        "table" => "table",
        other => {
            return Err(ctx.err(
                Some(kind_raw.span()),
                entry,
                "signal.type",
                format!("unknown signal type '{other}' (sine, multisine, chirp, impulse or table)"),
            ))
        }
    };
    // Keys that do not belong to this type are errors, like unknown keys.
    let allowed: &[&str] = match kind {
        "sine" => &["amplitude", "frequency", "phase"],
        "multisine" => &["components"],
        "chirp" => &["amplitude", "f0", "f1", "duration"],
        "impulse" => &["amplitude", "t0", "width"],
        _ => &["amplitude", "file", "column"],
    };
    let present: [(&str, Option<Range<usize>>); 11] = [
        ("amplitude", rs.amplitude.as_ref().map(|v| v.span())),
        ("frequency", rs.frequency.as_ref().map(|v| v.span())),
        ("phase", rs.phase.as_ref().map(|v| v.span())),
        ("components", rs.components.as_ref().map(|v| v.span())),
        ("f0", rs.f0.as_ref().map(|v| v.span())),
        ("f1", rs.f1.as_ref().map(|v| v.span())),
        ("duration", rs.duration.as_ref().map(|v| v.span())),
        ("t0", rs.t0.as_ref().map(|v| v.span())),
        ("width", rs.width.as_ref().map(|v| v.span())),
        ("file", rs.file.as_ref().map(|v| v.span())),
        ("column", rs.column.as_ref().map(|v| v.span())),
    ];
    for (key, span) in present {
        if let Some(span) = span {
            if !allowed.contains(&key) {
                return Err(ctx.err(
                    Some(span),
                    entry,
                    &format!("signal.{key}"),
                    format!(
                        "'{key}' does not apply to a {kind} signal (it takes {})",
                        allowed.join(", ")
                    ),
                ));
            }
        }
    }
    let f = Dimension::FORCE;
    let hz = Dimension::FREQUENCY;
    let s = Dimension::TIME;
    let one = Dimension::DIMENSIONLESS;
    let req = |ctx: &Ctx, v: &Option<SNum>, field: &str, dim: Dimension| -> Result<f64> {
        ctx.number(
            required(ctx, v, sig.span(), entry, &format!("signal.{field}"))?,
            dim,
            entry,
            &format!("signal.{field}"),
        )
    };
    let amplitude = |ctx: &mut Ctx, v: &Option<SNum>, default: Option<f64>| -> Result<Value> {
        match (v, default) {
            (Some(v), _) => ctx.value(v, f, entry, "signal.amplitude"),
            (None, Some(d)) => Ok(Value::Fixed(d)),
            (None, None) => Err(ctx.err(
                Some(sig.span()),
                entry,
                "signal.amplitude",
                "'amplitude' is missing",
            )),
        }
    };
    let positive = |ctx: &Ctx, x: f64, field: &str| -> Result<f64> {
        if x > 0.0 {
            Ok(x)
        } else {
            Err(ctx.err(
                Some(sig.span()),
                entry,
                &format!("signal.{field}"),
                format!("must be positive (found {x})"),
            ))
        }
    };
    let terms = match kind {
        "sine" => {
            let frequency = req(ctx, &rs.frequency, "frequency", hz)?;
            let phase = rs
                .phase
                .as_ref()
                .map(|p| ctx.number(p, one, entry, "signal.phase"))
                .transpose()?
                .unwrap_or(0.0);
            vec![Term {
                amplitude: amplitude(ctx, &rs.amplitude, None)?,
                shape: Shape::Sine { frequency, phase },
            }]
        }
        "multisine" => {
            let comps = required(ctx, &rs.components, sig.span(), entry, "signal.components")?;
            if comps.get_ref().is_empty() {
                return Err(ctx.err(
                    Some(comps.span()),
                    entry,
                    "signal.components",
                    "a multisine needs at least one component",
                ));
            }
            let mut terms = Vec::new();
            for tone in comps.get_ref() {
                let t = tone.get_ref();
                let fr = ctx.number(
                    required(
                        ctx,
                        &t.frequency,
                        tone.span(),
                        entry,
                        "signal.components.frequency",
                    )?,
                    hz,
                    entry,
                    "signal.components.frequency",
                )?;
                let phase = t
                    .phase
                    .as_ref()
                    .map(|p| ctx.number(p, one, entry, "signal.components.phase"))
                    .transpose()?
                    .unwrap_or(0.0);
                let a = ctx.value(
                    required(
                        ctx,
                        &t.amplitude,
                        tone.span(),
                        entry,
                        "signal.components.amplitude",
                    )?,
                    f,
                    entry,
                    "signal.components.amplitude",
                )?;
                terms.push(Term {
                    amplitude: a,
                    shape: Shape::Sine {
                        frequency: fr,
                        phase,
                    },
                });
            }
            terms
        }
        "chirp" => {
            let f0 = req(ctx, &rs.f0, "f0", hz)?;
            let f1 = req(ctx, &rs.f1, "f1", hz)?;
            let duration = match &rs.duration {
                Some(d) => positive(ctx, ctx.number(d, s, entry, "signal.duration")?, "duration")?,
                None => simulation_duration(ctx, raw)?,
            };
            vec![Term {
                amplitude: amplitude(ctx, &rs.amplitude, None)?,
                shape: Shape::Chirp { f0, f1, duration },
            }]
        }
        "impulse" => {
            let t0 = req(ctx, &rs.t0, "t0", s)?;
            let width = positive(ctx, req(ctx, &rs.width, "width", s)?, "width")?;
            vec![Term {
                amplitude: amplitude(ctx, &rs.amplitude, None)?,
                shape: Shape::Impulse { t0, width },
            }]
        }
        _ => {
            let file = required(ctx, &rs.file, sig.span(), entry, "signal.file")?;
            let column = required(ctx, &rs.column, sig.span(), entry, "signal.column")?;
            let path = ctx.dir.join(file.get_ref());
            ctx.files.borrow_mut().push(path.clone());
            let ts = read_csv(&path)
                .map_err(|e| ctx.err(Some(file.span()), entry, "signal.file", e.to_string()))?;
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
            vec![Term {
                amplitude: amplitude(ctx, &rs.amplitude, Some(1.0))?,
                shape: Shape::Table { times, values },
            }]
        }
    };
    Ok(Signal { kind, terms })
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

pub(super) fn simulation_duration(ctx: &Ctx, raw: &RawFile) -> Result<f64> {
    sampling(ctx, raw).map(|s| s.duration)
}

pub(super) fn sampling(ctx: &Ctx, raw: &RawFile) -> Result<Sampling> {
    let entry = "[simulation]";
    let sim = raw.simulation.as_ref().ok_or_else(|| {
        ctx.err(
            None,
            entry,
            "",
            "the model has no [simulation] table (duration, sample_rate)",
        )
    })?;
    let rs = sim.get_ref();
    let duration = ctx.number(
        required(ctx, &rs.duration, sim.span(), entry, "duration")?,
        Dimension::TIME,
        entry,
        "duration",
    )?;
    let rate_raw = required(ctx, &rs.sample_rate, sim.span(), entry, "sample_rate")?;
    let sample_rate = ctx.number(rate_raw, Dimension::FREQUENCY, entry, "sample_rate")?;
    if !(duration > 0.0) {
        return Err(ctx.err(
            rs.duration.as_ref().map(|d| d.span()),
            entry,
            "duration",
            "must be positive",
        ));
    }
    if !(sample_rate > 0.0) {
        return Err(ctx.err(
            Some(rate_raw.span()),
            entry,
            "sample_rate",
            "must be positive",
        ));
    }
    let n = (duration * sample_rate).round();
    if !(2.0..=1e8).contains(&n) {
        return Err(ctx.err(
            Some(sim.span()),
            entry,
            "duration",
            format!("duration × sample_rate gives {n} samples; it must be 2 to 1e8"),
        ));
    }
    let substeps = match &rs.substeps {
        None => None,
        Some(s) if (1..=crate::simulation::MAX_SUBSTEPS as i64).contains(s.get_ref()) => {
            Some(*s.get_ref() as usize)
        }
        Some(s) => {
            return Err(ctx.err(
                Some(s.span()),
                entry,
                "substeps",
                "must be a whole number from 1 to 1000",
            ))
        }
    };
    let tolerance = match &rs.tolerance {
        None => crate::simulation::DEFAULT_TOLERANCE,
        Some(t) => {
            let v = ctx.number(t, Dimension::DIMENSIONLESS, entry, "tolerance")?;
            if !crate::simulation::TOLERANCE_RANGE.contains(&v) {
                return Err(ctx.err(
                    Some(t.span()),
                    entry,
                    "tolerance",
                    crate::simulation::steps::tolerance_range_text(),
                ));
            }
            v
        }
    };
    Ok(Sampling {
        duration,
        sample_rate,
        substeps,
        tolerance,
    })
}
