//! `[[experiment]]` entries (SPEC §5): the tests of a campaign.
use super::ctx::*;
use crate::io::model_file::raw::*;
use crate::model::*;
use crate::units::{parse_quantity, Dimension};
use std::collections::HashMap;

pub(super) fn experiments(
    ctx: &Ctx,
    raw: &RawFile,
    parameters: &[Parameter],
    excitations: &[Excitation],
    sensors: &[Sensor],
    sampling: &Sampling,
) -> Result<Vec<Experiment>> {
    let mut seen = HashMap::new();
    let mut out = Vec::with_capacity(raw.experiment.len());
    for (i, x) in raw.experiment.iter().enumerate() {
        let (name, span) = name_of(ctx, &x.get_ref().name, x.span(), "experiment", i)?;
        let entry = format!("experiment \"{name}\"");
        if name.contains(['[', ']', ',', '"']) {
            return Err(ctx.err(
                Some(span),
                &entry,
                "name",
                "an experiment's name cannot contain brackets, commas or quotes",
            ));
        }
        check_unique(ctx, &mut seen, &name, span, "experiment", i)?;
        out.push(experiment(
            ctx,
            x,
            name,
            &entry,
            parameters,
            excitations,
            sensors,
            sampling,
        )?);
    }
    if !out.is_empty() && out.iter().all(|e| e.role == Role::Validation) {
        return Err(ctx.err(
            None,
            "",
            "experiment",
            "every experiment has use = \"validation\": none is left to fit",
        ));
    }
    Ok(out)
}

#[allow(clippy::too_many_arguments)]
fn experiment(
    ctx: &Ctx,
    x: &toml::Spanned<RawExperiment>,
    name: String,
    entry: &str,
    parameters: &[Parameter],
    excitations: &[Excitation],
    sensors: &[Sensor],
    sampling: &Sampling,
) -> Result<Experiment> {
    let rx = x.get_ref();
    let data_raw = required(ctx, &rx.data, x.span(), entry, "data")?;
    if data_raw.get_ref().trim().is_empty() {
        return Err(ctx.err(Some(data_raw.span()), entry, "data", "the path is empty"));
    }
    let data = ctx.dir.join(data_raw.get_ref().trim());
    let mut set = Vec::new();
    if let Some(table) = &rx.set {
        for (key, v) in table.get_ref() {
            set.push(set_value(ctx, key, v, table.span(), entry, parameters)?);
        }
    }
    let positive = |v: &Option<SNum>, dim: Dimension, field: &str| -> Result<Option<f64>> {
        let Some(v) = v else { return Ok(None) };
        let n = ctx.number(v, dim, entry, field)?;
        if !(n > 0.0) {
            return Err(ctx.err(Some(v.span()), entry, field, "must be positive"));
        }
        Ok(Some(n))
    };
    let duration = positive(&rx.duration, Dimension::TIME, "duration")?;
    let sample_rate = positive(&rx.sample_rate, Dimension::FREQUENCY, "sample_rate")?;
    let n = (duration.unwrap_or(sampling.duration) * sample_rate.unwrap_or(sampling.sample_rate))
        .round();
    if !(2.0..=1e8).contains(&n) {
        return Err(ctx.err(
            Some(x.span()),
            entry,
            if duration.is_some() {
                "duration"
            } else {
                "sample_rate"
            },
            format!("duration × sample_rate gives {n} samples; it must be 2 to 1e8"),
        ));
    }
    let from = match &rx.from {
        None => 0.0,
        Some(v) => {
            let t = ctx.number(v, Dimension::TIME, entry, "from")?;
            let end = duration.unwrap_or(sampling.duration);
            if !(t >= 0.0 && t < end) {
                return Err(ctx.err(
                    Some(v.span()),
                    entry,
                    "from",
                    format!("must lie in [0, {end}) s, the experiment's record"),
                ));
            }
            t
        }
    };
    let names_e: Vec<&str> = excitations.iter().map(|e| e.name.as_str()).collect();
    let excitations = pick(ctx, &rx.excitations, &names_e, entry, "excitations", true)?;
    let names_s: Vec<&str> = sensors.iter().map(|s| s.name.as_str()).collect();
    let sensors = pick(ctx, &rx.sensors, &names_s, entry, "sensors", false)?;
    let role = match &rx.role {
        None => Role::Fit,
        Some(r) => match r.get_ref().trim() {
            "fit" => Role::Fit,
            "validation" => Role::Validation,
            other => {
                return Err(ctx.err(
                    Some(r.span()),
                    entry,
                    "use",
                    format!("unknown use '{other}' (fit or validation)"),
                ))
            }
        },
    };
    let weight = match &rx.weight {
        None => 1.0,
        Some(w) => {
            let v = ctx.number(w, Dimension::DIMENSIONLESS, entry, "weight")?;
            if !(v > 0.0) {
                return Err(ctx.err(Some(w.span()), entry, "weight", "must be positive"));
            }
            v
        }
    };
    Ok(Experiment {
        name,
        data,
        set,
        from,
        duration,
        sample_rate,
        excitations,
        sensors,
        role,
        weight,
    })
}

/// One `set = { NAME = VALUE }` item: a fixed parameter and its value, SI.
fn set_value(
    ctx: &Ctx,
    key: &str,
    v: &SNum,
    table: std::ops::Range<usize>,
    entry: &str,
    parameters: &[Parameter],
) -> Result<(usize, f64)> {
    let field = format!("set.{key}");
    let Some(i) = parameters.iter().position(|p| p.name == key.trim()) else {
        let known: Vec<&str> = parameters.iter().map(|p| p.name.as_str()).collect();
        return Err(ctx.err(
            Some(table),
            entry,
            &field,
            format!("unknown parameter '{key}' (parameters: {})", list(&known)),
        ));
    };
    let p = &parameters[i];
    if p.bounds.is_some() {
        return Err(ctx.err(
            Some(v.span()),
            entry,
            &field,
            format!(
                "'{key}' is identified (it has 'min' and 'max'); only fixed parameters take a value \
                 per experiment (give it 'per_experiment = true' to identify one value per experiment)"
            ),
        ));
    }
    let value = match v.get_ref() {
        RawNum::Num(x) => ctx.finite(*x, v.span(), entry, &field)?,
        RawNum::Text(t) => {
            let q = parse_quantity(t)
                .map_err(|e| ctx.err(Some(v.span()), entry, &field, e.to_string()))?;
            if !bare(t) && q.dim != p.dimension {
                return Err(ctx.err(
                    Some(v.span()),
                    entry,
                    &field,
                    format!(
                        "'{t}' has the dimension {}, but {key} is {}",
                        q.dim, p.dimension
                    ),
                ));
            }
            ctx.finite(q.value, v.span(), entry, &field)?
        }
    };
    Ok((i, value))
}

/// Names from a list (`excitations` or `sensors`) as indices; `None` when
/// the list is not given. An empty list is allowed only where `empty_ok`.
fn pick(
    ctx: &Ctx,
    v: &Option<toml::Spanned<Vec<toml::Spanned<String>>>>,
    known: &[&str],
    entry: &str,
    field: &str,
    empty_ok: bool,
) -> Result<Option<Vec<usize>>> {
    let Some(list_raw) = v else { return Ok(None) };
    if list_raw.get_ref().is_empty() && !empty_ok {
        return Err(ctx.err(Some(list_raw.span()), entry, field, "the list is empty"));
    }
    let mut out: Vec<usize> = Vec::new();
    for n in list_raw.get_ref() {
        let Some(k) = known.iter().position(|k| *k == n.get_ref().trim()) else {
            return Err(ctx.err(
                Some(n.span()),
                entry,
                field,
                format!("unknown name '{}' (known: {})", n.get_ref(), list(known)),
            ));
        };
        if out.contains(&k) {
            return Err(ctx.err(
                Some(n.span()),
                entry,
                field,
                format!("'{}' is listed twice", n.get_ref()),
            ));
        }
        out.push(k);
    }
    out.sort_unstable();
    Ok(Some(out))
}
