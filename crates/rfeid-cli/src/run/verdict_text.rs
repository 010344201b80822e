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
    for hint in hints(&v.reasons, r.plan.points) {
        let _ = writeln!(out, "hint: {hint}");
    }
}

/// The hints after the reasons, chosen by the evidence: with model error
/// the starts agree on the lowest minimum, so the larger-plan hint (a wrong
/// minimum) would contradict it and is left out; an estimate on a bound
/// then gets its own hint. Without model error, a search reason (a bound,
/// distinct minima, the iteration limit) or a failed fit gets the
/// larger-plan hint.
fn hints(reasons: &[Reason], plan_points: usize) -> Vec<String> {
    let model_error = reasons
        .iter()
        .any(|r| matches!(r, Reason::ModelError { .. }));
    let mut out = Vec::new();
    if model_error {
        out.push(
            "the starts agree, so a larger plan will not help: the model lacks something the \
             data show (a joint law, a mode, a preload, the sensor's placement); the estimates \
             are the model's best fit, and their standard errors cover the noise only"
                .to_string(),
        );
        if reasons.iter().any(|r| matches!(r, Reason::AtBound { .. })) {
            out.push(
                "an estimate on a bound is the model's best fit inside its box: widen that box \
                 to see whether the fit improves beyond it"
                    .to_string(),
            );
        }
    } else if reasons.iter().any(is_search_reason) {
        out.push(format!(
            "a wrong minimum is the usual cause on wide boxes: a larger plan with more starts \
             (e.g. --plan {} --starts 4) often finds a lower one; if the estimate stays on a \
             bound, widen that box; if the fit stays poor, check the model",
            (4 * plan_points).max(400)
        ));
    }
    out
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
/// plan may cure, as a failed fit may when the starts do not agree.
fn is_search_reason(r: &Reason) -> bool {
    match r {
        Reason::AtBound { .. } | Reason::DistinctMinima { .. } | Reason::IterationLimit { .. } => {
            true
        }
        _ => is_fit_reason(r),
    }
}

#[cfg(test)]
mod tests {
    use super::hints;
    use rfeid::identification::verdict::{Reason, Side};

    fn model_error() -> Reason {
        Reason::ModelError {
            starts: 3,
            cost: 1.0,
            sensors: Vec::new(),
        }
    }

    fn at_bound() -> Reason {
        Reason::AtBound {
            parameter: "k".into(),
            side: Side::Lower,
            distance: 0.0,
            threshold: 0.01,
        }
    }

    fn distinct_minima() -> Reason {
        Reason::DistinctMinima {
            minima: Vec::new(),
            threshold: 1.0,
        }
    }

    #[test]
    fn model_error_never_comes_with_the_larger_plan_hint() {
        for others in [
            vec![],
            vec![at_bound()],
            vec![distinct_minima(), at_bound()],
        ] {
            let reasons: Vec<Reason> = std::iter::once(model_error()).chain(others).collect();
            let text = hints(&reasons, 16).join("\n");
            assert!(text.contains("a larger plan will not help"), "{text}");
            assert!(!text.contains("often finds a lower one"), "{text}");
        }
        let with_bound = hints(&[model_error(), at_bound()], 16);
        assert_eq!(with_bound.len(), 2);
        assert!(with_bound[1].contains("widen that box"), "{with_bound:?}");
    }

    #[test]
    fn search_reasons_without_model_error_get_the_larger_plan_hint() {
        for reason in [at_bound(), distinct_minima()] {
            let text = hints(&[reason], 16);
            assert_eq!(text.len(), 1, "{text:?}");
            assert!(text[0].contains("--plan 400 --starts 4"), "{text:?}");
        }
        assert!(hints(&[], 16).is_empty());
    }
}
