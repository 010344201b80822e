//! The last run with sensitivities of each experiment, kept while a caller
//! asks ([`OutputError::keep_runs`]). Re-weighting the sensors
//! (`pipeline::weights`) ends one search and starts the next at the same
//! point: the Jacobian the first ended with, under the new weights, is the
//! same runs weighted anew, so the next takes its first residuals and
//! Jacobian from them instead of simulating again; the bounds at the
//! estimate take theirs, or the residuals that check a refining search's,
//! from them too. A kept run is used only for the same parameter values
//! (to the bit), integrator and kernel, so the residuals and the Jacobian
//! are those of a new run bit for bit (a run with sensitivities gives the
//! plain run's response bit for bit); it is not a simulation, and is not
//! counted as one.
use super::part::PartWorkspace;
use super::{OutputError, OutputErrorWorkspace};
use crate::simulation::{Integrator, Kernel, Response, Sensitivities, Simulator};
use nalgebra::DMatrix;
use std::sync::Mutex;

/// Each experiment's last run with sensitivities, if kept; off (`None`)
/// unless asked for. A clone starts off: it may simulate with other steps,
/// and searches run at once on one criterion would otherwise take each
/// other's runs, and their tallies would depend on the threads.
#[derive(Debug, Default)]
pub(super) struct KeptRuns(Option<Mutex<Vec<KeptRun>>>);

impl Clone for KeptRuns {
    fn clone(&self) -> Self {
        KeptRuns(None)
    }
}

/// One experiment's run: what it was run with, and what it gave.
#[derive(Debug)]
struct KeptRun {
    params: Vec<f64>,
    integrator: Integrator,
    kernel: Kernel,
    response: Response,
    sens: Sensitivities,
}

impl KeptRun {
    /// Whether this run is the one `sim` would make at `params`.
    fn matches(&self, sim: &Simulator<'_>, params: &[f64]) -> bool {
        self.integrator == sim.integrator()
            && self.kernel == sim.kernel()
            && self.params.len() == params.len()
            && (self.params.iter().zip(params)).all(|(a, b)| a.to_bits() == b.to_bits())
    }
}

impl OutputError<'_> {
    /// Keeps each experiment's last run with sensitivities from now on
    /// (`true`; those kept so far stay), or forgets them and stops
    /// (`false`); see the module's documentation. Only for searches one
    /// after the other: searches at once on one criterion would take each
    /// other's runs, and their tallies would depend on the threads.
    pub fn keep_runs(&mut self, keep: bool) {
        match keep {
            true if self.kept.0.is_some() => {}
            true => self.kept = KeptRuns(Some(Mutex::new(Vec::new()))),
            false => self.kept = KeptRuns(None),
        }
    }

    /// Whether runs are kept ([`OutputError::keep_runs`]).
    pub fn keeps_runs(&self) -> bool {
        self.kept.0.is_some()
    }

    /// Calls `f` with the workspaces and every experiment's kept run at
    /// `u` (the parameters into `PartWorkspace::params`), if every one is
    /// kept there; returns whether they were.
    fn with_kept(
        &self,
        ws: &mut OutputErrorWorkspace,
        u: &[f64],
        f: impl FnOnce(&mut OutputErrorWorkspace, &[KeptRun]),
    ) -> bool {
        let Some(kept) = &self.kept.0 else {
            return false;
        };
        for (part, pws) in self.parts.iter().zip(ws.parts.iter_mut()) {
            part.all_params(u, &self.maps, &mut pws.params);
        }
        let Ok(kept) = kept.lock() else {
            return false;
        };
        let hit = kept.len() == self.parts.len()
            && (self.parts.iter().zip(&ws.parts).zip(kept.iter()))
                .all(|((part, pws), run)| run.matches(&part.data.sim, &pws.params));
        if hit {
            f(ws, &kept);
        }
        hit
    }

    /// Every experiment's kept response at `u`, if each one's run is kept
    /// there and it runs at its chosen steps: the fit there
    /// ([`OutputError::simulate_all`]) without simulating.
    pub(super) fn kept_fit_at(&self, u: &[f64]) -> Option<Vec<Response>> {
        let kept = self.kept.0.as_ref()?.lock().ok()?;
        if kept.len() != self.parts.len() {
            return None;
        }
        let mut params = Vec::new();
        let mut responses = Vec::with_capacity(kept.len());
        for (part, run) in self.parts.iter().zip(kept.iter()) {
            part.all_params(u, &self.maps, &mut params);
            let sim = &part.data.sim;
            if sim.searching() || !run.matches(sim, &params) {
                return None;
            }
            responses.push(run.response.clone());
        }
        Some(responses)
    }

    /// Forgets the kept runs (before new ones are made, so that the old
    /// and the new are not held at once).
    pub(super) fn forget_kept(&self) {
        if let Some(Ok(mut kept)) = self.kept.0.as_ref().map(|k| k.lock()) {
            kept.clear();
        }
    }

    /// Keeps the runs the workspaces hold (just made, at their `params`),
    /// if runs are kept: the sensitivities move out of the workspaces,
    /// which the next run fills anew, and the response is copied.
    pub(super) fn keep(&self, ws: &mut [PartWorkspace]) {
        let Some(kept) = &self.kept.0 else {
            return;
        };
        let Ok(mut kept) = kept.lock() else {
            return;
        };
        kept.clear();
        for (part, pws) in self.parts.iter().zip(ws) {
            let sim = &part.data.sim;
            let none = Sensitivities {
                wrt: Vec::new(),
                values: Vec::new(),
            };
            kept.push(KeptRun {
                params: pws.params.clone(),
                integrator: sim.integrator(),
                kernel: sim.kernel(),
                response: pws.response.clone(),
                sens: std::mem::replace(&mut pws.sens, none),
            });
        }
    }
}

impl OutputError<'_> {
    /// The residuals and the Jacobian at `u` from the kept runs
    /// ([`OutputError::keep_runs`]) if every experiment's is kept there;
    /// returns whether they were.
    pub(super) fn linearise_kept(
        &self,
        ws: &mut OutputErrorWorkspace,
        u: &[f64],
        r: &mut [f64],
        jac: &mut DMatrix<f64>,
    ) -> bool {
        self.with_kept(ws, u, |ws, runs| {
            let at = (u, &self.maps[..]);
            if let ([part], [pws], [run]) = (&self.parts[..], &mut ws.parts[..], runs) {
                let own = (&mut pws.dx_du[..], &mut pws.jac);
                part.linearise((&run.response, &run.sens), own, at, r, Some((jac, 0)));
                return;
            }
            let rows = self.split_rows(r);
            let each = self.parts.iter().zip(&mut ws.parts).zip(rows).zip(runs);
            for (((part, pws), r), run) in each {
                let own = (&mut pws.dx_du[..], &mut pws.jac);
                part.linearise((&run.response, &run.sens), own, at, r, None);
            }
            self.gather_jacobian(ws, jac);
        })
    }

    /// The residuals at `u` from the kept runs' responses (a run with
    /// sensitivities gives the plain run's response bit for bit), if every
    /// experiment's is kept there; returns whether they were.
    pub(super) fn residuals_kept(
        &self,
        ws: &mut OutputErrorWorkspace,
        u: &[f64],
        r: &mut [f64],
    ) -> bool {
        self.with_kept(ws, u, |_, runs| {
            let rows = self.split_rows(r);
            for ((part, r), run) in self.parts.iter().zip(rows).zip(runs) {
                part.fill_residuals(&run.response, r);
            }
        })
    }

    /// Each experiment's rows of the Jacobian, from its workspace into
    /// `jac`.
    pub(super) fn gather_jacobian(&self, ws: &OutputErrorWorkspace, jac: &mut DMatrix<f64>) {
        for (part, pws) in self.parts.iter().zip(&ws.parts) {
            let rows = part.n_residuals();
            for j in 0..jac.ncols() {
                jac.view_mut((part.row0, j), (rows, 1))
                    .copy_from(&pws.jac.column(j));
            }
        }
    }
}
