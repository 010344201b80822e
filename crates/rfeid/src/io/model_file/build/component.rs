//! One component (ux … rz) of an element: its law and damping.
use super::ctx::*;
use crate::io::model_file::raw::*;
use crate::model::*;
use crate::units::Dimension;
use toml::Spanned;

/// A component's table, its entry name and whether it is a rotation.
struct Comp<'a> {
    c: &'a Spanned<RawComponent>,
    entry: String,
    rotational: bool,
}

impl Comp<'_> {
    /// The component's fields.
    fn raw(&self) -> &RawComponent {
        self.c.get_ref()
    }
}

/// One component of an element: its law (linear, power or none) and damping `c`.
pub(super) fn component(
    ctx: &mut Ctx,
    c: &Spanned<RawComponent>,
    dof: usize,
    element: &str,
) -> Result<Component> {
    let cname = COMPONENT_NAMES[dof];
    let comp = Comp {
        c,
        entry: format!("{element}, component {cname}"),
        rotational: dof >= 3,
    };
    let law = law(ctx, &comp)?;
    let damping = damping(ctx, &comp)?;
    Ok(Component { dof, law, damping })
}

/// The law a component names, or the one its coefficients imply.
fn law_name(rc: &RawComponent) -> String {
    match &rc.law {
        Some(l) => l.get_ref().trim().to_string(),
        None if rc.a.is_some() || rc.m.is_some() => "power".into(),
        None if rc.k.is_some() => "linear".into(),
        None => "none".into(),
    }
}

/// A component's spring law, with only that law's coefficients.
fn law(ctx: &mut Ctx, comp: &Comp) -> Result<Law> {
    let rc = comp.raw();
    match law_name(rc).as_str() {
        "linear" => linear_law(ctx, comp),
        "power" => power_law(ctx, comp),
        "none" => {
            forbid(ctx, &rc.reference, "reference", "none", &comp.entry)?;
            if rc.c.is_none() {
                return Err(ctx.err(
                    Some(comp.c.span()),
                    &comp.entry,
                    "law",
                    "the component has neither a spring (k, or a and m) nor damping (c)",
                ));
            }
            Ok(Law::None)
        }
        other => {
            let span = rc.law.as_ref().map(|l| l.span());
            Err(ctx.err(
                span,
                &comp.entry,
                "law",
                format!("unknown law '{other}' (linear or power)"),
            ))
        }
    }
}

/// An error if a coefficient that does not belong to `law` is given.
fn forbid(ctx: &Ctx, v: &Option<SNum>, field: &str, law: &str, entry: &str) -> Result<()> {
    match v {
        Some(v) => Err(ctx.err(
            Some(v.span()),
            entry,
            field,
            format!("'{field}' does not belong to the {law} law"),
        )),
        None => Ok(()),
    }
}

/// A linear spring: a non-negative stiffness `k`.
fn linear_law(ctx: &mut Ctx, comp: &Comp) -> Result<Law> {
    let (rc, entry) = (comp.raw(), comp.entry.as_str());
    forbid(ctx, &rc.a, "a", "linear", entry)?;
    forbid(ctx, &rc.m, "m", "linear", entry)?;
    forbid(ctx, &rc.reference, "reference", "linear", entry)?;
    let k_dim = if comp.rotational {
        Dimension::MOMENT
    } else {
        Dimension::STIFFNESS
    };
    let k = ctx.value(
        required(ctx, &rc.k, comp.c.span(), entry, "k")?,
        k_dim,
        entry,
        "k",
    )?;
    non_negative(ctx, k, &rc.k, entry, "k")?;
    Ok(Law::Linear { k })
}

/// A power-law spring: exponent `m ≥ 1`, optional reference deformation, `a ≥ 0`.
fn power_law(ctx: &mut Ctx, comp: &Comp) -> Result<Law> {
    let (rc, entry) = (comp.raw(), comp.entry.as_str());
    forbid(ctx, &rc.k, "k", "power", entry)?;
    let (m, m_nominal) = exponent(ctx, comp)?;
    let reference = reference(ctx, comp)?;
    // With a reference deformation δ_ref, a is the force (moment) at
    // δ_ref; without, a multiplies |δ|^m with δ in m (rad).
    let a_dim = if comp.rotational {
        Dimension::MOMENT
    } else if rc.reference.is_some() {
        Dimension::FORCE
    } else {
        Dimension::FORCE.div(Dimension::LENGTH.powf(m_nominal))
    };
    let a = ctx.value(
        required(ctx, &rc.a, comp.c.span(), entry, "a")?,
        a_dim,
        entry,
        "a",
    )?;
    non_negative(ctx, a, &rc.a, entry, "a")?;
    Ok(Law::Power { a, m, reference })
}

/// A power law's exponent `m` and its nominal value, which must be at least 1.
fn exponent(ctx: &mut Ctx, comp: &Comp) -> Result<(Value, f64)> {
    let entry = comp.entry.as_str();
    let m_raw = required(ctx, &comp.raw().m, comp.c.span(), entry, "m")?;
    let m = ctx.value(m_raw, Dimension::DIMENSIONLESS, entry, "m")?;
    let m_nominal = match m {
        Value::Fixed(x) => x,
        Value::Param(i) => ctx.params[i].value.0,
    };
    if !(m_nominal >= 1.0) {
        return Err(ctx.err(
            Some(m_raw.span()),
            entry,
            "m",
            format!("the exponent must be at least 1 (found {m_nominal})"),
        ));
    }
    Ok((m, m_nominal))
}

/// A power law's reference deformation (m, or rad for a rotation): positive, 1 when absent.
fn reference(ctx: &Ctx, comp: &Comp) -> Result<f64> {
    let Some(v) = &comp.raw().reference else {
        return Ok(1.0);
    };
    let dim = if comp.rotational {
        Dimension::DIMENSIONLESS
    } else {
        Dimension::LENGTH
    };
    let r = ctx.number(v, dim, &comp.entry, "reference")?;
    if !(r > 0.0) {
        return Err(ctx.err(
            Some(v.span()),
            &comp.entry,
            "reference",
            format!("the reference deformation must be positive (found {r})"),
        ));
    }
    Ok(r)
}

/// A component's damping `c`: non-negative, 0 when absent.
fn damping(ctx: &mut Ctx, comp: &Comp) -> Result<Value> {
    let rc = comp.raw();
    let Some(v) = &rc.c else {
        return Ok(Value::Fixed(0.0));
    };
    let c_dim = if comp.rotational {
        Dimension::ROTATIONAL_DAMPING
    } else {
        Dimension::DAMPING
    };
    let d = ctx.value(v, c_dim, &comp.entry, "c")?;
    non_negative(ctx, d, &rc.c, &comp.entry, "c")?;
    Ok(d)
}

/// An error if a fixed coefficient is negative.
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
