//! One experiment's part of the criterion: its residual rows and their
//! Jacobian.
use super::ExperimentData;
use crate::identification::box_map::BoxMap;
use crate::identification::noise::ar::Whitener;
use crate::simulation::{Response, Sensitivities, SimulationError, Workspace};
use nalgebra::DMatrix;

/// One experiment of the criterion.
#[derive(Debug, Clone)]
pub(super) struct Part<'m> {
    pub(super) data: ExperimentData<'m>,
    /// Sensor weights w_ec.
    pub(super) sensor_weights: Vec<f64>,
    /// √(w_e w_ec) per sensor.
    pub(super) sqrt_weights: Vec<f64>,
    /// Each sensor's whitening filter ([`crate::identification::noise`];
    /// no coefficients: white noise).
    pub(super) whitening: Vec<Whitener>,
    /// The identified parameters (model indices) and their columns in u.
    pub(super) wrt: Vec<usize>,
    pub(super) cols: Vec<usize>,
    /// Values of all parameters; the identified ones are overwritten.
    pub(super) base: Vec<f64>,
    /// The part's first residual row.
    pub(super) row0: usize,
    /// Each excitation's force at the samples used, at the model's nominal
    /// values (for the verdict's residual–input test).
    pub(super) inputs: Vec<Vec<f64>>,
}

/// Each excitation's force P(t_k) of `model` at its nominal values, for
/// the samples from `first`.
pub(super) fn excitation_samples(model: &crate::model::Model, first: usize) -> Vec<Vec<f64>> {
    let x = model.nominal();
    let sampling = model.sampling;
    model
        .excitations
        .iter()
        .map(|e| {
            (first..sampling.n_samples())
                .map(|k| e.signal.at(sampling.time(k), &x))
                .collect()
        })
        .collect()
}

/// Scratch memory of one experiment's evaluation.
#[derive(Debug, Clone)]
pub(super) struct PartWorkspace {
    pub(super) sim: Workspace,
    pub(super) response: Response,
    pub(super) sens: Sensitivities,
    pub(super) params: Vec<f64>,
    /// dx/du of the part's identified parameters at the current u.
    pub(super) dx_du: Vec<f64>,
    /// The part's rows of the Jacobian (campaigns only).
    pub(super) jac: DMatrix<f64>,
    /// What a watched evaluation (`watch`) carries between its checks:
    /// per sensor, the last unfiltered residuals the whitening reaches
    /// back to; a filter's input; a block's residuals.
    pub(super) past: Vec<Vec<f64>>,
    pub(super) line: Vec<f64>,
    pub(super) block: Vec<f64>,
}

impl Part<'_> {
    pub(super) fn samples_used(&self) -> usize {
        self.data.measured.n_samples.saturating_sub(self.data.first)
    }

    pub(super) fn n_residuals(&self) -> usize {
        self.data.measured.n_sensors * self.samples_used()
    }

    pub(super) fn workspace(&self, n_cols: usize) -> PartWorkspace {
        PartWorkspace {
            sim: Workspace::default(),
            response: self.data.sim.response_buffer(),
            sens: Sensitivities {
                wrt: Vec::new(),
                values: Vec::new(),
            },
            params: Vec::with_capacity(self.base.len()),
            dx_du: vec![0.0; self.wrt.len()],
            jac: DMatrix::zeros(if n_cols > 0 { self.n_residuals() } else { 0 }, n_cols),
            past: vec![Vec::new(); self.whitening.len()],
            line: Vec::new(),
            block: Vec::new(),
        }
    }

    pub(super) fn all_params(&self, u: &[f64], maps: &[BoxMap], out: &mut Vec<f64>) {
        out.clear();
        out.extend_from_slice(&self.base);
        for (&i, &c) in self.wrt.iter().zip(&self.cols) {
            out[i] = maps[c].to_physical(u[c]);
        }
    }

    pub(super) fn fill_residuals(&self, response: &Response, r: &mut [f64]) {
        let n = response.n_samples;
        let first = self.data.first;
        let used = n - first;
        for c in 0..response.n_sensors {
            let g = &response.sensor(c)[first..];
            let y = &self.data.measured.sensor(c)[first..];
            let w = self.sqrt_weights[c];
            let rows = &mut r[c * used..(c + 1) * used];
            for ((ri, gi), yi) in rows.iter_mut().zip(g).zip(y) {
                *ri = w * (gi - yi);
            }
            self.whitening[c].apply(rows);
        }
    }

    pub(super) fn residuals(
        &self,
        ws: &mut PartWorkspace,
        u: &[f64],
        maps: &[BoxMap],
        r: &mut [f64],
    ) -> Result<(), SimulationError> {
        self.all_params(u, maps, &mut ws.params);
        self.data
            .sim
            .run(&ws.params, &mut ws.sim, &mut ws.response)?;
        self.fill_residuals(&ws.response, r);
        Ok(())
    }

    /// Residuals into `r` and the Jacobian into rows `row0..` of `jac` (the
    /// whole Jacobian) or, if `jac` is `None`, into the workspace's own.
    pub(super) fn residuals_jacobian(
        &self,
        ws: &mut PartWorkspace,
        u: &[f64],
        maps: &[BoxMap],
        r: &mut [f64],
        jac: Option<(&mut DMatrix<f64>, usize)>,
    ) -> Result<(), SimulationError> {
        self.all_params(u, maps, &mut ws.params);
        self.data.sim.run_with_sensitivities(
            &ws.params,
            &self.wrt,
            &mut ws.sim,
            &mut ws.response,
            &mut ws.sens,
        )?;
        let run = (&ws.response, &ws.sens);
        self.linearise(run, (&mut ws.dx_du, &mut ws.jac), (u, maps), r, jac);
        Ok(())
    }

    /// [`Part::residuals_jacobian`] from a run with sensitivities at `u`
    /// (`response`, `sens`), with the workspace's `dx_du` and own Jacobian
    /// (`own`, used when `jac` is `None`).
    pub(super) fn linearise(
        &self,
        (response, sens): (&Response, &Sensitivities),
        (dx_du, own): (&mut [f64], &mut DMatrix<f64>),
        (u, maps): (&[f64], &[BoxMap]),
        r: &mut [f64],
        jac: Option<(&mut DMatrix<f64>, usize)>,
    ) {
        let n_cols = maps.len();
        self.fill_residuals(response, r);
        for (d, &c) in dx_du.iter_mut().zip(&self.cols) {
            *d = maps[c].derivative(u[c]);
        }
        let (jac, row0) = match jac {
            Some(j) => j,
            None => {
                // A workspace made without it (for the factor by blocks).
                if own.nrows() != self.n_residuals() {
                    *own = DMatrix::zeros(self.n_residuals(), n_cols);
                }
                (own, 0)
            }
        };
        let n = response.n_samples;
        let first = self.data.first;
        let used = n - first;
        let p = self.wrt.len();
        for c in 0..response.n_sensors {
            let w = self.sqrt_weights[c];
            for k in first..n {
                let row = row0 + c * used + (k - first);
                let src = &sens.values[(c * n + k) * p..(c * n + k + 1) * p];
                for j in 0..p {
                    jac[(row, self.cols[j])] = w * src[j] * dx_du[j];
                }
            }
            // The same fixed filter as the residuals': the filtered
            // Jacobian is the Jacobian of the filtered residuals.
            if self.whitening[c].order() > 0 {
                let (n_rows, start) = (jac.nrows(), row0 + c * used);
                for &col in &self.cols {
                    let column = &mut jac.as_mut_slice()[col * n_rows..(col + 1) * n_rows];
                    self.whitening[c].apply(&mut column[start..start + used]);
                }
            }
        }
    }
}
