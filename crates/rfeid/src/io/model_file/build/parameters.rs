//! Parameters: read first (so that fields can name them), then finished with
//! dimensions from their uses, boxes and units.
use super::ctx::*;
use crate::io::model_file::raw::*;
use crate::model::*;
use crate::units::{parse_quantity, Dimension};
use std::ops::Range;
use toml::Spanned;

/// A parameter's number as read: its SI value, its unit's dimension and symbol.
type ReadNumber = (f64, Option<Dimension>, String);

/// Reads every `[[parameter]]` into `ctx.params`, in file order.
pub(super) fn read_parameters(ctx: &mut Ctx, raw: &RawFile) -> Result<()> {
    for (i, p) in raw.parameter.iter().enumerate() {
        let draft = read_parameter(ctx, p, i)?;
        ctx.param_index.insert(draft.name.clone(), i);
        ctx.params.push(draft);
    }
    Ok(())
}

/// One `[[parameter]]`: name, value, box, unit, scale and per-experiment flag.
fn read_parameter(ctx: &Ctx, p: &Spanned<RawParameter>, i: usize) -> Result<ParamDraft> {
    let (name, span) = name_of(ctx, &p.get_ref().name, p.span(), "parameter", i)?;
    if ctx.param_index.contains_key(&name) {
        return Err(ctx.err(
            Some(span),
            &format!("parameter \"{name}\""),
            "name",
            "duplicate parameter name",
        ));
    }
    let entry = format!("parameter \"{name}\"");
    let rp = p.get_ref();
    let value_raw = required(ctx, &rp.value, p.span(), &entry, "value")?;
    let (value, vdim, sym) = read_number(ctx, value_raw, &entry, "value")?;
    let bounds = parameter_bounds(ctx, p, &entry, value_raw, value)?;
    let value_spans = [
        value_raw.span(),
        rp.min.as_ref().map_or(value_raw.span(), |v| v.span()),
        rp.max.as_ref().map_or(value_raw.span(), |v| v.span()),
    ];
    let unit = display_unit(&sym, value_raw);
    let scale = parameter_scale(ctx, rp, p.span(), &entry, bounds.map(|b| (b.0 .0, b.1 .0)))?;
    let per_experiment = per_experiment(ctx, rp, &entry, bounds.is_some())?;
    Ok(ParamDraft {
        per_experiment,
        name,
        span,
        value: (value, vdim),
        bounds,
        value_spans,
        unit,
        scale,
        uses: Vec::new(),
    })
}

/// A parameter's value or bound: a plain number, or a quantity with any unit.
fn read_number(ctx: &Ctx, v: &SNum, entry: &str, field: &str) -> Result<ReadNumber> {
    match v.get_ref() {
        RawNum::Bool(b) => Err(ctx.boolean(*b, v, entry, field, false)),
        RawNum::Num(x) => Ok((ctx.finite(*x, v.span(), entry, field)?, None, String::new())),
        RawNum::Text(t) => {
            let q = parse_quantity(t)
                .map_err(|e| ctx.err(Some(v.span()), entry, field, e.to_string()))?;
            let sym = unit_symbol(t).to_string();
            let dim = (!sym.is_empty()).then_some(q.dim);
            Ok((ctx.finite(q.value, v.span(), entry, field)?, dim, sym))
        }
    }
}

/// A parameter's box: both `min` and `max` or neither; `min < max`, value inside.
fn parameter_bounds(
    ctx: &Ctx,
    p: &Spanned<RawParameter>,
    entry: &str,
    value_raw: &SNum,
    value: f64,
) -> Result<Option<(Reading, Reading)>> {
    let rp = p.get_ref();
    let (lo, hi) = match (&rp.min, &rp.max) {
        (None, None) => return Ok(None),
        (Some(_), None) => {
            return Err(ctx.err(
                Some(p.span()),
                entry,
                "max",
                "'min' is given but 'max' is missing",
            ))
        }
        (None, Some(_)) => {
            return Err(ctx.err(
                Some(p.span()),
                entry,
                "min",
                "'max' is given but 'min' is missing",
            ))
        }
        (Some(lo), Some(hi)) => (lo, hi),
    };
    let (l, ld, _) = read_number(ctx, lo, entry, "min")?;
    let (h, hd, _) = read_number(ctx, hi, entry, "max")?;
    if l >= h {
        return Err(ctx.err(
            Some(lo.span()),
            entry,
            "min",
            format!("min ({l:e}) must be below max ({h:e})"),
        ));
    }
    if value < l || value > h {
        return Err(ctx.err(
            Some(value_raw.span()),
            entry,
            "value",
            format!("the value {value:e} lies outside [min, max] = [{l:e}, {h:e}] (SI)"),
        ));
    }
    Ok(Some(((l, ld), (h, hd))))
}

/// The unit a parameter is shown in: its value's unit symbol, if it had one.
fn display_unit(sym: &str, value_raw: &SNum) -> DisplayUnit {
    match value_raw.get_ref() {
        RawNum::Text(_) if !sym.is_empty() => DisplayUnit {
            symbol: sym.to_string(),
            scale: parse_quantity(&format!("1 {sym}"))
                .map(|q| q.value)
                .unwrap_or(1.0),
        },
        _ => DisplayUnit::default(),
    }
}

/// A parameter's `per_experiment` flag, allowed only on an identified parameter.
fn per_experiment(ctx: &Ctx, rp: &RawParameter, entry: &str, has_box: bool) -> Result<bool> {
    match &rp.per_experiment {
        Some(f) if *f.get_ref() && !has_box => Err(ctx.err(
            Some(f.span()),
            entry,
            "per_experiment",
            "only an identified parameter can differ between experiments: give 'min' and 'max' too",
        )),
        Some(f) => Ok(*f.get_ref()),
        None => Ok(false),
    }
}

/// A parameter's `scale`: `"log"` or `"linear"`, only with a box; log needs
/// `min > 0`. Without it, [`Scale::default_for`] the box.
fn parameter_scale(
    ctx: &Ctx,
    rp: &RawParameter,
    span: Range<usize>,
    entry: &str,
    bounds: Option<(f64, f64)>,
) -> Result<Scale> {
    let Some(raw) = &rp.scale else {
        return Ok(bounds.map_or(Scale::Linear, |(lo, hi)| Scale::default_for(lo, hi)));
    };
    let scale = match raw.get_ref().as_str() {
        "log" => Scale::Log,
        "linear" => Scale::Linear,
        other => {
            return Err(ctx.err(
                Some(raw.span()),
                entry,
                "scale",
                format!("unknown scale '{other}' (log or linear)"),
            ))
        }
    };
    match bounds {
        None => Err(ctx.err(
            Some(span),
            entry,
            "scale",
            "'scale' applies to identified parameters only: give 'min' and 'max' too",
        )),
        Some((lo, _)) if scale == Scale::Log && !(lo > 0.0) => Err(ctx.err(
            Some(raw.span()),
            entry,
            "scale",
            format!("a log scale needs min > 0 (min is {lo:e})"),
        )),
        _ => Ok(scale),
    }
}

/// The parameters, each with the dimension of its uses, in file order.
pub(super) fn finish_parameters(ctx: &Ctx) -> Result<Vec<Parameter>> {
    ctx.params
        .iter()
        .map(|p| finish_parameter(ctx, p))
        .collect()
}

/// One parameter: its uses agree and its units fit them (each use checked
/// its box against its rule where it was read: [`super::rules`]).
fn finish_parameter(ctx: &Ctx, p: &ParamDraft) -> Result<Parameter> {
    let entry = format!("parameter \"{}\"", p.name);
    let dim = used_dimension(ctx, p, &entry)?;
    let value = in_use_dimension(ctx, p, &entry, dim, p.value, "value", &p.value_spans[0])?;
    let bounds = match p.bounds {
        None => None,
        Some((lo, hi)) => Some((
            in_use_dimension(ctx, p, &entry, dim, lo, "min", &p.value_spans[1])?,
            in_use_dimension(ctx, p, &entry, dim, hi, "max", &p.value_spans[2])?,
        )),
    };
    Ok(Parameter {
        name: p.name.clone(),
        value,
        bounds,
        scale: p.scale,
        unit: p.unit.clone(),
        dimension: dim,
        per_experiment: p.per_experiment,
    })
}

/// The dimension of a parameter's first use; every other use must agree.
fn used_dimension(ctx: &Ctx, p: &ParamDraft, entry: &str) -> Result<Dimension> {
    let Some((dim, _, _, _)) = p.uses.first() else {
        return Err(ctx.err(
            Some(p.span.clone()),
            entry,
            "name",
            "the parameter is never used",
        ));
    };
    for (d, span, e, f) in &p.uses {
        if d != dim {
            return Err(ctx.err(
                Some(span.clone()),
                e,
                f,
                format!("parameter '{}' is used with the dimension {d} here, but {dim} at its first use ({}, {})", p.name, p.uses[0].2, p.uses[0].3),
            ));
        }
    }
    Ok(*dim)
}

/// A value or bound whose unit, if it had one, has the dimension of the uses.
fn in_use_dimension(
    ctx: &Ctx,
    p: &ParamDraft,
    entry: &str,
    dim: Dimension,
    (v, vd): Reading,
    field: &str,
    span: &Range<usize>,
) -> Result<f64> {
    match vd {
        Some(vd) if vd != dim => Err(ctx.err(
            Some(span.clone()),
            entry,
            field,
            format!(
                "the unit has the dimension {vd}, but the parameter is used as {dim} ({}, {})",
                p.uses[0].2, p.uses[0].3
            ),
        )),
        _ => Ok(v),
    }
}
