//! The verdict in words: the fit per sensor, the minima the starts
//! reached, and every reason for suspicion, with a hint.
use rfeid::identification::result::IdentificationResult;
use rfeid::identification::verdict::{is_fit_reason, Outcome, Reason, Verdict};
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
    let headline = match v.outcome() {
        Outcome::ModelError => {
            "verdict: MODEL ERROR — the model's best fit, with standard errors that cover the noise only:"
        }
        _ => "verdict: SUSPECT — do not use these estimates before resolving:",
    };
    let _ = writeln!(out, "{headline}");
    for reason in &v.reasons {
        let _ = writeln!(out, "  - {reason}");
    }
    let _ = writeln!(out, "decided by: {}", v.decided_by.join(", "));
    let model_error = v
        .reasons
        .iter()
        .any(|r| matches!(r, Reason::ModelError { .. }));
    if model_error {
        let _ = writeln!(
            out,
            "hint: the starts agree, so a larger plan will not help: the model lacks something \
             the data show (a joint law, a mode, a preload, the sensor's placement); the \
             estimates are the model's best fit, and their standard errors cover the noise only"
        );
    }
    if v.reasons.iter().any(|r| is_search_reason(r, model_error)) {
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
        // The ends are compared in the weighting their searches used; the
        // criterion J above is in the final one (estimated weights, noise
        // model), so the two differ.
        let _ = writeln!(
            out,
            "minima reached by the starts (J in the weighting of their searches): {}",
            list.join(", ")
        );
    }
}

/// Whether a reason points at the search (a wrong minimum), which a larger
/// plan may cure; a failed fit check does not when the verdict found model
/// error.
fn is_search_reason(r: &Reason, model_error: bool) -> bool {
    match r {
        Reason::AtBound { .. } | Reason::DistinctMinima { .. } | Reason::IterationLimit { .. } => {
            true
        }
        _ => !model_error && is_fit_reason(r),
    }
}
