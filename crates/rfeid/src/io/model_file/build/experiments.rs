//! `[[experiment]]` entries (SPEC §5): the tests of a campaign.
use super::ctx::*;
use crate::io::model_file::raw::*;
use crate::model::*;
use crate::units::{parse_quantity, Dimension};
use std::collections::HashMap;
use std::path::PathBuf;

/// What the rest of the model file declares, which experiments refer to.
struct Declared<'a> {
    parameters: &'a [Parameter],
    excitations: &'a [Excitation],
    sensors: &'a [Sensor],
    /// The candidate sensors (`candidate = true`), which no test measures.
    candidates: &'a [Sensor],
    sampling: &'a Sampling,
}

/// Reads every `[[experiment]]`; if there are any, one at least must be fitted.
pub(super) fn experiments(
    ctx: &Ctx,
    raw: &RawFile,
    parameters: &[Parameter],
    excitations: &[Excitation],
    (sensors, candidates): (&[Sensor], &[Sensor]),
    sampling: &Sampling,
) -> Result<Vec<Experiment>> {
    let declared = Declared {
        parameters,
        excitations,
        sensors,
        candidates,
        sampling,
    };
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
        out.push(experiment(ctx, x, name, &entry, &declared)?);
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

/// One `[[experiment]]`: data file, set values, record, excitations, sensors, use, weight.
fn experiment(
    ctx: &Ctx,
    x: &toml::Spanned<RawExperiment>,
    name: String,
    entry: &str,
    declared: &Declared,
) -> Result<Experiment> {
    let rx = x.get_ref();
    let data = data_path(ctx, x, entry)?;
    let set = set_values(ctx, rx, entry, declared.parameters)?;
    let duration = positive(ctx, &rx.duration, Dimension::TIME, entry, "duration")?;
    let sample_rate = positive(
        ctx,
        &rx.sample_rate,
        Dimension::FREQUENCY,
        entry,
        "sample_rate",
    )?;
    check_samples(ctx, x, entry, duration, sample_rate, declared.sampling)?;
    let from = from(
        ctx,
        rx,
        entry,
        duration.unwrap_or(declared.sampling.duration),
    )?;
    let names_e: Vec<&str> = declared
        .excitations
        .iter()
        .map(|e| e.name.as_str())
        .collect();
    let excitations = pick(
        ctx,
        &rx.excitations,
        (&names_e, &[]),
        entry,
        "excitations",
        true,
    )?;
    let names_s: Vec<&str> = declared.sensors.iter().map(|s| s.name.as_str()).collect();
    let names_c: Vec<&str> = declared
        .candidates
        .iter()
        .map(|s| s.name.as_str())
        .collect();
    let sensors = pick(
        ctx,
        &rx.sensors,
        (&names_s, &names_c),
        entry,
        "sensors",
        false,
    )?;
    let role = role(ctx, rx, entry)?;
    if let (Some(list), Role::Fit) = (&rx.excitations, &role) {
        // A validation test may record a free or ambient response; a fitted
        // one without an excitation would fit a response that is zero.
        if list.get_ref().is_empty() {
            return Err(ctx.err(
                Some(list.span()),
                entry,
                "excitations",
                "the list is empty: nothing excites this test, so its simulated response is zero and there is nothing to fit (list its excitations, or give it use = \"validation\")",
            ));
        }
    }
    let weight = weight(ctx, rx, entry)?;
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

/// The experiment's data file, relative to the model file's folder.
fn data_path(ctx: &Ctx, x: &toml::Spanned<RawExperiment>, entry: &str) -> Result<PathBuf> {
    let data_raw = required(ctx, &x.get_ref().data, x.span(), entry, "data")?;
    if data_raw.get_ref().trim().is_empty() {
        return Err(ctx.err(Some(data_raw.span()), entry, "data", "the path is empty"));
    }
    Ok(ctx.dir.join(data_raw.get_ref().trim()))
}

/// The experiment's `set` table, item by item in file order.
fn set_values(
    ctx: &Ctx,
    rx: &RawExperiment,
    entry: &str,
    parameters: &[Parameter],
) -> Result<Vec<(usize, f64)>> {
    let mut set = Vec::new();
    if let Some(table) = &rx.set {
        for (key, v) in table.get_ref() {
            set.push(set_value(ctx, key, v, table.span(), entry, parameters)?);
        }
    }
    Ok(set)
}

/// An optional positive number of dimension `dim`.
fn positive(
    ctx: &Ctx,
    v: &Option<SNum>,
    dim: Dimension,
    entry: &str,
    field: &str,
) -> Result<Option<f64>> {
    let Some(v) = v else { return Ok(None) };
    let n = ctx.number(v, dim, entry, field)?;
    if !(n > 0.0) {
        return Err(ctx.err(Some(v.span()), entry, field, "must be positive"));
    }
    Ok(Some(n))
}

/// The experiment's record (its own duration and rate, or the simulation's) has 2 to 1e8 samples.
fn check_samples(
    ctx: &Ctx,
    x: &toml::Spanned<RawExperiment>,
    entry: &str,
    duration: Option<f64>,
    sample_rate: Option<f64>,
    sampling: &Sampling,
) -> Result<()> {
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
    Ok(())
}

/// Where the fit starts, in [0, `end`) s; 0 when absent.
fn from(ctx: &Ctx, rx: &RawExperiment, entry: &str, end: f64) -> Result<f64> {
    let Some(v) = &rx.from else { return Ok(0.0) };
    let t = ctx.number(v, Dimension::TIME, entry, "from")?;
    if !(t >= 0.0 && t < end) {
        return Err(ctx.err(
            Some(v.span()),
            entry,
            "from",
            format!("must lie in [0, {end}) s, the experiment's record"),
        ));
    }
    Ok(t)
}

/// The experiment's `use`: fit (the default) or validation.
fn role(ctx: &Ctx, rx: &RawExperiment, entry: &str) -> Result<Role> {
    let Some(r) = &rx.role else {
        return Ok(Role::Fit);
    };
    match r.get_ref().trim() {
        "fit" => Ok(Role::Fit),
        "validation" => Ok(Role::Validation),
        other => Err(ctx.err(
            Some(r.span()),
            entry,
            "use",
            format!("unknown use '{other}' (fit or validation)"),
        )),
    }
}

/// The experiment's positive weight; 1 when absent.
fn weight(ctx: &Ctx, rx: &RawExperiment, entry: &str) -> Result<f64> {
    let Some(w) = &rx.weight else { return Ok(1.0) };
    let v = ctx.number(w, Dimension::DIMENSIONLESS, entry, "weight")?;
    if !(v > 0.0) {
        return Err(ctx.err(Some(w.span()), entry, "weight", "must be positive"));
    }
    Ok(v)
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
        RawNum::Bool(b) => return Err(ctx.boolean(*b, v, entry, &field, false)),
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

/// Names from a list (`excitations` or `sensors`) as indices into `known`;
/// `None` when the list is not given. An empty list is allowed only where
/// `empty_ok`. A name of `unmeasured` (a candidate sensor) is refused as
/// such: it is declared, but no test records it.
fn pick(
    ctx: &Ctx,
    v: &Option<toml::Spanned<Vec<toml::Spanned<String>>>>,
    (known, unmeasured): (&[&str], &[&str]),
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
        let name = n.get_ref().trim();
        if unmeasured.contains(&name) {
            return Err(ctx.err(
                Some(n.span()),
                entry,
                field,
                format!(
                    "'{name}' is a candidate sensor (candidate = true), a place `rfeid design` \
                     may choose, not a measured one; a test's sensors are among {} (to measure \
                     it, remove its 'candidate = true')",
                    list(known)
                ),
            ));
        }
        let Some(k) = known.iter().position(|k| *k == name) else {
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
