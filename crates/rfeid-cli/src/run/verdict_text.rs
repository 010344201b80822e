//! The verdict in words: the fit per sensor, the minima the starts
//! reached, and every reason for suspicion, with a hint.
use rfeid::identification::result::IdentificationResult;
use rfeid::identification::verdict::{Reason, Verdict};
use std::fmt::Write as _;

/// The verdict, with every reason and the fit per sensor.
pub fn write_verdict(out: &mut String, r: &IdentificationResult) {
    let Some(v) = &r.verdict else {
        return;
    };
    write_fits_and_minima(out, v);
    if v.trustworthy {
        let _ = writeln!(out, "verdict: trustworthy (no bound, minimum, convergence, fit, residual or identifiability check failed)");
        return;
    }
    let _ = writeln!(
        out,
        "verdict: SUSPECT — do not use these estimates before resolving:"
    );
    for reason in &v.reasons {
        let _ = writeln!(out, "  - {reason}");
    }
    if v.reasons.iter().any(is_search_reason) {
        let _ = writeln!(
            out,
            "hint: a wrong minimum is the usual cause on wide boxes: a larger plan with more \
             starts (e.g. --plan {} --starts 4) often finds a lower one; if the estimate \
             stays on a bound, widen that box; if the fit stays poor, check the model",
            (4 * r.plan.points).max(400)
        );
    }
}

/// The fit per sensor, and the minima when the starts reached more than
/// one (or one from several starts).
fn write_fits_and_minima(out: &mut String, v: &Verdict) {
    let fits: Vec<String> = v
        .sensors
        .iter()
        .map(|s| match s.fit_percent {
            Some(f) => format!("{} {f:.2} %", s.sensor),
            None => format!("{} -", s.sensor),
        })
        .collect();
    if !fits.is_empty() {
        let _ = writeln!(out, "fit per sensor: {}", fits.join(", "));
    }
    if v.minima.len() > 1 || v.minima.first().is_some_and(|m| m.starts > 1) {
        let list: Vec<String> = v
            .minima
            .iter()
            .map(|m| {
                format!(
                    "J = {:.4e} ({} start{})",
                    m.cost,
                    m.starts,
                    if m.starts == 1 { "" } else { "s" }
                )
            })
            .collect();
        let _ = writeln!(out, "minima reached by the starts: {}", list.join(", "));
    }
}

/// Whether a reason points at the search (a wrong minimum), which a larger
/// plan may cure.
fn is_search_reason(r: &Reason) -> bool {
    matches!(
        r,
        Reason::AtBound { .. }
            | Reason::DistinctMinima { .. }
            | Reason::PoorFit { .. }
            | Reason::NotWhite { .. }
            | Reason::NoiseMismatch { .. }
            | Reason::IterationLimit { .. }
    )
}
