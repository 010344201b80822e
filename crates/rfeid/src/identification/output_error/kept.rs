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
pub(super) struct KeptRuns(Option<Mutex<Vec<Option<KeptRun>>>>);

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

    /// Copies into the workspaces the kept run of every experiment at `u`
    /// (the parameters into `PartWorkspace::params`), its response and, if
    /// `sens`, its sensitivities, if every one is kept; returns whether
    /// they were.
    fn take_kept(&self, ws: &mut OutputErrorWorkspace, u: &[f64], sens: bool) -> bool {
        let Some(kept) = &self.kept.0 else {
            return false;
        };
        let ws = &mut ws.parts[..];
        for (part, pws) in self.parts.iter().zip(ws.iter_mut()) {
            part.all_params(u, &self.maps, &mut pws.params);
        }
        let Ok(kept) = kept.lock() else {
            return false;
        };
        let hit = kept.len() == self.parts.len()
            && (self.parts.iter().zip(ws.iter()).zip(kept.iter())).all(|((part, pws), run)| {
                run.as_ref()
                    .is_some_and(|run| run.matches(&part.data.sim, &pws.params))
            });
        if hit {
            for (pws, run) in ws.iter_mut().zip(kept.iter().flatten()) {
                pws.response.clone_from(&run.response);
                if sens {
                    pws.sens.clone_from(&run.sens);
                }
            }
        }
        hit
    }

    /// Keeps the runs the workspaces hold (just made, at their
    /// `params`), if runs are kept.
    pub(super) fn keep(&self, ws: &[PartWorkspace]) {
        let Some(kept) = &self.kept.0 else {
            return;
        };
        let Ok(mut kept) = kept.lock() else {
            return;
        };
        kept.resize_with(self.parts.len(), || None);
        for ((part, pws), run) in self.parts.iter().zip(ws).zip(kept.iter_mut()) {
            let sim = &part.data.sim;
            *run = Some(KeptRun {
                params: pws.params.clone(),
                integrator: sim.integrator(),
                kernel: sim.kernel(),
                response: pws.response.clone(),
                sens: pws.sens.clone(),
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
        if !self.take_kept(ws, u, true) {
            return false;
        }
        if let ([part], [pws]) = (self.parts.as_slice(), ws.parts.as_mut_slice()) {
            part.linearise(pws, u, &self.maps, r, Some((jac, 0)));
            return true;
        }
        let rows = self.split_rows(r);
        for ((part, pws), r) in self.parts.iter().zip(&mut ws.parts).zip(rows) {
            part.linearise(pws, u, &self.maps, r, None);
        }
        self.gather_jacobian(ws, jac);
        true
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
        if !self.take_kept(ws, u, false) {
            return false;
        }
        let rows = self.split_rows(r);
        for ((part, pws), r) in self.parts.iter().zip(&ws.parts).zip(rows) {
            part.fill_residuals(&pws.response, r);
        }
        true
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
