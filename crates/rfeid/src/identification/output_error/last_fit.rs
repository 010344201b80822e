//! The responses of the last [`OutputError::simulate_all`], kept for the
//! next call at the same point. The pipeline asks for the fit at one point
//! several times over: the fit checks at a search's end, the first round of
//! the reweighting there, the verdict's fitted signals at the estimate. A
//! response depends on the parameter values, the integrator and the kernel
//! alone, so the kept one is what a new run would give, bit for bit; it is
//! not a simulation, and is not counted as one.
use super::OutputError;
use crate::simulation::{Integrator, Kernel, Response, Simulator};
use std::sync::Mutex;

/// The last fit, if any. A clone starts empty, as the kept runs do
/// (`kept`): searches at once on clones would otherwise take each other's
/// fits, and their tallies would depend on the threads.
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
