//! The profile likelihoods' table (`--profiles`): each profiled
//! parameter's estimate, the Wald 95 % interval of its standard error
//! (eq. 26) and the profile's likelihood-ratio 95 % interval, then the
//! profiles' warnings.
use crate::format::{sig, table};
use rfeid::identification::profile::{IntervalEnd, ParameterProfile};
use rfeid::identification::result::IdentificationResult;
use rfeid::model::Model;
use std::fmt::Write as _;

/// The table and the warnings of the profiles, if any were computed; a
/// line saying why none were, if they were skipped.
pub fn write_profiles(out: &mut String, model: &Model, r: &IdentificationResult) {
    let skipped = r.warnings.iter().filter(|w| {
        matches!(
            w,
            rfeid::identification::warning::Warning::ProfilesSkipped(_)
        )
    });
    for w in skipped {
        let _ = writeln!(out, "warning: {w}\n");
    }
    let Some(first) = r.profiles.first() else {
        return;
    };
    let s2 = first.s2;
    // κ ≠ 1: the bounds took each sensor's own noise level (equal
    // weights), and each profile's ΔJ is scaled by its own κ s².
    let scaled = r.profiles.iter().any(|p| p.variance_ratio != 1.0);
    let mut rows: Vec<Vec<String>> = r.profiles.iter().map(|p| row(model, r, p)).collect();
    let mut header = vec![
        "parameter",
        "unit",
        "identified",
        "Wald 95 %",
        "profile 95 %",
        "refits",
    ];
    if scaled {
        let _ = writeln!(
            out,
            "profile likelihoods: 95 % intervals where ΔJ/(κ s²) ≤ χ²₁(0.95) = {:.3} (s² = {s2:.4e}; \
             κ, the estimate's variance over eq. 26's with one s², as the sensors' noise levels differ)",
            first.threshold
        );
        header.push("κ");
        for (row, p) in rows.iter_mut().zip(&r.profiles) {
            row.push(sig(p.variance_ratio, 3));
        }
    } else {
        let _ = writeln!(
            out,
            "profile likelihoods: 95 % intervals where ΔJ/s² ≤ χ²₁(0.95) = {:.3} (s² = {s2:.4e})",
            first.threshold
        );
    }
    out.push_str(&table(&header, &rows));
    for w in r.profiles.iter().flat_map(|p| &p.warnings) {
        let _ = writeln!(out, "warning: {w}");
    }
    let _ = writeln!(out);
}

/// One profiled parameter's row.
fn row(model: &Model, r: &IdentificationResult, p: &ParameterProfile) -> Vec<String> {
    let estimate = r.parameters.iter().find(|e| e.name == p.name);
    let scale = estimate.map_or(1.0, |e| e.unit_scale);
    let unit = match estimate {
        Some(e) if !e.unit.is_empty() => e.unit.clone(),
        _ => model
            .parameter_index(&p.name)
            .map(|i| model.parameters[i].dimension.to_string())
            .unwrap_or_default(),
    };
    let show = |v: f64| sig(v / scale, 5);
    let wald = p
        .wald
        .map(|[lo, hi]| format!("{} … {}", show(lo), show(hi)))
        .unwrap_or_else(|| "-".into());
    let end = |e: &IntervalEnd, side: &str| match e {
        IntervalEnd::Crossed { value } => show(*value),
        IntervalEnd::Open { .. } => format!("open at {side}"),
        IntervalEnd::Unresolved { last } => format!("? beyond {}", show(*last)),
    };
    let failed = p.points.iter().filter(|x| x.criterion.is_none()).count();
    vec![
        p.name.clone(),
        unit,
        show(p.estimate),
        wald,
        format!("{} … {}", end(&p.lower, "min"), end(&p.upper, "max")),
        match failed {
            0 => format!("{}", p.points.len() - 1),
            f => format!("{} ({f} failed)", p.points.len() - 1),
        },
    ]
}
