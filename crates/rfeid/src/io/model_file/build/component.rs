//! One component (ux … rz) of an element: its law and damping.
use super::ctx::*;
use super::rules::ruled;
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
        None if rc.f.is_some() => "friction".into(),
        None if rc.alpha.is_some() => "bouc-wen".into(),
        None if rc.k.is_some() => "linear".into(),
        None => "none".into(),
    }
}

/// A component's spring law, with only that law's coefficients.
fn law(ctx: &mut Ctx, comp: &Comp) -> Result<Law> {
    let rc = comp.raw();
    let name = law_name(rc);
    // Named first: a misspelt law is not a home for misplaced keys.
    let build: fn(&mut Ctx, &Comp) -> Result<Law> = match name.as_str() {
        "linear" => linear_law,
        "power" => power_law,
        "friction" => friction_law,
        "bouc-wen" => bouc_wen_law,
        "none" => damper_only,
        other => {
            return Err(ctx.err(
                rc.law.as_ref().map(|l| l.span()),
                &comp.entry,
                "law",
                format!(
                    "unknown law '{other}' (linear, power, friction or bouc-wen){}",
                    law_hint(other)
                ),
            ))
        }
    };
    if name != "friction" {
        for (v, field) in friction_keys(rc) {
            forbid(ctx, v, field, &name, &comp.entry)?;
        }
    }
    if name != "bouc-wen" {
        for (v, field) in hysteresis_keys(rc) {
            forbid(ctx, v, field, &name, &comp.entry)?;
        }
    }
    build(ctx, comp)
}

/// The laws a component can name.
const LAWS: [&str; 4] = ["linear", "power", "friction", "bouc-wen"];

/// `"; did you mean 'friction'?"` for a law's name written with another
/// case, without its hyphen, or within two edits of it; empty otherwise.
fn law_hint(written: &str) -> String {
    let plain = |s: &str| -> Vec<char> {
        s.to_lowercase()
            .chars()
            .filter(|c| c.is_alphanumeric())
            .collect()
    };
    let w = plain(written);
    LAWS.iter()
        .map(|law| (edit_distance(&w, &plain(law)), law))
        .filter(|(d, _)| *d <= 2)
        .min_by_key(|(d, _)| *d)
        .map(|(_, law)| format!("; did you mean '{law}'?"))
        .unwrap_or_default()
}

/// The Levenshtein distance between two words.
fn edit_distance(a: &[char], b: &[char]) -> usize {
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.iter().enumerate() {
        let mut diagonal = row[0];
        row[0] = i + 1;
        for (j, cb) in b.iter().enumerate() {
            let substituted = diagonal + usize::from(ca != cb);
            diagonal = row[j + 1];
            row[j + 1] = substituted.min(row[j] + 1).min(diagonal + 1);
        }
    }
    row[b.len()]
}

/// No spring: a damper `c` alone (a direction free of springs).
fn damper_only(ctx: &mut Ctx, comp: &Comp) -> Result<Law> {
    let rc = comp.raw();
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

/// The friction law's own keys, with their names.
fn friction_keys(rc: &RawComponent) -> [(&Option<SNum>, &'static str); 5] {
    [
        (&rc.f, "f"),
        (&rc.f_neg, "f_neg"),
        (&rc.fs, "fs"),
        (&rc.vs, "vs"),
        (&rc.smoothing, "smoothing"),
    ]
}

/// The Bouc–Wen law's own keys (its `k` is shared), with their names.
fn hysteresis_keys(rc: &RawComponent) -> [(&Option<SNum>, &'static str); 5] {
    [
        (&rc.alpha, "alpha"),
        (&rc.beta, "beta"),
        (&rc.gamma, "gamma"),
        (&rc.d, "d"),
        (&rc.n, "n"),
    ]
}

/// Bouc–Wen hysteresis (SPEC §1): `alpha`, `beta`, `gamma` and `d`
/// required, the exponent `n ≥ 1` (default 1), an optional spring `k ≥ 0`.
/// β's unit follows n: `ż` is a force per second, so β γ |v| |z|^n is too
/// (β in 1/m for n = 1).
fn bouc_wen_law(ctx: &mut Ctx, comp: &Comp) -> Result<Law> {
    let (rc, entry) = (comp.raw(), comp.entry.as_str());
    forbid(ctx, &rc.a, "a", "bouc-wen", entry)?;
    forbid(ctx, &rc.m, "m", "bouc-wen", entry)?;
    forbid(ctx, &rc.reference, "reference", "bouc-wen", entry)?;
    let (force, length, k_dim) = match comp.rotational {
        true => (
            Dimension::MOMENT,
            Dimension::DIMENSIONLESS,
            Dimension::MOMENT,
        ),
        false => (Dimension::FORCE, Dimension::LENGTH, Dimension::STIFFNESS),
    };
    let (n, n_nominal) = match &rc.n {
        None => (Value::Fixed(1.0), 1.0),
        Some(raw) => {
            let n = ruled(ctx, raw, Dimension::DIMENSIONLESS, entry, "n")?;
            (n, nominal(ctx, n))
        }
    };
    let span = comp.c.span();
    let get = |ctx: &mut Ctx, raw: &Option<SNum>, dim: Dimension, field: &str| {
        ruled(
            ctx,
            required(ctx, raw, span.clone(), entry, field)?,
            dim,
            entry,
            field,
        )
    };
    let alpha = get(ctx, &rc.alpha, k_dim, "alpha")?;
    let beta_dim = force.powf(1.0 - n_nominal).div(length);
    let beta = beta(ctx, comp, n, beta_dim)?;
    let gamma = get(ctx, &rc.gamma, Dimension::DIMENSIONLESS, "gamma")?;
    let d = get(ctx, &rc.d, Dimension::DIMENSIONLESS, "d")?;
    let k = match &rc.k {
        Some(_) => get(ctx, &rc.k, k_dim, "k")?,
        None => Value::Fixed(0.0),
    };
    Ok(Law::BoucWen(BoucWen {
        k,
        alpha,
        beta,
        gamma,
        d,
        n,
    }))
}

/// Bouc–Wen's β, of dimension `dim`: N^(1−n)/m at n's value (1/m for
/// n = 1). With n a parameter, whose value the search, `--set` or an
/// experiment's `set` changes, a unit would mean a different β at each n:
/// β is then a bare number (or a parameter with bare numbers), taken in N
/// and m (N·m and rad for a rotation) at every n, and a unit is refused
/// saying so.
fn beta(ctx: &mut Ctx, comp: &Comp, n: Value, dim: Dimension) -> Result<Value> {
    let entry = comp.entry.as_str();
    let raw = required(ctx, &comp.raw().beta, comp.c.span(), entry, "beta")?;
    if let Value::Param(ni) = n {
        let with_unit = match raw.get_ref() {
            RawNum::Num(_) | RawNum::Bool(_) => false,
            RawNum::Text(t) if looks_numeric(t) => !bare(t),
            RawNum::Text(t) => ctx.param_index.get(t.trim()).is_some_and(|&i| {
                let p = &ctx.params[i];
                let box_units = p
                    .bounds
                    .is_some_and(|(lo, hi)| lo.1.is_some() || hi.1.is_some());
                p.value.1.is_some() || box_units
            }),
        };
        if with_unit {
            let si = match comp.rotational {
                true => "N·m and rad",
                false => "N and m",
            };
            let message = format!(
                "n is the parameter '{}', so beta's unit, N^(1−n)/m ({dim} at n = {}), changes \
                 with n: write beta (or its parameter's value, min and max) as a bare number, \
                 taken in {si} at every n",
                ctx.params[ni].name, ctx.params[ni].value.0
            );
            return Err(ctx.err(Some(raw.span()), entry, "beta", message));
        }
    }
    ruled(ctx, raw, dim, entry, "beta")
}

/// Friction (SPEC §1): a Coulomb force `f ≥ 0`, optional `f_neg ≥ 0`,
/// Stribeck's `fs` and `vs` together, the smoothing velocity (default
/// 1 mm/s, or 1 mrad/s for a rotation) and an optional parallel spring `k`.
fn friction_law(ctx: &mut Ctx, comp: &Comp) -> Result<Law> {
    let (rc, entry) = (comp.raw(), comp.entry.as_str());
    forbid(ctx, &rc.a, "a", "friction", entry)?;
    forbid(ctx, &rc.m, "m", "friction", entry)?;
    forbid(ctx, &rc.reference, "reference", "friction", entry)?;
    let (f_dim, v_dim, k_dim) = match comp.rotational {
        true => (Dimension::MOMENT, Dimension::FREQUENCY, Dimension::MOMENT),
        false => (
            Dimension::FORCE,
            Dimension::LENGTH.div(Dimension::TIME),
            Dimension::STIFFNESS,
        ),
    };
    let force = |ctx: &mut Ctx, raw: &Option<SNum>, field: &str| -> Result<Option<Value>> {
        let Some(r) = raw else { return Ok(None) };
        Ok(Some(ruled(ctx, r, f_dim, entry, field)?))
    };
    let f_raw = required(ctx, &rc.f, comp.c.span(), entry, "f")?;
    let f = force(ctx, &Some(f_raw.clone()), "f")?.expect("given");
    let f_neg = force(ctx, &rc.f_neg, "f_neg")?;
    let stribeck = match (&rc.fs, &rc.vs) {
        (Some(_), Some(vs)) => {
            let fs = force(ctx, &rc.fs, "fs")?.expect("given");
            Some((fs, ruled(ctx, vs, v_dim, entry, "vs")?))
        }
        (None, None) => None,
        (given, _) => {
            let (field, other) = match given {
                Some(_) => ("fs", "vs"),
                None => ("vs", "fs"),
            };
            let span = rc.fs.as_ref().or(rc.vs.as_ref()).map(|v| v.span());
            return Err(ctx.err(
                span,
                entry,
                field,
                format!("Stribeck friction needs both fs and vs: add '{other}'"),
            ));
        }
    };
    let smoothing = match &rc.smoothing {
        Some(s) => ruled(ctx, s, v_dim, entry, "smoothing")?,
        None => Value::Fixed(1e-3),
    };
    let k = match &rc.k {
        Some(k) => ruled(ctx, k, k_dim, entry, "k")?,
        None => Value::Fixed(0.0),
    };
    Ok(Law::Friction(Friction {
        k,
        f,
        f_neg,
        stribeck,
        smoothing,
    }))
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
    let k = ruled(
        ctx,
        required(ctx, &rc.k, comp.c.span(), entry, "k")?,
        k_dim,
        entry,
        "k",
    )?;
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
    let a = ruled(
        ctx,
        required(ctx, &rc.a, comp.c.span(), entry, "a")?,
        a_dim,
        entry,
        "a",
    )?;
    Ok(Law::Power { a, m, reference })
}

/// A power law's exponent `m` and its nominal value, which must be at least 1
/// (over its box, if it is identified).
fn exponent(ctx: &mut Ctx, comp: &Comp) -> Result<(Value, f64)> {
    let entry = comp.entry.as_str();
    let m_raw = required(ctx, &comp.raw().m, comp.c.span(), entry, "m")?;
    let m = ruled(ctx, m_raw, Dimension::DIMENSIONLESS, entry, "m")?;
    Ok((m, nominal(ctx, m)))
}

/// A value's nominal number: its own, or its parameter's.
fn nominal(ctx: &Ctx, v: Value) -> f64 {
    match v {
        Value::Fixed(x) => x,
        Value::Param(i) => ctx.params[i].value.0,
    }
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
    ruled(ctx, v, c_dim, &comp.entry, "c")
}

#[cfg(test)]
mod tests {
    use super::law_hint;

    #[test]
    fn a_law_written_nearly_right_gets_a_hint() {
        for (written, law) in [
            ("fricton", "friction"),
            ("Friction", "friction"),
            ("boucwen", "bouc-wen"),
            ("Bouc_Wen", "bouc-wen"),
            ("linaer", "linear"),
            ("POWER", "power"),
        ] {
            assert_eq!(law_hint(written), format!("; did you mean '{law}'?"));
        }
        for far in ["quadratic", "coulomb", "nonsense", ""] {
            assert_eq!(law_hint(far), "", "{far}");
        }
    }
}
