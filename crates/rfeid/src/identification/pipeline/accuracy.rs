//! Stage 6, the accuracy at the estimate: the steps per sample were chosen
//! before the search and held fixed (so that J stays smooth); they are
//! checked at the estimate, and if it needs finer ones, or the searches
//! took the fewer steps a search may (`crate::simulation::steps`,
//! "Searches"), the search goes on at the checked steps. Modes above the
//! Nyquist frequency are named.
use super::error::IdentifyError;
use super::searcher::Searcher;
use crate::identification::output_error::OutputError;
use crate::identification::search::SearchOutcome;
use crate::identification::tally::Tally;
use crate::identification::warning::Warning;
use crate::simulation::steps::{choose_steps, estimate_error};
use crate::simulation::StepChoice;

/// The steps checked at the estimate; the estimate, refined if finer steps
/// were needed or the searches took fewer (the search continued: see
/// [`SearchOutcome::then`]; with the residuals and whole Jacobian it ended
/// with, when Levenberg–Marquardt took one, for the bounds), and the
/// warnings. Every experiment takes its checked steps afterwards.
pub(super) fn check(
    problem: &mut OutputError<'_>,
    searcher: &Searcher<'_>,
    mut best: SearchOutcome,
) -> Result<(SearchOutcome, Vec<Warning>), IdentifyError> {
    let mut warnings = Vec::new();
    for _ in 0..3 {
        // Finer steps than chosen (check again after the search), or back
        // from a search's fewer steps to the checked ones (no need to).
        let (mut finer, mut back) = (false, false);
        for p in 0..problem.n_experiments() {
            let ran = problem.experiment_simulator(p).integrator().substeps;
            match check_steps(problem, p, &best.u) {
                Ok(Checked::Finer) => finer = true,
                Ok(Checked::Held(w)) => warnings.extend(w),
                Err(e) => {
                    warnings.push(Warning::StepsUnchecked(e));
                    problem.use_chosen_steps(p);
                }
            }
            back |= problem.experiment_simulator(p).integrator().substeps != ran;
        }
        if !finer && !back {
            break;
        }
        let refined = searcher.refine(problem, &best.u)?;
        best = best.then(refined);
        if !finer {
            break;
        }
    }
    warnings.dedup();
    for p in 0..problem.n_experiments() {
        let mut x = Vec::new();
        problem.experiment_params(p, &best.u, &mut x);
        warnings.extend(
            crate::simulation::aliasing::above_nyquist(problem.experiment_simulator(p), &x)
                .into_iter()
                .map(Warning::AboveNyquist),
        );
    }
    warnings.dedup();
    Ok((best, warnings))
}

/// What the check of one experiment's steps found.
enum Checked {
    /// Finer steps than chosen are needed: the search must go on.
    Finer,
    /// The steps stay; a warning if their error exceeds the tolerance.
    Held(Option<Warning>),
}

/// Checks experiment p's steps per sample at u and holds the checked ones
/// (their runs recorded in the problem's tally).
fn check_steps(
    problem: &mut OutputError<'_>,
    p: usize,
    u: &[f64],
) -> Result<Checked, crate::simulation::SimulationError> {
    let mut x = Vec::new();
    problem.experiment_params(p, u, &mut x);
    let sim = problem.experiment_simulator(p);
    let (model, held) = (sim.model(), sim.steps());
    let since = std::time::Instant::now();
    let c = match held.automatic {
        true => choose_steps(model, &x, held.tolerance, held.substeps),
        false => estimate_error(model, &x, held.substeps).map(|e| StepChoice {
            estimated_error: Some(e),
            runs: 2,
            ..held
        }),
    }?;
    problem.record(Tally::plain(c.runs), since.elapsed());
    problem.set_experiment_steps(
        p,
        StepChoice {
            runs: held.runs + c.runs,
            // What the plan and the searches took (the check starts from
            // the held steps, so its own record is of no search).
            search: held.search.filter(|s| s.substeps < c.substeps),
            ..c
        },
    );
    if c.substeps != held.substeps {
        return Ok(Checked::Finer);
    }
    Ok(Checked::Held(
        c.estimated_error
            .filter(|e| *e > c.tolerance)
            .map(|error| Warning::StepsTooCoarse {
                substeps: c.substeps,
                error,
                tolerance: c.tolerance,
            }),
    ))
}
