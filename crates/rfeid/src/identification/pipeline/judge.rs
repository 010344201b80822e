//! Stage 7, the verdict: the fit at the estimate, every sensor's signals,
//! and the checks of [`crate::identification::verdict`].
use super::bounds::Bounds;
use crate::identification::noise::{NoiseModel, Whitener};

/// No whitening (white noise).
static NO_FILTER: Whitener = Whitener::NONE;
use crate::identification::output_error::OutputError;
use crate::identification::problem::LeastSquares;
use crate::identification::search::SearchOutcome;
use crate::identification::verdict::{
    assess, fit_fails, fitted_exactly, Evidence, FitSignal, StartEnd, Verdict, VerdictSettings,
};
use crate::model::ColumnName;
use crate::simulation::{Response, SimulationError};

/// Whether the fit at u passes the verdict's per-sensor checks (fit,
/// whiteness, noise level, input) with each sensor's residuals whitened by
/// a noise model fitted to them (of the kind `noise_model` says), not by
/// the weighting the search used: coloured noise then passes with a correct
/// model whatever the search's weighting, and the decision does not depend
/// on prewhitening a criterion whose model may be wrong. A failed
/// simulation does not pass.
pub(super) fn fit_passes(
    problem: &OutputError<'_>,
    s: &VerdictSettings,
    noise_model: NoiseModel,
    u: &[f64],
) -> bool {
    let Ok(fitted) = problem.simulate_all(u) else {
        return false;
    };
    let mut signals = fit_signals(problem, Some(&fitted));
    let filters: Vec<Whitener> = signals
        .iter()
        .map(|sig| own_filter(sig, s, noise_model))
        .collect();
    for (sig, filter) in signals.iter_mut().zip(&filters) {
        sig.whitening = filter;
    }
    !fit_fails(&signals, s)
}

/// The whitening filter of a noise model of kind `noise_model` fitted to
/// the residuals of `sig` (none for white noise, or a sensor fitted exactly).
fn own_filter(sig: &FitSignal<'_>, s: &VerdictSettings, noise_model: NoiseModel) -> Whitener {
    if fitted_exactly(sig, s) {
        return Whitener::default();
    }
    noise_model.filter(&sig.residuals())
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
                whitening: filters.next().unwrap_or(&NO_FILTER),
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
