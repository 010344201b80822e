//! Stage 8, the verdict: the fit at the estimate, every sensor's signals,
//! and the checks of [`crate::identification::verdict`].
use super::bounds::Bounds;
use crate::identification::noise::{NoiseModel, Whitener};
use crate::identification::output_error::OutputError;
use crate::identification::problem::LeastSquares;
use crate::identification::search::SearchOutcome;
use crate::identification::verdict::{
    assess, fit_fails, fitted_exactly, Evidence, FitSignal, StartEnd, Verdict, VerdictSettings,
};
use crate::model::ColumnName;
use crate::simulation::{Response, SimulationError};

/// No whitening (white noise).
static NO_FILTER: Whitener = Whitener::NONE;

/// Whether the fit at u passes the verdict's per-sensor checks (fit,
/// whiteness, noise level, input) on what a noise model fitted to each
/// sensor's residuals leaves ([`own_filters`]), as the verdict judges them.
/// A failed simulation does not pass.
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
    let filters = own_filters(&signals, s, noise_model);
    whiten_by(&mut signals, &filters);
    !fit_fails(&signals, s)
}

/// Each sensor's whitening filter for the residual checks: a noise model
/// of kind `noise_model` fitted to its own residuals, not the weighting the
/// search used. The checks then judge what the noise model leaves and only
/// that, whatever the criterion was prewhitened with: coloured noise passes
/// with a correct model even where the final fit is output error with
/// white noise, and a check that a low-pass alone fails (the noise level
/// against first differences, the residuals following the input) never
/// sees unwhitened coloured residuals. With white noise models
/// (`--noise-model white`) the residuals are judged as they are.
fn own_filters(
    signals: &[FitSignal<'_>],
    s: &VerdictSettings,
    noise_model: NoiseModel,
) -> Vec<Whitener> {
    signals
        .iter()
        .map(|sig| own_filter(sig, s, noise_model))
        .collect()
}

/// Sets each signal's whitening to its filter in `filters`.
fn whiten_by<'a>(signals: &mut [FitSignal<'a>], filters: &'a [Whitener]) {
    for (sig, filter) in signals.iter_mut().zip(filters) {
        sig.whitening = filter;
    }
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
/// `fitted` at the estimate, its residual tests on what each sensor's own
/// noise model leaves ([`own_filters`]).
pub(super) fn verdict(
    problem: &OutputError<'_>,
    best: &SearchOutcome,
    ends: &[StartEnd],
    bounds: &Bounds,
    fitted: &Result<Vec<Response>, SimulationError>,
    settings: &super::Settings,
) -> Verdict {
    let names: Vec<String> = problem.columns().iter().map(|c| c.name.clone()).collect();
    let signals = fitted
        .as_ref()
        .map(|g| fit_signals(problem, Some(g)))
        .map_err(|e| e.to_string());
    let filters = signals.as_ref().map_or_else(
        |_| Vec::new(),
        |sig| own_filters(sig, &settings.verdict, settings.noise_model),
    );
    let signals = signals.map(|mut sig| {
        whiten_by(&mut sig, &filters);
        sig
    });
    assess(
        &Evidence {
            parameters: &names,
            u: &best.u,
            ends,
            observations: problem.n_residuals(),
            stop: best.stop,
            iterations: best.iterations,
            termination: best.stop.to_string(),
            signals,
            identifiability: match &bounds.cramer_rao {
                Ok(c) => Ok(&c.warnings),
                Err(e) => Err(e.describe(&names)),
            },
            correlation_threshold: settings.uncertainty.correlation_threshold(),
        },
        &settings.verdict,
    )
}
