//! One component (ux … rz) of an element: its law and damping.
use super::ctx::*;
use crate::io::model_file::raw::*;
use crate::model::*;
use crate::units::Dimension;
use toml::Spanned;

pub(super) fn component(
    ctx: &mut Ctx,
    c: &Spanned<RawComponent>,
    dof: usize,
    element: &str,
) -> Result<Component> {
    let cname = COMPONENT_NAMES[dof];
    let entry = format!("{element}, component {cname}");
    let rc = c.get_ref();
    let rotational = dof >= 3;
    let (k_dim, c_dim) = if rotational {
        (Dimension::MOMENT, Dimension::ROTATIONAL_DAMPING)
    } else {
        (Dimension::STIFFNESS, Dimension::DAMPING)
    };
    let law_name = match &rc.law {
        Some(l) => l.get_ref().trim().to_string(),
        None if rc.a.is_some() || rc.m.is_some() => "power".into(),
        None if rc.k.is_some() => "linear".into(),
        None => "none".into(),
    };
    let forbid = |ctx: &Ctx, v: &Option<SNum>, field: &str, law: &str| -> Result<()> {
        match v {
            Some(v) => Err(ctx.err(
                Some(v.span()),
                &entry,
                field,
                format!("'{field}' does not belong to the {law} law"),
            )),
            None => Ok(()),
        }
    };
    let law = match law_name.as_str() {
        "linear" => {
            forbid(ctx, &rc.a, "a", "linear")?;
            forbid(ctx, &rc.m, "m", "linear")?;
            forbid(ctx, &rc.reference, "reference", "linear")?;
            let k = ctx.value(
                required(ctx, &rc.k, c.span(), &entry, "k")?,
                k_dim,
                &entry,
                "k",
            )?;
            non_negative(ctx, k, &rc.k, &entry, "k")?;
            Law::Linear { k }
        }
        "power" => {
            forbid(ctx, &rc.k, "k", "power")?;
            let m_raw = required(ctx, &rc.m, c.span(), &entry, "m")?;
            let m = ctx.value(m_raw, Dimension::DIMENSIONLESS, &entry, "m")?;
            let m_nominal = match m {
                Value::Fixed(x) => x,
                Value::Param(i) => ctx.params[i].value.0,
            };
            if !(m_nominal >= 1.0) {
                return Err(ctx.err(
                    Some(m_raw.span()),
                    &entry,
                    "m",
                    format!("the exponent must be at least 1 (found {m_nominal})"),
                ));
            }
            // With a reference deformation δ_ref, a is the force (moment) at
            // δ_ref; without, a multiplies |δ|^m with δ in m (rad).
            let reference = match &rc.reference {
                None => 1.0,
                Some(v) => {
                    let dim = if rotational {
                        Dimension::DIMENSIONLESS
                    } else {
                        Dimension::LENGTH
                    };
                    let r = ctx.number(v, dim, &entry, "reference")?;
                    if !(r > 0.0) {
                        return Err(ctx.err(
                            Some(v.span()),
                            &entry,
                            "reference",
                            format!("the reference deformation must be positive (found {r})"),
                        ));
                    }
                    r
                }
            };
            let a_dim = if rotational {
                Dimension::MOMENT
            } else if rc.reference.is_some() {
                Dimension::FORCE
            } else {
                Dimension::FORCE.div(Dimension::LENGTH.powf(m_nominal))
            };
            let a = ctx.value(
                required(ctx, &rc.a, c.span(), &entry, "a")?,
                a_dim,
                &entry,
                "a",
            )?;
            non_negative(ctx, a, &rc.a, &entry, "a")?;
            Law::Power { a, m, reference }
        }
        "none" => {
            forbid(ctx, &rc.reference, "reference", "none")?;
            if rc.c.is_none() {
                return Err(ctx.err(
                    Some(c.span()),
                    &entry,
                    "law",
                    "the component has neither a spring (k, or a and m) nor damping (c)",
                ));
            }
            Law::None
        }
        other => {
            let span = rc.law.as_ref().map(|l| l.span());
            return Err(ctx.err(
                span,
                &entry,
                "law",
                format!("unknown law '{other}' (linear or power)"),
            ));
        }
    };
    let damping = match &rc.c {
        Some(v) => {
            let d = ctx.value(v, c_dim, &entry, "c")?;
            non_negative(ctx, d, &rc.c, &entry, "c")?;
            d
        }
        None => Value::Fixed(0.0),
    };
    Ok(Component { dof, law, damping })
}

pub(super) fn non_negative(
    ctx: &Ctx,
    v: Value,
    raw: &Option<SNum>,
    entry: &str,
    field: &str,
) -> Result<()> {
    if let Value::Fixed(x) = v {
        if x < 0.0 {
            return Err(ctx.err(
                raw.as_ref().map(|r| r.span()),
                entry,
                field,
                format!("must not be negative (found {x})"),
            ));
        }
    }
    Ok(())
}
