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
use super::blocked_qr::{jacobian_bytes, BlockedQr};
use super::box_map::BoxMap;
use super::cancel::Cancel;
use super::noise::ar::Whitener;
use super::noise::SensorWeighting;
use super::problem::LeastSquares;
use super::tally::Counter;
use crate::simulation::{Response, SimulationError, Simulator};
use nalgebra::DMatrix;
use rayon::prelude::*;
use std::time::Instant;

mod count;
mod factor;
mod fit;
mod kept;
mod part;
mod steps;
mod watch;
use part::{Part, PartWorkspace};
pub use watch::Watched;

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

/// Model(s), data and weighting: the criterion J(u).
#[derive(Debug, Clone)]
pub struct OutputError<'m> {
    parts: Vec<Part<'m>>,
    columns: Vec<Column>,
    maps: Vec<BoxMap>,
    width: Vec<f64>,
    n_res: usize,
    /// Every simulation run through this criterion (shared by its clones).
    counter: Counter,
    /// Set to stop: every simulation after it fails with
    /// [`SimulationError::Cancelled`] (shared by its clones).
    cancel: Cancel,
    /// Bytes the whole Jacobian may take; beyond them it is taken by
    /// blocks ([`LeastSquares::jacobian_by_blocks`]).
    jacobian_memory: usize,
    /// Samples per block when the Jacobian is taken by blocks.
    block_samples: usize,
    /// The last runs with sensitivities, if kept ([`OutputError::keep_runs`]).
    kept: kept::KeptRuns,
    /// The responses of the last [`OutputError::simulate_all`].
    last_fit: fit::LastFit,
}

/// The default of [`OutputError::set_jacobian_memory`]: 256 MiB, a
/// Jacobian of 33 million entries (one of 10⁶ samples of 6 sensors and
/// 5 parameters). A search holds it two or three times over, with the
/// simulated sensitivities.
pub const DEFAULT_JACOBIAN_MEMORY: usize = 256 << 20;

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
                    .map(|e| crate::model::ColumnName::new(&p.name, &e.name).to_string())
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
                    inputs: part::excitation_samples(data.sim.model(), data.first),
                    base: data.sim.model().nominal(),
                    sensor_weights: vec![1.0; n_sensors],
                    sqrt_weights: vec![data.weight.sqrt(); n_sensors],
                    whitening: vec![Whitener::default(); n_sensors],
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
            counter: Counter::default(),
            cancel: Cancel::new(),
            jacobian_memory: DEFAULT_JACOBIAN_MEMORY,
            block_samples: factor::BLOCK_SAMPLES,
            kept: kept::KeptRuns::default(),
            last_fit: fit::LastFit::default(),
        }
    }

    /// Stops this criterion (and its clones) when `cancel` is set: each
    /// simulation asked for after that fails at once with
    /// [`SimulationError::Cancelled`].
    pub fn set_cancel(&mut self, cancel: Cancel) {
        self.cancel = cancel;
    }

    /// The criterion's cancellation flag.
    pub fn cancel(&self) -> &Cancel {
        &self.cancel
    }

    /// [`SimulationError::Cancelled`] once the criterion is cancelled.
    fn check_cancel(&self) -> Result<(), SimulationError> {
        match self.cancel.is_set() {
            true => Err(SimulationError::Cancelled),
            false => Ok(()),
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

    /// Experiment p's inputs: each excitation's force at the samples used
    /// (at the model's nominal values).
    pub fn experiment_inputs(&self, p: usize) -> &[Vec<f64>] {
        &self.parts[p].inputs
    }

    /// Experiment p's weight w_e.
    pub fn experiment_weight(&self, p: usize) -> f64 {
        self.parts[p].data.weight
    }

    /// Sets the whole weighting: each sensor's weight and whitening filter
    /// ([`OutputError::set_weights`], [`OutputError::set_whitening`]).
    pub fn set_weighting(&mut self, weighting: &SensorWeighting) {
        self.set_weights(&weighting.weights);
        self.set_whitening(&weighting.filters);
    }

    /// The whole weighting the criterion holds.
    pub fn weighting(&self) -> SensorWeighting {
        SensorWeighting {
            weights: self.weights(),
            filters: self.whitening(),
        }
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

    /// Sets each sensor's whitening filter (order 0: none), in
    /// [`OutputError::weights`]' order: the residuals and the Jacobian rows
    /// of that sensor are filtered by `A(q)` with its exact start
    /// ([`crate::identification::noise`]).
    pub fn set_whitening(&mut self, filters: &[Whitener]) {
        let mut f = filters.iter();
        for part in &mut self.parts {
            for w in &mut part.whitening {
                *w = f.next().expect("one filter per sensor").clone();
            }
        }
    }

    /// Each sensor's whitening filter, in [`OutputError::weights`]' order.
    pub fn whitening(&self) -> Vec<Whitener> {
        self.whitening_filters().cloned().collect()
    }

    /// Each sensor's whitening filter, borrowed, in
    /// [`OutputError::weights`]' order.
    pub fn whitening_filters(&self) -> impl Iterator<Item = &Whitener> + '_ {
        self.parts.iter().flat_map(|p| p.whitening.iter())
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

    /// The model whose parameters are identified (every experiment's model
    /// has the same parameters; the first experiment's).
    pub fn model(&self) -> &'m crate::model::Model {
        self.parts[0].data.sim.model()
    }

    /// All of experiment p's parameter values at u.
    pub fn experiment_params(&self, p: usize, u: &[f64], out: &mut Vec<f64>) {
        self.parts[p].all_params(u, &self.maps, out);
    }

    /// Per-sensor sums of squared unweighted residuals of the responses `g`
    /// (one per experiment), in [`OutputError::weights`]' order.
    pub fn sensor_ssr(&self, g: &[Response]) -> Vec<f64> {
        self.sensor_residuals(g)
            .iter()
            .map(|e| e.iter().map(|v| v * v).sum())
            .collect()
    }

    /// Each sensor's unweighted, unfiltered residuals `g − y` of the
    /// responses `g` (one per experiment) from the first sample used, in
    /// [`OutputError::weights`]' order.
    pub fn sensor_residuals(&self, g: &[Response]) -> Vec<Vec<f64>> {
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
                        .map(|(a, b)| a - b)
                        .collect()
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

impl OutputError<'_> {
    /// Evaluates every experiment's part into its own rows of `r` (in
    /// parallel when there are several; `jac` goes to a lone part, which
    /// writes its Jacobian there directly), counts the simulations (with
    /// sensitivities or not), and returns the first failure in experiment
    /// order.
    fn each_part(
        &self,
        ws: &mut OutputErrorWorkspace,
        r: &mut [f64],
        jac: Option<&mut DMatrix<f64>>,
        sensitivities: bool,
        eval: impl Fn(
                &Part<'_>,
                &mut PartWorkspace,
                &mut [f64],
                Option<&mut DMatrix<f64>>,
            ) -> Result<(), SimulationError>
            + Sync,
    ) -> Result<(), SimulationError> {
        self.check_cancel()?;
        let since = Instant::now();
        if let ([part], [pws]) = (self.parts.as_slice(), ws.parts.as_mut_slice()) {
            let result = eval(part, pws, r, jac);
            self.count(std::slice::from_ref(&result), sensitivities, since);
            return result;
        }
        let rows = self.split_rows(r);
        let results: Vec<_> = self
            .parts
            .par_iter()
            .zip(ws.parts.par_iter_mut())
            .zip(rows)
            .map(|((part, pws), r)| eval(part, pws, r, None))
            .collect();
        self.count(&results, sensitivities, since);
        first_error(results)
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
        let n_cols = if self.parts.len() > 1 && !self.jacobian_by_blocks() {
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
        self.check_cancel()?;
        if self.residuals_kept(ws, u, r) {
            return Ok(());
        }
        self.each_part(ws, r, None, false, |part, pws, r, _| {
            part.residuals(pws, u, &self.maps, r)
        })
    }

    fn residuals_jacobian(
        &self,
        ws: &mut OutputErrorWorkspace,
        u: &[f64],
        r: &mut [f64],
        jac: &mut DMatrix<f64>,
    ) -> Result<(), SimulationError> {
        self.check_cancel()?;
        if self.linearise_kept(ws, u, r, jac) {
            return Ok(());
        }
        self.forget_kept();
        if self.parts.len() == 1 {
            self.each_part(ws, r, Some(jac), true, |part, pws, r, jac| {
                part.residuals_jacobian(pws, u, &self.maps, r, jac.map(|j| (j, 0)))
            })?;
            self.keep(&mut ws.parts);
            return Ok(());
        }
        self.each_part(ws, r, None, true, |part, pws, r, _| {
            part.residuals_jacobian(pws, u, &self.maps, r, None)
        })?;
        self.keep(&mut ws.parts);
        self.gather_jacobian(ws, jac);
        Ok(())
    }

    fn jacobian_by_blocks(&self) -> bool {
        jacobian_bytes(self.n_res, self.columns.len()) > self.jacobian_memory
    }

    /// The experiments one after the other, each simulated by blocks
    /// (`factor`) with its columns in parallel groups.
    fn residuals_factor(
        &self,
        ws: &mut OutputErrorWorkspace,
        u: &[f64],
        r: &mut [f64],
        qr: &mut BlockedQr,
    ) -> Result<(), SimulationError> {
        self.check_cancel()?;
        match qr.n_cols() == self.columns.len() {
            true => qr.clear(),
            false => *qr = BlockedQr::new(self.columns.len()),
        }
        let rows = self.split_rows(r);
        for ((part, pws), r) in self.parts.iter().zip(&mut ws.parts).zip(rows) {
            let since = Instant::now();
            let result = part.residuals_factor(
                pws,
                (u, &self.maps),
                r,
                qr,
                (self.block_samples, &self.cancel),
            );
            self.count(std::slice::from_ref(&result), true, since);
            result?;
        }
        Ok(())
    }
}
