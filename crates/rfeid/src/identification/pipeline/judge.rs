//! Stage 7, the verdict: the fit at the estimate, every sensor's signals,
//! and the checks of [`crate::identification::verdict`].
use super::bounds::Bounds;
use crate::identification::output_error::OutputError;
use crate::identification::problem::LeastSquares;
use crate::identification::search::SearchOutcome;
use crate::identification::verdict::{
    assess, fit_fails, Evidence, FitSignal, StartEnd, Verdict, VerdictSettings,
};
use crate::model::ColumnName;
use crate::simulation::{Response, SimulationError};

/// Whether the fit at u passes the verdict's per-sensor checks (fit,
/// whiteness, noise level); a failed simulation does not.
pub(super) fn fit_passes(problem: &OutputError<'_>, s: &VerdictSettings, u: &[f64]) -> bool {
    problem
        .simulate_all(u)
        .is_ok_and(|g| !fit_fails(&fit_signals(problem, Some(&g)), s))
}

/// Every sensor of every experiment, named `sensor[experiment]` in a
/// campaign, with its measured and fitted signals from the first sample
/// used and its whitening filter.
pub(super) fn fit_signals<'a>(
    problem: &'a OutputError<'_>,
    fitted: Option<&'a [Response]>,
) -> Vec<FitSignal<'a>> {
    let mut filters = problem.whitening_filters();
    let mut out = Vec::new();
    for p in 0..problem.n_experiments() {
        let model = problem.experiment_simulator(p).model();
        let y = problem.experiment_measured(p);
        let first = problem.experiment_first(p);
        for (c, s) in model.sensors.iter().enumerate() {
            out.push(FitSignal {
                sensor: ColumnName::new(&s.name, problem.experiment_name(p)).to_string(),
                measured: &y.sensor(c)[first..],
                fitted: fitted.map_or(&[][..], |g| &g[p].sensor(c)[first..]),
                whitening: filters.next().unwrap_or(&[]),
                inputs: problem.experiment_inputs(p),
                sample_rate: model.sampling.sample_rate,
            });
        }
    }
    out
}

/// The verdict on `best`, kept `ends` and the `bounds`, from the fit
/// `fitted` at the estimate.
pub(super) fn verdict(
    problem: &OutputError<'_>,
    best: &SearchOutcome,
    ends: &[StartEnd],
    bounds: &Bounds,
    fitted: &Result<Vec<Response>, SimulationError>,
    settings: &super::Settings,
) -> Verdict {
    let names: Vec<String> = problem.columns().iter().map(|c| c.name.clone()).collect();
    assess(
        &Evidence {
            parameters: &names,
            u: &best.u,
            ends,
            observations: problem.n_residuals(),
            stop: best.stop,
            iterations: best.iterations,
            termination: best.stop.to_string(),
            signals: match fitted {
                Ok(g) => Ok(fit_signals(problem, Some(g))),
                Err(e) => Err(e.to_string()),
            },
            identifiability: match &bounds.cramer_rao {
                Ok(c) => Ok(&c.warnings),
                Err(e) => Err(e.to_string()),
            },
            correlation_threshold: settings.uncertainty.correlation_threshold(),
        },
        &settings.verdict,
    )
}
