//! A model simulated at an identification's estimate (the library's
//! [`IdentificationResult::simulate_at_estimate`]), its failures as the
//! command line reports them.
use super::failures::simulation_failure;
use crate::diagnostics::Failure;
use rfeid::identification::result::{EstimateError, IdentificationResult};
use rfeid::model::Model;
use rfeid::simulation::{Response, StepChoice};

/// `m` simulated at the result's estimate, as experiment `experiment` sees
/// it, with steps chosen there: the response and the steps. A result of
/// another model is bad input; a failed simulation as
/// [`simulation_failure`] says.
pub fn simulate_at_estimate(
    result: &IdentificationResult,
    m: &Model,
    experiment: &str,
) -> Result<(Response, StepChoice), Failure> {
    result
        .simulate_at_estimate(m, experiment)
        .map_err(|e| match e {
            EstimateError::NotInModel(message) => Failure::input_msg(message),
            EstimateError::Simulation(e) => simulation_failure("simulating at the estimate", e),
        })
}
