//! Parameters: dimensions from their uses, boxes, units.
use super::ctx::*;
use crate::model::*;
use crate::units::Dimension;
use std::ops::Range;

pub(super) fn finish_parameters(ctx: &Ctx) -> Result<Vec<Parameter>> {
    let mut out = Vec::new();
    for p in &ctx.params {
        let entry = format!("parameter \"{}\"", p.name);
        let Some((dim, _, _, _)) = p.uses.first() else {
            return Err(ctx.err(
                Some(p.span.clone()),
                &entry,
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
        let check = |(v, vd): (f64, Option<Dimension>),
                     field: &str,
                     span: &Range<usize>|
         -> Result<f64> {
            match vd {
                Some(vd) if vd != *dim => Err(ctx.err(
                    Some(span.clone()),
                    &entry,
                    field,
                    format!("the unit has the dimension {vd}, but the parameter is used as {dim} ({}, {})", p.uses[0].2, p.uses[0].3),
                )),
                _ => Ok(v),
            }
        };
        let value = check(p.value, "value", &p.value_spans[0])?;
        let bounds = match p.bounds {
            None => None,
            Some((lo, hi)) => Some((
                check(lo, "min", &p.value_spans[1])?,
                check(hi, "max", &p.value_spans[2])?,
            )),
        };
        let lowest = bounds.map(|b| b.0).unwrap_or(value);
        for (_, span, e, f) in &p.uses {
            let need_positive = f == "mass" || f == "inertia";
            let need_non_negative = matches!(f.as_str(), "k" | "a" | "c");
            if (need_positive && !(lowest > 0.0))
                || (need_non_negative && lowest < 0.0)
                || (f == "m" && lowest < 1.0)
            {
                let what = if need_positive {
                    "positive"
                } else if f == "m" {
                    "at least 1"
                } else {
                    "non-negative"
                };
                return Err(ctx.err(
                    Some(span.clone()),
                    e,
                    f,
                    format!(
                        "parameter '{}' must be {what} over its whole box (lowest {lowest:e})",
                        p.name
                    ),
                ));
            }
        }
        out.push(Parameter {
            name: p.name.clone(),
            value,
            bounds,
            scale: p.scale,
            unit: p.unit.clone(),
            dimension: *dim,
            per_experiment: p.per_experiment,
        });
    }
    Ok(out)
}
