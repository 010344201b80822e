//! A model simulated at an identification's estimate.
use super::failures::simulation_failure;
use crate::diagnostics::Failure;
use rfeid::identification::result::IdentificationResult;
use rfeid::model::Model;
use rfeid::simulation::{Response, Simulator, Workspace};

/// `m` simulated at the result's estimate, as experiment `experiment` sees
/// it, with steps chosen there.
pub fn simulate_at_estimate(
    result: &IdentificationResult,
    m: &Model,
    experiment: &str,
) -> Result<Response, Failure> {
    let x = result
        .parameter_values(m, experiment)
        .map_err(Failure::input_msg)?;
    let sim = Simulator::choose(m, &x)
        .map_err(|e| simulation_failure("simulating at the estimate", e))?;
    let mut out = sim.response_buffer();
    sim.run(&x, &mut Workspace::default(), &mut out)
        .map_err(|e| simulation_failure("simulating at the estimate", e))?;
    Ok(out)
}
