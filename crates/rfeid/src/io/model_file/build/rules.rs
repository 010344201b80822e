//! The sign rules of masses and joint-law keys, checked where a key is
//! read: on a fixed value, and on a parameter's nominal value and box.
//!
//! A parameter whose box reaches values a law refuses is refused when the
//! file is read, rather than only warned about by `check`: the box is the
//! set the search is told the value lies in, so plan points and local
//! steps land there, and each such point fails (friction with f < 0, a
//! Bouc–Wen exponent below 1) or is meaningless; the run would report
//! "plan: 8 points, 2 failed" about a mistake in the file. Every rule is a
//! lower limit, so the box's `min` alone decides, and the message says
//! what `min` must be.
use super::ctx::*;
use crate::io::model_file::raw::SNum;
use crate::model::Value;
use crate::units::Dimension;
use std::ops::Range;

/// The lower limit a rule sets.
#[derive(Clone, Copy, PartialEq, Debug)]
enum Limit {
    /// Greater than zero.
    Positive,
    /// Zero or more.
    NonNegative,
    /// One or more (exponents).
    AtLeastOne,
}

impl Limit {
    /// Whether `x` obeys the limit (NaN never does).
    fn holds(self, x: f64) -> bool {
        match self {
            Limit::Positive => x > 0.0,
            Limit::NonNegative => x >= 0.0,
            Limit::AtLeastOne => x >= 1.0,
        }
    }

    /// The limit written after a key's name: `> 0`, `≥ 0`, `≥ 1`.
    fn text(self) -> &'static str {
        match self {
            Limit::Positive => "> 0",
            Limit::NonNegative => "≥ 0",
            Limit::AtLeastOne => "≥ 1",
        }
    }

    /// The limit's value, in SI.
    fn bound(self) -> f64 {
        match self {
            Limit::AtLeastOne => 1.0,
            _ => 0.0,
        }
    }

    /// What a fixed value breaking the limit is told (the texts the model
    /// file's errors have always used).
    fn broken(self, x: f64) -> String {
        match self {
            Limit::Positive => format!("must be positive (found {x})"),
            Limit::NonNegative => format!("must not be negative (found {x})"),
            Limit::AtLeastOne => format!("the exponent must be at least 1 (found {x})"),
        }
    }
}

/// A field's rule: its limit and why, as a law states it.
#[rustfmt::skip]
fn rule_of(field: &str) -> Option<(Limit, &'static str)> {
    Some(match field {
        "mass" | "inertia" => (Limit::Positive, "a mass or moment of inertia must be positive"),
        "k" => (Limit::NonNegative, "a stiffness must not be negative"),
        "a" => (Limit::NonNegative, "a power-law coefficient must not be negative"),
        "c" => (Limit::NonNegative, "a damping must not be negative"),
        "alpha" => (Limit::NonNegative, "Bouc–Wen's hysteretic stiffness must not be negative"),
        "f" | "f_neg" | "fs" => (Limit::NonNegative, "a friction force must not be negative"),
        "vs" | "smoothing" => (Limit::Positive, "a velocity scale must be positive"),
        "m" => (Limit::AtLeastOne, "a power-law exponent must be at least 1"),
        "n" => (Limit::AtLeastOne, "the Bouc–Wen exponent must be at least 1"),
        _ => return None,
    })
}

/// Reads a coefficient (a number with a unit of dimension `dim`, or a
/// parameter's name) that must obey its field's rule ([`rule_of`]): a fixed
/// value, a parameter's nominal value and, for an identified parameter,
/// its whole box.
pub(super) fn ruled(
    ctx: &mut Ctx,
    raw: &SNum,
    dim: Dimension,
    entry: &str,
    field: &str,
) -> Result<Value> {
    let v = ctx.value(raw, dim, entry, field)?;
    check_rule(ctx, v, Some(raw.span()), dim, entry, field)?;
    Ok(v)
}

/// An error if `v` (read at `span` for `entry`'s `field`) breaks the
/// field's rule; fields without a rule pass.
pub(super) fn check_rule(
    ctx: &Ctx,
    v: Value,
    span: Option<Range<usize>>,
    dim: Dimension,
    entry: &str,
    field: &str,
) -> Result<()> {
    let Some((limit, why)) = rule_of(field) else {
        return Ok(());
    };
    let message = match v {
        Value::Fixed(x) if !limit.holds(x) => limit.broken(x),
        Value::Fixed(_) => return Ok(()),
        Value::Param(i) => {
            let p = &ctx.params[i];
            let rule = format!("{why} ({field} {})", limit.text());
            match p.bounds {
                None if limit.holds(p.value.0) => return Ok(()),
                None => format!(
                    "parameter '{}' is {}: {rule}",
                    p.name,
                    shown(p, dim, p.value.0)
                ),
                Some(((lo, _), _)) if limit.holds(lo) => return Ok(()),
                Some(((lo, _), (hi, _))) => box_refused(p, dim, (lo, hi), limit, &rule),
            }
        }
    };
    Err(ctx.err(span, entry, field, message))
}

/// What a parameter whose box `[lo, hi]` (SI) reaches values the `rule`
/// refuses is told: its box, the rule, and what its `min` must be.
fn box_refused(
    p: &ParamDraft,
    dim: Dimension,
    (lo, hi): (f64, f64),
    limit: Limit,
    rule: &str,
) -> String {
    let min = match limit {
        Limit::Positive => "above",
        _ => "of at least",
    };
    format!(
        "parameter '{}' has the box [{}, {}], which reaches values the law refuses: {rule}, \
         and plan points there would fail; give '{}' a min {min} {}",
        p.name,
        shown(p, dim, lo),
        shown(p, dim, hi),
        p.name,
        shown(p, dim, limit.bound()),
    )
}

/// `x` (SI) in the parameter's unit: the one its value was written in, or
/// the SI unit of its use.
fn shown(p: &ParamDraft, dim: Dimension, x: f64) -> String {
    let number = |v: f64| {
        // Six significant digits: a unit's scale leaves no 4.9999999999.
        let v: f64 = format!("{v:.5e}").parse().unwrap_or(v);
        match v == 0.0 || (1e-4..1e7).contains(&v.abs()) {
            true => format!("{v}"),
            false => format!("{v:e}"),
        }
    };
    if !p.unit.symbol.is_empty() {
        format!("{} {}", number(x / p.unit.scale), p.unit.symbol)
    } else if dim.is_dimensionless() {
        number(x)
    } else {
        format!("{} {dim}", number(x))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_limit_refuses_nan_and_its_side() {
        for limit in [Limit::Positive, Limit::NonNegative, Limit::AtLeastOne] {
            assert!(!limit.holds(f64::NAN));
            assert!(!limit.holds(limit.bound() - 1e-12));
            assert!(limit.holds(limit.bound() + 1e-12));
        }
        assert!(!Limit::Positive.holds(0.0));
        assert!(Limit::NonNegative.holds(0.0));
    }

    #[test]
    fn every_law_key_with_a_sign_has_a_rule() {
        let signed = "f f_neg fs vs smoothing n m k a c alpha mass inertia";
        for key in signed.split(' ') {
            assert!(rule_of(key).is_some(), "{key}");
        }
        for key in ["beta", "gamma", "d", "offset", "gain"] {
            assert!(rule_of(key).is_none(), "{key}");
        }
    }
}
