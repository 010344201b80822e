//! Stage 2, the starts: local searches from the plan's best points (or once
//! from the parameters' values), each failed start recorded rather than
//! ending the run.
use super::error::{IdentifyError, SearchError};
use super::plan_run::PlanRun;
use super::searcher::Searcher;
use super::settings::Start;
use crate::identification::output_error::OutputError;
use crate::identification::result::StartFailure;
use crate::identification::search::SearchOutcome;
use crate::identification::warning::Warning;

/// The local searches so far: the finished ones, the failed starts, and
/// the warnings they raised.
pub(super) struct Ends {
    /// Finished searches, in the order they started.
    pub searches: Vec<SearchOutcome>,
    /// Starts whose search could not run.
    pub failures: Vec<StartFailure>,
    /// Plan indices the searches started from.
    pub used: Vec<usize>,
    /// Warnings of the searches (a failed window search).
    pub warnings: Vec<Warning>,
    /// What the restarts did, when any ran.
    pub restart_warning: Option<Warning>,
}

/// Runs the first searches: from each of the plan's best points, or once
/// from the parameters' values ([`Start::Values`]).
pub(super) fn run(
    problem: &OutputError<'_>,
    searcher: &Searcher<'_>,
    plan: &PlanRun<'_, '_>,
) -> Result<Ends, IdentifyError> {
    let mut warnings = Vec::new();
    let (searches, failures) = match searcher.settings().start {
        Start::Plan => run_starts(&plan.starts, |k, idx, cost| {
            searcher
                .progress()
                .search_started(k, plan.starts.len(), cost);
            searcher.start_search(problem, plan.plan.point(idx), &mut warnings)
        })?,
        Start::Values => {
            let values: Vec<f64> = problem
                .wrt()
                .iter()
                .map(|&i| problem.model().parameters[i].value)
                .collect();
            let u0: Vec<f64> = problem
                .to_normalised(&values)
                .into_iter()
                .map(|u| u.clamp(0.0, 1.0))
                .collect();
            let search = searcher
                .start_search(problem, &u0, &mut warnings)
                .map_err(IdentifyError::ValuesStart)?;
            (vec![search], Vec::new())
        }
    };
    Ok(Ends {
        searches,
        failures,
        used: plan.starts.iter().map(|&(idx, _)| idx).collect(),
        warnings,
        restart_warning: None,
    })
}

/// Runs `search` from every start (plan index, J), recording a failed
/// start instead of ending there; the finished searches and the failures,
/// or [`IdentifyError::AllStartsFailed`] if none finished.
fn run_starts<S>(
    starts: &[(usize, f64)],
    mut search: impl FnMut(usize, usize, f64) -> Result<S, SearchError>,
) -> Result<(Vec<S>, Vec<StartFailure>), IdentifyError> {
    let mut done = Vec::new();
    let mut failures = Vec::new();
    for (k, &(idx, cost)) in starts.iter().enumerate() {
        match search(k, idx, cost) {
            Ok(s) => done.push(s),
            Err(e) => failures.push(StartFailure {
                plan_index: idx,
                reason: e.to_string(),
            }),
        }
    }
    if done.is_empty() {
        return Err(IdentifyError::AllStartsFailed(failures));
    }
    Ok((done, failures))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::identification::problem::EvalError;
    use crate::identification::termination::SolveError;
    use crate::simulation::SimulationError;

    fn failed() -> SearchError {
        SolveError::StartFailed(EvalError::<SimulationError>::NonFinite { index: 0 })
    }

    /// Regression: one start whose first evaluation failed ended the whole
    /// identification, and the other starts were never tried.
    #[test]
    fn a_failed_start_does_not_end_the_identification() {
        let starts = [(4, 1.0), (7, 2.0), (2, 3.0)];
        let mut tried = Vec::new();
        let (done, failures) = run_starts(&starts, |k, idx, _| {
            tried.push(k);
            if idx == 4 {
                Err(failed())
            } else {
                Ok(idx)
            }
        })
        .unwrap();
        assert_eq!(tried, [0, 1, 2]);
        assert_eq!(done, [7, 2]);
        assert_eq!(
            failures,
            [StartFailure {
                plan_index: 4,
                reason: failed().to_string()
            }]
        );
    }

    /// Only when every start fails does the identification fail, naming each
    /// start's reason.
    #[test]
    fn all_starts_failed_names_every_reason() {
        let starts = [(4, 1.0), (7, 2.0)];
        let e = run_starts(&starts, |_, _, _| -> Result<(), _> { Err(failed()) }).unwrap_err();
        let IdentifyError::AllStartsFailed(f) = &e else {
            panic!("{e:?}")
        };
        assert_eq!(f.len(), 2);
        let msg = e.to_string();
        let reason = failed().to_string();
        assert!(
            msg.contains(&format!("plan point 5: {reason}"))
                && msg.contains(&format!("plan point 8: {reason}")),
            "{msg}"
        );
    }
}
