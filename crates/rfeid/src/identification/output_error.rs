//! The output-error criterion of a model against measured signals
//! (eq. 10–16) as a [`LeastSquares`] problem in normalised coordinates,
//! for one data file or a campaign of several experiments (SPEC §5).
//!
//! Residuals are `r_eck = √(w_e w_ec) (g_eck(x) − y_eck)` for every fitted
//! experiment e, every sensor c and every sample k from the first used one,
//! so `J = Σ r²` is eq. 13 with `R⁻¹ = diag(w_e w_ec)` summed over the
//! experiments, and eq. 16 for unit weights. The residual vector stacks the
//! experiments in order, so the Jacobian is their Jacobians stacked: H₁ of
//! eq. 27–28 for the whole campaign, and eq. 29's N counts every scalar
//! observation of every experiment.
//!
//! The parameters are `x = x_min + u (x_max − x_min)` (eq. 17), or
//! `x = x_min (x_max/x_min)^u` on a log scale ([`super::box_map`]); a
//! parameter marked `per_experiment` has one decision variable per
//! experiment, named `name[experiment]`, and every other one is shared. The
//! Jacobian comes from the forward sensitivities ([`crate::simulation::run`])
//! times `dx/du`.
//!
//! The experiments are simulated in parallel (rayon), each into its own
//! rows, so the residuals do not depend on the number of threads. A data file
//! on its own is a campaign of one experiment.
use super::box_map::BoxMap;
use super::problem::LeastSquares;
use crate::simulation::{Response, Sensitivities, SimulationError, Simulator, Workspace};
use nalgebra::DMatrix;
use rayon::prelude::*;

/// One experiment's data for [`OutputError::campaign`].
#[derive(Debug, Clone)]
pub struct ExperimentData<'m> {
    /// The experiment's name (used in `name[experiment]`).
    pub name: String,
    /// The simulator of the experiment's model
    /// ([`crate::model::Model::for_experiment`]); every experiment's model
    /// has the same parameters.
    pub sim: Simulator<'m>,
    /// The measured signals on the experiment's sampling and sensors.
    pub measured: Response,
    /// First sample used.
    pub first: usize,
    /// The experiment's weight w_e (> 0).
    pub weight: f64,
}

/// A decision variable: the parameter it sets and its name.
#[derive(Debug, Clone, PartialEq)]
pub struct Column {
    /// The parameter's index in the model.
    pub parameter: usize,
    /// The parameter's name, or `name[experiment]` for one that is
    /// identified per experiment.
    pub name: String,
}

#[derive(Debug, Clone)]
struct Part<'m> {
    data: ExperimentData<'m>,
    /// Sensor weights w_ec.
    sensor_weights: Vec<f64>,
    /// √(w_e w_ec) per sensor.
    sqrt_weights: Vec<f64>,
    /// The identified parameters (model indices) and their columns in u.
    wrt: Vec<usize>,
    cols: Vec<usize>,
    /// Values of all parameters; the identified ones are overwritten.
    base: Vec<f64>,
    /// The part's first residual row.
    row0: usize,
}

/// Model(s), data and weighting: the criterion J(u).
#[derive(Debug, Clone)]
pub struct OutputError<'m> {
    parts: Vec<Part<'m>>,
    columns: Vec<Column>,
    maps: Vec<BoxMap>,
    width: Vec<f64>,
    n_res: usize,
}

/// Scratch memory of one experiment's evaluation.
#[derive(Debug, Clone)]
struct PartWorkspace {
    sim: Workspace,
    response: Response,
    sens: Sensitivities,
    params: Vec<f64>,
    /// dx/du of the part's identified parameters at the current u.
    dx_du: Vec<f64>,
    /// The part's rows of the Jacobian (campaigns only).
    jac: DMatrix<f64>,
}

/// Scratch memory of one evaluation.
#[derive(Debug, Clone)]
pub struct OutputErrorWorkspace {
    parts: Vec<PartWorkspace>,
}

impl<'m> OutputError<'m> {
    /// The criterion for the model's identified parameters against one data
    /// set; `measured` must have the model's sensors and sampling
    /// ([`crate::measurement::match_data`]).
    pub fn new(sim: Simulator<'m>, measured: Response, first: usize) -> Self {
        Self::campaign(vec![ExperimentData {
            name: String::new(),
            sim,
            measured,
            first,
            weight: 1.0,
        }])
    }

    /// The criterion of a campaign: the experiments' criteria summed, with
    /// the parameters shared except those marked `per_experiment`, which get
    /// one decision variable per experiment (when there are several).
    ///
    /// # Panics
    /// If `experiments` is empty (a programmer's error).
    pub fn campaign(experiments: Vec<ExperimentData<'m>>) -> Self {
        assert!(!experiments.is_empty(), "a campaign has an experiment");
        let model = experiments[0].sim.model();
        let several = experiments.len() > 1;
        let mut columns = Vec::new();
        let mut maps = Vec::new();
        // Per identified parameter: its first column, and whether it has one per experiment.
        let mut first_col = Vec::new();
        let wrt = model.identified();
        for &i in &wrt {
            let p = &model.parameters[i];
            let (lo, hi) = p.bounds.expect("identified parameters have boxes");
            let split = several && p.per_experiment;
            first_col.push((columns.len(), split));
            let names: Vec<String> = match split {
                true => experiments
                    .iter()
                    .map(|e| format!("{}[{}]", p.name, e.name))
                    .collect(),
                false => vec![p.name.clone()],
            };
            for name in names {
                columns.push(Column { parameter: i, name });
                maps.push(BoxMap::new(lo, hi, p.scale));
            }
        }
        let mut row0 = 0;
        let parts = experiments
            .into_iter()
            .enumerate()
            .map(|(e, data)| {
                let n_sensors = data.measured.n_sensors;
                let cols = first_col
                    .iter()
                    .map(|&(c, split)| if split { c + e } else { c })
                    .collect();
                let part = Part {
                    base: data.sim.model().nominal(),
                    sensor_weights: vec![1.0; n_sensors],
                    sqrt_weights: vec![data.weight.sqrt(); n_sensors],
                    wrt: wrt.clone(),
                    cols,
                    row0,
                    data,
                };
                row0 += part.n_residuals();
                part
            })
            .collect();
        let width = maps.iter().map(BoxMap::width).collect();
        OutputError {
            parts,
            columns,
            maps,
            width,
            n_res: row0,
        }
    }

    /// Number of experiments (1 for a single data file).
    pub fn n_experiments(&self) -> usize {
        self.parts.len()
    }

    /// Experiment p's name (empty for a single data file).
    pub fn experiment_name(&self, p: usize) -> &str {
        &self.parts[p].data.name
    }

    /// Experiment p's simulator.
    pub fn experiment_simulator(&self, p: usize) -> &Simulator<'m> {
        &self.parts[p].data.sim
    }

    /// Experiment p's measured signals.
    pub fn experiment_measured(&self, p: usize) -> &Response {
        &self.parts[p].data.measured
    }

    /// Experiment p's first sample used.
    pub fn experiment_first(&self, p: usize) -> usize {
        self.parts[p].data.first
    }

    /// Experiment p's weight w_e.
    pub fn experiment_weight(&self, p: usize) -> f64 {
        self.parts[p].data.weight
    }

    /// Sets the sensor weights w_ec (eq. 13 with a diagonal R), every
    /// experiment's sensors in turn ([`OutputError::weights`]' order).
    pub fn set_weights(&mut self, weights: &[f64]) {
        let mut w = weights.iter();
        for part in &mut self.parts {
            for (sw, sq) in part.sensor_weights.iter_mut().zip(&mut part.sqrt_weights) {
                *sw = *w.next().expect("one weight per sensor");
                *sq = (part.data.weight * *sw).sqrt();
            }
        }
    }

    /// The sensor weights w_ec, every experiment's sensors in turn.
    pub fn weights(&self) -> Vec<f64> {
        self.parts
            .iter()
            .flat_map(|p| p.sensor_weights.iter().copied())
            .collect()
    }

    /// Samples used per sensor, in [`OutputError::weights`]' order.
    pub fn weight_samples(&self) -> Vec<usize> {
        self.parts
            .iter()
            .flat_map(|p| std::iter::repeat_n(p.samples_used(), p.sensor_weights.len()))
            .collect()
    }

    /// The decision variables.
    pub fn columns(&self) -> &[Column] {
        &self.columns
    }

    /// The identified parameters (model indices), one per decision variable.
    pub fn wrt(&self) -> Vec<usize> {
        self.columns.iter().map(|c| c.parameter).collect()
    }

    /// Box widths `x_max − x_min`.
    pub fn widths(&self) -> &[f64] {
        &self.width
    }

    /// The maps between the boxes and the normalised coordinate.
    pub fn maps(&self) -> &[BoxMap] {
        &self.maps
    }

    /// Physical parameter values (decision variables only) at u.
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

    /// The first experiment's simulator (the only one for a data file).
    pub fn simulator(&self) -> &Simulator<'m> {
        self.experiment_simulator(0)
    }

    /// Experiment p simulates with `steps` steps per sample from now on (the
    /// criterion changes with them: use between searches, never within one).
    pub fn set_experiment_steps(&mut self, p: usize, steps: crate::simulation::StepChoice) {
        self.parts[p].data.sim.set_steps(steps);
    }

    /// Every experiment simulates with `steps` steps per sample from now on.
    pub fn set_steps(&mut self, steps: crate::simulation::StepChoice) {
        for p in 0..self.parts.len() {
            self.set_experiment_steps(p, steps);
        }
    }

    /// The first experiment's measured signals.
    pub fn measured(&self) -> &Response {
        self.experiment_measured(0)
    }

    /// The first experiment's first sample used.
    pub fn first_sample(&self) -> usize {
        self.experiment_first(0)
    }

    /// Samples used per sensor in the first experiment.
    pub fn samples_used(&self) -> usize {
        self.parts[0].samples_used()
    }

    /// All of experiment p's parameter values at u.
    pub fn experiment_params(&self, p: usize, u: &[f64], out: &mut Vec<f64>) {
        self.parts[p].all_params(u, &self.maps, out);
    }

    /// All parameter values of the first experiment at u.
    pub fn all_params(&self, u: &[f64], out: &mut Vec<f64>) {
        self.experiment_params(0, u, out);
    }

    /// Every experiment's simulated response at u, in parallel.
    pub fn simulate_all(&self, u: &[f64]) -> Result<Vec<Response>, SimulationError> {
        (0..self.parts.len())
            .into_par_iter()
            .map(|i| self.simulate_part(i, u))
            .collect::<Vec<_>>()
            .into_iter()
            .collect()
    }

    /// The first experiment's simulated response at u.
    pub fn simulate(&self, u: &[f64]) -> Result<Response, SimulationError> {
        self.simulate_part(0, u)
    }

    /// Experiment `i`'s simulated response at u.
    fn simulate_part(&self, i: usize, u: &[f64]) -> Result<Response, SimulationError> {
        let part = &self.parts[i];
        let mut ws = part.workspace(0);
        part.all_params(u, &self.maps, &mut ws.params);
        part.data
            .sim
            .run(&ws.params, &mut ws.sim, &mut ws.response)?;
        Ok(ws.response)
    }

    /// Per-sensor sums of squared unweighted residuals of the responses `g`
    /// (one per experiment), in [`OutputError::weights`]' order.
    pub fn sensor_ssr(&self, g: &[Response]) -> Vec<f64> {
        self.parts
            .iter()
            .zip(g)
            .flat_map(|(part, g)| {
                let y = &part.data.measured;
                let first = part.data.first;
                (0..y.n_sensors).map(move |c| {
                    g.sensor(c)[first..]
                        .iter()
                        .zip(&y.sensor(c)[first..])
                        .map(|(a, b)| (a - b) * (a - b))
                        .sum()
                })
            })
            .collect()
    }

    /// Splits `r` into the experiments' rows.
    fn split_rows<'a>(&self, mut r: &'a mut [f64]) -> Vec<&'a mut [f64]> {
        let mut out = Vec::with_capacity(self.parts.len());
        for part in &self.parts {
            let (head, tail) = r.split_at_mut(part.n_residuals());
            out.push(head);
            r = tail;
        }
        out
    }
}

impl Part<'_> {
    fn samples_used(&self) -> usize {
        self.data.measured.n_samples.saturating_sub(self.data.first)
    }

    fn n_residuals(&self) -> usize {
        self.data.measured.n_sensors * self.samples_used()
    }

    fn workspace(&self, n_cols: usize) -> PartWorkspace {
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
        }
    }

    fn all_params(&self, u: &[f64], maps: &[BoxMap], out: &mut Vec<f64>) {
        out.clear();
        out.extend_from_slice(&self.base);
        for (&i, &c) in self.wrt.iter().zip(&self.cols) {
            out[i] = maps[c].to_physical(u[c]);
        }
    }

    fn fill_residuals(&self, response: &Response, r: &mut [f64]) {
        let n = response.n_samples;
        let first = self.data.first;
        let used = n - first;
        for c in 0..response.n_sensors {
            let g = &response.sensor(c)[first..];
            let y = &self.data.measured.sensor(c)[first..];
            let w = self.sqrt_weights[c];
            for ((ri, gi), yi) in r[c * used..(c + 1) * used].iter_mut().zip(g).zip(y) {
                *ri = w * (gi - yi);
            }
        }
    }

    fn residuals(
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
    fn residuals_jacobian(
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
        self.fill_residuals(&ws.response, r);
        for (d, &c) in ws.dx_du.iter_mut().zip(&self.cols) {
            *d = maps[c].derivative(u[c]);
        }
        let (jac, row0) = match jac {
            Some(j) => j,
            None => (&mut ws.jac, 0),
        };
        let n = ws.response.n_samples;
        let first = self.data.first;
        let used = n - first;
        let p = self.wrt.len();
        for c in 0..ws.response.n_sensors {
            let w = self.sqrt_weights[c];
            for k in first..n {
                let row = row0 + c * used + (k - first);
                let src = &ws.sens.values[(c * n + k) * p..(c * n + k + 1) * p];
                for j in 0..p {
                    jac[(row, self.cols[j])] = w * src[j] * ws.dx_du[j];
                }
            }
        }
        Ok(())
    }
}

/// The first failure in experiment order, so that the error does not
/// depend on which thread failed first.
fn first_error(results: Vec<Result<(), SimulationError>>) -> Result<(), SimulationError> {
    results.into_iter().collect()
}

impl LeastSquares for OutputError<'_> {
    type Workspace = OutputErrorWorkspace;
    type Error = SimulationError;

    fn n_params(&self) -> usize {
        self.columns.len()
    }

    fn n_residuals(&self) -> usize {
        self.n_res
    }

    fn workspace(&self) -> OutputErrorWorkspace {
        let n_cols = if self.parts.len() > 1 {
            self.columns.len()
        } else {
            0
        };
        OutputErrorWorkspace {
            parts: self.parts.iter().map(|p| p.workspace(n_cols)).collect(),
        }
    }

    fn residuals(
        &self,
        ws: &mut OutputErrorWorkspace,
        u: &[f64],
        r: &mut [f64],
    ) -> Result<(), SimulationError> {
        if let ([part], [pws]) = (self.parts.as_slice(), ws.parts.as_mut_slice()) {
            return part.residuals(pws, u, &self.maps, r);
        }
        let rows = self.split_rows(r);
        let results = self
            .parts
            .par_iter()
            .zip(ws.parts.par_iter_mut())
            .zip(rows)
            .map(|((part, pws), r)| part.residuals(pws, u, &self.maps, r))
            .collect();
        first_error(results)
    }

    fn residuals_jacobian(
        &self,
        ws: &mut OutputErrorWorkspace,
        u: &[f64],
        r: &mut [f64],
        jac: &mut DMatrix<f64>,
    ) -> Result<(), SimulationError> {
        if let ([part], [pws]) = (self.parts.as_slice(), ws.parts.as_mut_slice()) {
            return part.residuals_jacobian(pws, u, &self.maps, r, Some((jac, 0)));
        }
        let rows = self.split_rows(r);
        let results = self
            .parts
            .par_iter()
            .zip(ws.parts.par_iter_mut())
            .zip(rows)
            .map(|((part, pws), r)| part.residuals_jacobian(pws, u, &self.maps, r, None))
            .collect();
        first_error(results)?;
        for (part, pws) in self.parts.iter().zip(&ws.parts) {
            let rows = part.n_residuals();
            for j in 0..jac.ncols() {
                jac.view_mut((part.row0, j), (rows, 1))
                    .copy_from(&pws.jac.column(j));
            }
        }
        Ok(())
    }
}
