//! The output-error criterion of a model against measured signals
//! (eq. 10–16) as a [`LeastSquares`] problem in normalised coordinates.
//!
//! Residuals are `r_ck = √w_c (g_ck(x) − y_ck)` for every sensor c and every
//! sample k from the first used one, so `J = Σ r²` is eq. 13 with
//! `R⁻¹ = diag(w_c)`, and eq. 16 for `w_c = 1`. The parameters are
//! `x = x_min + u (x_max − x_min)` (eq. 17), or `x = x_min (x_max/x_min)^u`
//! on a log scale ([`super::box_map`]); the Jacobian comes from the forward
//! sensitivities ([`crate::simulation::run`]) times `dx/du`.
use super::box_map::BoxMap;
use super::problem::LeastSquares;
use crate::model::Model;
use crate::simulation::{Response, Sensitivities, SimulationError, Simulator, Workspace};
use nalgebra::DMatrix;

/// Model, data and weighting: the criterion J(u).
#[derive(Debug, Clone)]
pub struct OutputError<'m> {
    sim: Simulator<'m>,
    measured: Response,
    /// Identified parameters (indices into the model's parameters).
    wrt: Vec<usize>,
    maps: Vec<BoxMap>,
    width: Vec<f64>,
    /// Values of all parameters; the identified ones are overwritten.
    base: Vec<f64>,
    /// √w_c per sensor.
    sqrt_weights: Vec<f64>,
    /// First sample used (`--from`).
    first: usize,
}

/// Scratch memory of one evaluation.
#[derive(Debug, Clone)]
pub struct OutputErrorWorkspace {
    sim: Workspace,
    response: Response,
    sens: Sensitivities,
    params: Vec<f64>,
    /// dx/du of the identified parameters at the current u.
    dx_du: Vec<f64>,
}

impl<'m> OutputError<'m> {
    /// The criterion for the model's identified parameters; `measured` must
    /// have the model's sensors and sampling ([`crate::measurement::match_data`]).
    pub fn new(sim: Simulator<'m>, measured: Response, first: usize) -> Self {
        let model: &Model = sim.model();
        let wrt = model.identified();
        let maps: Vec<BoxMap> = wrt
            .iter()
            .map(|&i| {
                let p = &model.parameters[i];
                let (lo, hi) = p.bounds.expect("identified parameters have boxes");
                BoxMap::new(lo, hi, p.scale)
            })
            .collect();
        let width = maps.iter().map(BoxMap::width).collect();
        let n_sensors = measured.n_sensors;
        OutputError {
            base: model.nominal(),
            sim,
            measured,
            wrt,
            maps,
            width,
            sqrt_weights: vec![1.0; n_sensors],
            first,
        }
    }

    /// Sets the per-sensor weights w_c (eq. 13 with a diagonal R).
    pub fn set_weights(&mut self, weights: &[f64]) {
        self.sqrt_weights = weights.iter().map(|w| w.sqrt()).collect();
    }

    /// The per-sensor weights w_c.
    pub fn weights(&self) -> Vec<f64> {
        self.sqrt_weights.iter().map(|s| s * s).collect()
    }

    /// The identified parameters (model indices).
    pub fn wrt(&self) -> &[usize] {
        &self.wrt
    }

    /// Box widths `x_max − x_min`.
    pub fn widths(&self) -> &[f64] {
        &self.width
    }

    /// The maps between the boxes and the normalised coordinate.
    pub fn maps(&self) -> &[BoxMap] {
        &self.maps
    }

    /// Physical parameter values (identified ones only) at u.
    pub fn to_physical(&self, u: &[f64]) -> Vec<f64> {
        u.iter()
            .zip(&self.maps)
            .map(|(u, m)| m.to_physical(*u))
            .collect()
    }

    /// Normalised coordinates of physical values.
    pub fn to_normalised(&self, x: &[f64]) -> Vec<f64> {
        x.iter()
            .zip(&self.maps)
            .map(|(x, m)| m.to_normalised(*x))
            .collect()
    }

    /// `dx_j/du_j` at u: the chain-rule factors between the Jacobians in u
    /// and in x.
    pub fn dx_du(&self, u: &[f64]) -> Vec<f64> {
        u.iter()
            .zip(&self.maps)
            .map(|(u, m)| m.derivative(*u))
            .collect()
    }

    /// The simulator.
    pub fn simulator(&self) -> &Simulator<'m> {
        &self.sim
    }

    /// Simulates with `steps` steps per sample from now on (the criterion
    /// changes with them: use between searches, never within one).
    pub fn set_steps(&mut self, steps: crate::simulation::StepChoice) {
        self.sim.set_steps(steps);
    }

    /// The measured signals.
    pub fn measured(&self) -> &Response {
        &self.measured
    }

    /// First sample used.
    pub fn first_sample(&self) -> usize {
        self.first
    }

    /// Samples used per sensor.
    pub fn samples_used(&self) -> usize {
        self.measured.n_samples.saturating_sub(self.first)
    }

    /// All parameter values at u.
    pub fn all_params(&self, u: &[f64], out: &mut Vec<f64>) {
        out.clear();
        out.extend_from_slice(&self.base);
        for ((&i, &u), m) in self.wrt.iter().zip(u).zip(&self.maps) {
            out[i] = m.to_physical(u);
        }
    }

    /// The simulated response at u.
    pub fn simulate(&self, u: &[f64]) -> Result<Response, SimulationError> {
        let mut ws = self.workspace();
        self.all_params(u, &mut ws.params);
        self.sim.run(&ws.params, &mut ws.sim, &mut ws.response)?;
        Ok(ws.response)
    }

    fn fill_residuals(&self, response: &Response, r: &mut [f64]) {
        let n = response.n_samples;
        let used = n - self.first;
        for c in 0..response.n_sensors {
            let g = &response.sensor(c)[self.first..];
            let y = &self.measured.sensor(c)[self.first..];
            let w = self.sqrt_weights[c];
            for ((ri, gi), yi) in r[c * used..(c + 1) * used].iter_mut().zip(g).zip(y) {
                *ri = w * (gi - yi);
            }
        }
    }
}

impl LeastSquares for OutputError<'_> {
    type Workspace = OutputErrorWorkspace;
    type Error = SimulationError;

    fn n_params(&self) -> usize {
        self.wrt.len()
    }

    fn n_residuals(&self) -> usize {
        self.measured.n_sensors * self.samples_used()
    }

    fn workspace(&self) -> OutputErrorWorkspace {
        OutputErrorWorkspace {
            sim: Workspace::default(),
            response: self.sim.response_buffer(),
            sens: Sensitivities {
                wrt: Vec::new(),
                values: Vec::new(),
            },
            params: Vec::with_capacity(self.base.len()),
            dx_du: vec![0.0; self.wrt.len()],
        }
    }

    fn residuals(
        &self,
        ws: &mut OutputErrorWorkspace,
        u: &[f64],
        r: &mut [f64],
    ) -> Result<(), SimulationError> {
        self.all_params(u, &mut ws.params);
        self.sim.run(&ws.params, &mut ws.sim, &mut ws.response)?;
        self.fill_residuals(&ws.response, r);
        Ok(())
    }

    fn residuals_jacobian(
        &self,
        ws: &mut OutputErrorWorkspace,
        u: &[f64],
        r: &mut [f64],
        jac: &mut DMatrix<f64>,
    ) -> Result<(), SimulationError> {
        self.all_params(u, &mut ws.params);
        self.sim.run_with_sensitivities(
            &ws.params,
            &self.wrt,
            &mut ws.sim,
            &mut ws.response,
            &mut ws.sens,
        )?;
        self.fill_residuals(&ws.response, r);
        for ((d, m), &u) in ws.dx_du.iter_mut().zip(&self.maps).zip(u) {
            *d = m.derivative(u);
        }
        let n = ws.response.n_samples;
        let used = n - self.first;
        let p = self.wrt.len();
        for c in 0..ws.response.n_sensors {
            let w = self.sqrt_weights[c];
            for k in self.first..n {
                let row = c * used + (k - self.first);
                let src = &ws.sens.values[(c * n + k) * p..(c * n + k + 1) * p];
                for j in 0..p {
                    jac[(row, j)] = w * src[j] * ws.dx_du[j];
                }
            }
        }
        Ok(())
    }
}
