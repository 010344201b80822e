//! The fit at a point ([`OutputError::simulate_all`]), and its responses
//! kept for the next call at the same point. The pipeline asks for the fit
//! at one point several times over: the fit checks at a search's end, the
//! first round of the reweighting there, the verdict's fitted signals at
//! the estimate. For the criterion's life the model, its fixed values and
//! the data are fixed, so a response depends on the parameter values, the
//! integrator and the kernel alone: the kept one is what a new run would
//! give, bit for bit; it is not a simulation, and is not counted as one.
use super::OutputError;
use crate::simulation::{Integrator, Kernel, Response, SimulationError, Simulator};
use rayon::prelude::*;
use std::sync::Mutex;
use std::time::Instant;

/// The last fit, if any. A clone starts empty, as the kept runs do
/// (`kept`), so that what a clone simulates does not depend on what its
/// original fitted before it was made.
#[derive(Debug, Default)]
pub(super) struct LastFit(Mutex<Option<Fit>>);

impl Clone for LastFit {
    fn clone(&self) -> Self {
        LastFit::default()
    }
}

/// One fit: the point, how each experiment was run, and the responses.
#[derive(Debug)]
struct Fit {
    u: Vec<f64>,
    runs: Vec<(Integrator, Kernel)>,
    responses: Vec<Response>,
}

/// How [`OutputError::simulate_all`] runs `sim`: at its chosen steps, with
/// its kernel.
fn fit_run(sim: &Simulator<'_>) -> (Integrator, Kernel) {
    let mut integrator = sim.integrator();
    integrator.substeps = sim.steps().substeps;
    (integrator, sim.kernel())
}

impl OutputError<'_> {
    /// Every experiment's simulated response at u, in parallel, at its
    /// chosen steps even while the searches take fewer
    /// ([`OutputError::use_search_steps`]): the fit is judged, and the noise
    /// estimated, at the full tolerance. A second call at the same point
    /// (to the bit) and the same steps takes the first's responses, and a
    /// call where the runs with sensitivities are kept
    /// ([`OutputError::keep_runs`]) at the chosen steps takes theirs: what a
    /// new run would give, bit for bit, and not counted as a simulation.
    pub fn simulate_all(&self, u: &[f64]) -> Result<Vec<Response>, SimulationError> {
        self.check_cancel()?;
        if let Some(responses) = self.last_fit_at(u) {
            return Ok(responses);
        }
        if let Some(responses) = self.kept_fit_at(u) {
            self.keep_fit(u, &responses);
            return Ok(responses);
        }
        let since = Instant::now();
        let results: Vec<_> = (0..self.parts.len())
            .into_par_iter()
            .map(|i| self.simulate_part(i, u))
            .collect();
        self.count(&results, false, since);
        let responses: Result<Vec<Response>, _> = results.into_iter().collect();
        if let Ok(responses) = &responses {
            self.keep_fit(u, responses);
        }
        responses
    }

    /// Experiment `i`'s simulated response at u, at its chosen steps.
    fn simulate_part(&self, i: usize, u: &[f64]) -> Result<Response, SimulationError> {
        self.check_cancel()?;
        let part = &self.parts[i];
        let mut ws = part.workspace(0);
        part.all_params(u, &self.maps, &mut ws.params);
        let chosen = part.data.sim.searching().then(|| {
            let mut sim = part.data.sim.clone();
            sim.use_chosen_steps();
            sim
        });
        chosen
            .as_ref()
            .unwrap_or(&part.data.sim)
            .run(&ws.params, &mut ws.sim, &mut ws.response)?;
        Ok(ws.response)
    }

    /// The responses of the last fit, if it was at `u` (to the bit) with
    /// the integrators and kernels every experiment now takes for a fit.
    pub(super) fn last_fit_at(&self, u: &[f64]) -> Option<Vec<Response>> {
        let last = self.last_fit.0.lock().ok()?;
        let fit = last.as_ref()?;
        let same_u = fit.u.len() == u.len()
            && (fit.u.iter().zip(u)).all(|(a, b)| a.to_bits() == b.to_bits());
        let same_runs = fit.runs.len() == self.parts.len()
            && (self.parts.iter().zip(&fit.runs)).all(|(p, r)| fit_run(&p.data.sim) == *r);
        (same_u && same_runs).then(|| fit.responses.clone())
    }

    /// Keeps `responses`, the fit at `u`, in place of the last.
    pub(super) fn keep_fit(&self, u: &[f64], responses: &[Response]) {
        if let Ok(mut last) = self.last_fit.0.lock() {
            *last = Some(Fit {
                u: u.to_vec(),
                runs: self.parts.iter().map(|p| fit_run(&p.data.sim)).collect(),
                responses: responses.to_vec(),
            });
        }
    }
}
