//! The Fisher information of each sensor (SPEC §6): one simulation with
//! exact sensitivities per experiment gives it for every placed and
//! candidate sensor at once, since a sensor's readings depend on the
//! parameters only through the motion that every sensor shares.
//!
//! With each sensor's noise σ_c known, the rows of the Jacobian H₁ of
//! eq. 27–28 divided by σ_c give `F = H₁ᵀH₁` such that eq. 26 with s² = 1 is
//! the Cramér–Rao bound. F is a sum over sensors (and over a campaign's
//! fitted experiments), so each sensor's share `F_c = Σ_k h_ckᵀh_ck / σ_c²`
//! is computed once and any set of sensors is a sum of shares.
//!
//! The shares are held in units of a common noise variance σ₀² (the
//! geometric mean of the sensors' σ², [`FisherParts::noise_scale`]):
//! `F·σ₀² = Σ_c h_cᵀh_c (σ₀/σ_c)²`. Only the ratios of the sensors' noise
//! then enter the sums, so a noise of 10⁻¹⁵⁰ or 10¹⁵⁰ (in any unit) neither
//! underflows nor overflows, and scaling every σ by a factor scales every
//! predicted standard error by it exactly.
use super::basis::{layout, member_shares, Layout};
use super::DesignError;
use crate::identification::output_error::{ExperimentData, OutputError};
use crate::identification::problem::LeastSquares;
use crate::model::{Model, Sensor};
use crate::simulation::Simulator;
use nalgebra::DMatrix;

/// One fitted experiment's information: each placed sensor's and each
/// candidate's share, in relative parameters.
#[derive(Debug, Clone)]
pub struct ExperimentFisher {
    /// The experiment's name (`""` for a model without experiments).
    pub name: String,
    /// The placed sensors' shares summed.
    pub placed: DMatrix<f64>,
    /// Each candidate's share, in the model's candidate order.
    pub candidates: Vec<DMatrix<f64>>,
    /// Samples used per sensor.
    pub samples: usize,
    /// Placed sensors measured in it.
    pub placed_sensors: usize,
}

/// The pieces a design is summed from, at one parameter point.
#[derive(Debug, Clone)]
pub struct FisherParts {
    /// The decision variables' names (`name[experiment]` for a parameter
    /// identified per experiment), as `identify` names them.
    pub columns: Vec<String>,
    /// Their values x_j at this point, SI.
    pub values: Vec<f64>,
    /// The relative coordinate's scale s_j: the Fisher matrices are in
    /// `x_j / s_j`, with s_j = x_j (or the box width where x_j = 0).
    pub scale: Vec<f64>,
    /// Their boxes' widths `x_max − x_min`.
    pub widths: Vec<f64>,
    /// σ₀, the common noise scale: every Fisher matrix here is `F·σ₀²`
    /// (the module's note), so `log det F = log det(F·σ₀²) − r ln σ₀²` and
    /// the covariance is `σ₀² (F·σ₀²)⁻¹`.
    pub noise_scale: f64,
    /// Each fitted experiment's shares.
    pub experiments: Vec<ExperimentFisher>,
}

impl FisherParts {
    /// The placed sensors' information, all experiments.
    pub fn placed(&self) -> DMatrix<f64> {
        let r = self.columns.len();
        self.experiments
            .iter()
            .fold(DMatrix::zeros(r, r), |f, e| f + &e.placed)
    }

    /// Candidate i's information, all experiments.
    pub fn candidate(&self, i: usize) -> DMatrix<f64> {
        let r = self.columns.len();
        self.experiments
            .iter()
            .fold(DMatrix::zeros(r, r), |f, e| f + &e.candidates[i])
    }

    /// `log det F − log det(F·σ₀²) = −r ln σ₀²`: what turns the log det
    /// of a matrix here into the log det of the information itself.
    pub fn log_det_shift(&self) -> f64 {
        -(self.columns.len() as f64) * self.noise_scale.powi(2).ln()
    }

    /// Every candidate's information, all experiments.
    pub fn candidates(&self) -> Vec<DMatrix<f64>> {
        let n = self.experiments.first().map_or(0, |e| e.candidates.len());
        (0..n).map(|i| self.candidate(i)).collect()
    }

    /// The observations of the placed sensors and of `extra` added
    /// candidates: samples × sensors summed over the experiments.
    pub fn observations(&self, extra: usize) -> usize {
        self.experiments
            .iter()
            .map(|e| e.samples * (e.placed_sensors + extra))
            .sum()
    }
}

/// The noise σ of `s`, or the error naming it.
fn noise_of(s: &Sensor, candidate: bool) -> Result<f64, DesignError> {
    s.noise.ok_or_else(|| DesignError::NoNoise {
        sensor: s.name.clone(),
        candidate,
        unit: s.kind.unit().to_string(),
    })
}

/// σ₀ ([`FisherParts::noise_scale`]) and the weight of each sensor of
/// `models` (each experiment's placed sensors, then its `n_extra` read
/// for the candidates, the first `n_direct` of them candidates themselves).
fn noise_weights(
    model: &Model,
    models: &[(String, Model, usize)],
    n_extra: usize,
    n_direct: usize,
) -> Result<(f64, Vec<f64>), DesignError> {
    // σ₀ from the placed sensors (each experiment's) and the candidates;
    // placed sensors and direct candidates weighted by (σ₀/σ)², a basis
    // (unit noise, read by its members) by 1 and its members by (σ₀/σ)²
    // in `member_shares`.
    let mut sigmas = Vec::new();
    for (_, m, _) in models {
        for s in &m.sensors[..m.sensors.len() - n_extra] {
            sigmas.push(noise_of(s, false)?);
        }
    }
    sigmas.extend(model.candidates.iter().filter_map(|c| c.noise));
    let noise_scale = common_scale(&sigmas);
    let mut weights = Vec::new();
    for (_, m, _) in models {
        let weighted = m.sensors.len() - n_extra + n_direct;
        for (c, s) in m.sensors.iter().enumerate() {
            let sigma = noise_of(s, c >= weighted)?;
            weights.push(if c < weighted {
                (noise_scale / sigma).powi(2)
            } else {
                1.0
            });
        }
    }
    Ok((noise_scale, weights))
}

/// σ₀: the geometric mean of the noises `sigmas` (each positive, with σ²
/// and 1/σ² finite, as the model file's rule has them), 1 if there are
/// none.
fn common_scale(sigmas: &[f64]) -> f64 {
    match sigmas.len() {
        0 => 1.0,
        n => (sigmas.iter().map(|s| s.ln()).sum::<f64>() / n as f64).exp(),
    }
}

/// The model as each fitted experiment sees it (the model itself without
/// experiments), with the sensors that read the candidates (`extra`)
/// appended to its sensors and the identified parameters at `x` (all of
/// the model's values, SI).
fn experiment_models(model: &Model, x: &[f64], extra: &[Sensor]) -> Vec<(String, Model, usize)> {
    let fitted = model.fitted_experiments();
    let seen: Vec<(String, Model, f64)> = if model.experiments.is_empty() {
        vec![(String::new(), model.clone(), 0.0)]
    } else {
        fitted
            .iter()
            .map(|&e| {
                let x_e = &model.experiments[e];
                (x_e.name.clone(), model.for_experiment(e), x_e.from)
            })
            .collect()
    };
    seen.into_iter()
        .map(|(name, mut m, from)| {
            for i in model.identified() {
                m.parameters[i].value = x[i];
            }
            let first = m.sampling.first_sample(from);
            m.sensors.extend(extra.iter().cloned());
            (name, m, first)
        })
        .collect()
}

/// Every sensor's share of the Fisher information at the model's values
/// `x` (all parameters, SI), each fitted experiment simulated once with
/// sensitivities (steps chosen there for the model's tolerance); many
/// candidates on one body are read through its basis ([`super::basis`]).
/// Every placed sensor and candidate needs its `noise`.
pub fn fisher_parts(model: &Model, x: &[f64]) -> Result<FisherParts, DesignError> {
    fisher_parts_with(model, x, true)
}

/// [`fisher_parts`], with `basis = false` simulating every candidate as a
/// sensor of its own (the reference the basis is tested against).
pub fn fisher_parts_with(
    model: &Model,
    x: &[f64],
    basis: bool,
) -> Result<FisherParts, DesignError> {
    for s in &model.candidates {
        noise_of(s, true)?;
    }
    let layout = layout(model, basis);
    let extra = layout.sensors(model);
    let models = experiment_models(model, x, &extra);
    if models.is_empty() {
        return Err(DesignError::NoFittedExperiment);
    }
    let (noise_scale, weights) = noise_weights(model, &models, extra.len(), layout.direct.len())?;
    let parts = models
        .iter()
        .map(|(name, m, first)| {
            let sim = Simulator::choose(m, &m.nominal()).map_err(DesignError::Simulation)?;
            let measured = sim.response_buffer();
            if *first + 2 > measured.n_samples {
                return Err(DesignError::TooShort {
                    experiment: name.clone(),
                });
            }
            Ok(ExperimentData {
                name: name.clone(),
                sim,
                measured,
                first: *first,
                weight: 1.0,
            })
        })
        .collect::<Result<Vec<_>, _>>()?;
    let mut problem = OutputError::campaign(parts);
    problem.set_weights(&weights);
    let columns: Vec<String> = problem.columns().iter().map(|c| c.name.clone()).collect();
    if columns.is_empty() {
        return Err(DesignError::NoParameters);
    }
    let values: Vec<f64> = problem.columns().iter().map(|c| x[c.parameter]).collect();
    let u = problem.to_normalised(&values);
    let (n, r) = (problem.n_residuals(), columns.len());
    let mut jac = DMatrix::zeros(n, r);
    let mut res = vec![0.0; n];
    problem
        .residuals_jacobian(&mut problem.workspace(), &u, &mut res, &mut jac)
        .map_err(DesignError::Simulation)?;
    let widths = problem.widths().to_vec();
    let scale: Vec<f64> = values
        .iter()
        .zip(&widths)
        .map(|(&v, &w)| if v != 0.0 { v.abs() } else { w })
        .collect();
    // ∂g/∂(x_j/s_j) = s_j ∂g/∂x_j = s_j (∂g/∂u_j) / (dx_j/du_j).
    for (j, d) in problem.dx_du(&u).iter().enumerate() {
        let f = scale[j] / d;
        jac.column_mut(j).iter_mut().for_each(|v| *v *= f);
    }
    let experiments = shares(model, &problem, &jac, &layout, extra.len(), noise_scale);
    Ok(FisherParts {
        columns,
        values,
        scale,
        widths,
        noise_scale,
        experiments,
    })
}

/// Each experiment's sensor shares `BᵀB` of the Jacobian's row blocks
/// (experiment by experiment, sensor by sensor, as the criterion stacks
/// them): the placed sensors', then the `n_extra` sensors that read the
/// candidates as `layout` says.
fn shares(
    model: &Model,
    problem: &OutputError,
    jac: &DMatrix<f64>,
    layout: &Layout,
    n_extra: usize,
    noise_scale: f64,
) -> Vec<ExperimentFisher> {
    let r = jac.ncols();
    let mut row = 0;
    (0..problem.n_experiments())
        .map(|p| {
            let measured = problem.experiment_measured(p);
            let used = measured.n_samples - problem.experiment_first(p);
            let n_placed = measured.n_sensors - n_extra;
            let block = |row: &mut usize| {
                let b = jac.rows(*row, used);
                *row += used;
                b
            };
            let mut placed = DMatrix::zeros(r, r);
            for _ in 0..n_placed {
                let b = block(&mut row);
                placed += b.transpose() * b;
            }
            let mut candidates = vec![DMatrix::zeros(r, r); model.candidates.len()];
            for &i in &layout.direct {
                let b = block(&mut row);
                candidates[i] = b.transpose() * b;
            }
            for g in &layout.groups {
                let blocks: Vec<_> = (0..6).map(|_| block(&mut row)).collect();
                for (i, f) in member_shares(model, g, &blocks, noise_scale) {
                    candidates[i] = f;
                }
            }
            ExperimentFisher {
                name: problem.experiment_name(p).to_string(),
                placed,
                candidates,
                samples: used,
                placed_sensors: n_placed,
            }
        })
        .collect()
}
