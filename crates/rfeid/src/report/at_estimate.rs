//! A result's report from the model and the measured signals: the model
//! simulated at the estimate with the steps the identification ended with,
//! then the report's files ([`report_files`]). `rfeid identify --report`,
//! `rfeid report` and the Python module's `Result.report` all render here.
use super::{report_files, ReportError, ReportInput};
use crate::identification::result::{EstimateError, IdentificationResult};
use crate::model::Model;
use crate::simulation::{Response, SimulationError, Simulator, Workspace};

/// Why a report could not be rendered.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// The result does not belong to the model (an estimate of a parameter
    /// the model lacks).
    #[error("{0}")]
    Parameters(String),
    /// The model could not be simulated at the estimate.
    #[error("simulating at the estimate failed: {0}")]
    Simulation(#[from] SimulationError),
    /// The report's inputs do not fit together.
    #[error("report: {0}")]
    Report(#[from] ReportError),
}

/// Simulates at the estimate, as experiment `experiment` of a campaign sees
/// it (`""` for a data file on its own), and renders the report's files
/// (name, text); `reference` is a column of reference values (the demo's
/// true values).
pub fn render(
    model: &Model,
    result: &IdentificationResult,
    experiment: &str,
    measured: &Response,
    reference: Option<&[f64]>,
    title: &str,
) -> Result<Vec<(String, String)>, RenderError> {
    let params = result
        .parameter_values(model, experiment)
        .map_err(RenderError::Parameters)?;
    // The steps the identification ended with, as recorded.
    let sim = match &result.simulation {
        Some(steps) => {
            Simulator::with_integrator(model, crate::simulation::steps::integrator(steps.substeps))
        }
        None => Simulator::new(model),
    };
    let mut fitted = sim.response_buffer();
    sim.run(&params, &mut Workspace::default(), &mut fitted)?;
    render_fitted(model, result, measured, &fitted, reference, title)
}

/// Renders the report's files (name, text) of `result` with the model's
/// response `fitted` at the estimate already simulated.
pub fn render_fitted(
    model: &Model,
    result: &IdentificationResult,
    measured: &Response,
    fitted: &Response,
    reference: Option<&[f64]>,
    title: &str,
) -> Result<Vec<(String, String)>, RenderError> {
    let time: Vec<f64> = (0..fitted.n_samples)
        .map(|k| model.sampling.time(k))
        .collect();
    let input = ReportInput {
        title: title.to_string(),
        model,
        result,
        time: &time,
        measured,
        fitted,
        reference,
    };
    Ok(report_files(&input)?)
}

/// The report of a campaign (SPEC §5): the fitted experiments' sensors side
/// by side (`sensor[experiment]`, as in the result), each experiment's
/// model (`models`, [`Model::for_experiment`]) simulated at the estimate
/// with steps chosen there, on the shortest of their records; the
/// experiments' fits in the summary.
pub fn render_campaign(
    model: &Model,
    models: &[Model],
    result: &IdentificationResult,
    measured: &[Response],
    title: &str,
) -> Result<Vec<(String, String)>, RenderError> {
    let fitted_idx = model.fitted_experiments();
    let n = fitted_idx
        .iter()
        .map(|&e| measured[e].n_samples)
        .min()
        .unwrap_or(0);
    let (mut y, mut g) = (Vec::new(), Vec::new());
    let mut sensors = 0;
    for &e in &fitted_idx {
        let name = &model.experiments[e].name;
        let (sim, _) = result
            .simulate_at_estimate(&models[e], name)
            .map_err(|e| match e {
                EstimateError::NotInModel(m) => RenderError::Parameters(m),
                EstimateError::Simulation(s) => RenderError::Simulation(s),
            })?;
        for c in 0..measured[e].n_sensors {
            y.extend_from_slice(&measured[e].sensor(c)[..n]);
            g.extend_from_slice(&sim.sensor(c)[..n]);
            sensors += 1;
        }
    }
    let stack = |values| Response {
        n_samples: n,
        n_sensors: sensors,
        values,
    };
    let (measured, fitted) = (stack(y), stack(g));
    let first = fitted_idx.first().map_or(0, |&e| e);
    let time: Vec<f64> = (0..n).map(|k| models[first].sampling.time(k)).collect();
    let input = ReportInput {
        title: title.to_string(),
        model,
        result,
        time: &time,
        measured: &measured,
        fitted: &fitted,
        reference: None,
    };
    Ok(report_files(&input)?)
}
