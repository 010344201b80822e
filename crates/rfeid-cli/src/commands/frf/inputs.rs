//! `rfeid frf`'s inputs: the model (an experiment's settings applied), the
//! parameter values (a result's estimate and covariance, or `--set`), the
//! excitations and outputs, the data sets and the frequency grid, every
//! problem bad input naming the option or file.
use crate::cli::{FrfArgs, Quantity, SpacingArg};
use crate::diagnostics::Failure;
use crate::run::belongs::check_belongs;
use crate::run::experiments::{experiment_data, experiment_model};
use crate::run::inputs::{apply_sets, fixed, load, load_data};
use crate::run::report::read_result;
use crate::ui::Ui;
use nalgebra::{DMatrix, Vector3};
use rfeid::frf::{at_estimate, default_segment, DataSet, FrfRequest, Output, Spacing};
use rfeid::model::{Model, SensorKind};
use rfeid::simulation::Response;
use std::path::PathBuf;

/// One data set read.
pub struct Data {
    label: String,
    model: Model,
    measured: Response,
    first: usize,
    /// `--force`'s samples and the excitation they measure.
    force: Option<(usize, Vec<f64>)>,
}

/// Everything the study needs.
pub struct Inputs {
    model: Model,
    params: Vec<f64>,
    wrt: Vec<usize>,
    covariance: Option<DMatrix<f64>>,
    /// Why a result gave no band.
    pub band_error: Option<String>,
    excitations: Vec<usize>,
    outputs: Vec<Output>,
    frequencies: Vec<f64>,
    data: Vec<Data>,
    segment: Option<usize>,
    files: Vec<PathBuf>,
}

impl Inputs {
    /// The files read (for the outputs' check).
    pub fn files(&self) -> Vec<PathBuf> {
        self.files.clone()
    }

    /// The library's request.
    pub fn request(&self) -> FrfRequest<'_> {
        FrfRequest {
            model: &self.model,
            params: self.params.clone(),
            wrt: self.wrt.clone(),
            covariance: self.covariance.clone(),
            excitations: self.excitations.clone(),
            outputs: self.outputs.clone(),
            frequencies: self.frequencies.clone(),
        }
    }

    /// The data sets.
    pub fn data_sets(&self) -> Vec<DataSet<'_>> {
        self.data
            .iter()
            .map(|d| DataSet {
                label: &d.label,
                model: &d.model,
                measured: &d.measured,
                first: d.first,
                segment: self.segment,
                force: d.force.as_ref().map(|(e, f)| (*e, f.as_slice())),
            })
            .collect()
    }
}

/// Reads and checks every input.
pub fn gather(args: &FrfArgs, ui: &Ui) -> Result<Inputs, Failure> {
    let mut files = Vec::new();
    let base = load(&args.model, ui)?;
    let (base, estimate) = match &args.result {
        Some(path) => {
            let result = read_result(path)?;
            let base = fixed(base, &result.source.set)?;
            check_belongs(&base, &result, &args.model, path)?;
            files.push(path.clone());
            (base, Some(result))
        }
        None => (base, None),
    };
    files.extend(base.files.iter().cloned());
    let experiment = args.experiment.clone().unwrap_or_default();
    let model = match &args.experiment {
        Some(name) => experiment_model(&base, &args.model, name)?,
        None => base.clone(),
    };
    let (mut params, wrt, covariance, band_error) = match &estimate {
        Some(r) => {
            let at = at_estimate(r, &model, &experiment).map_err(Failure::input_msg)?;
            let (cov, why) = match at.covariance {
                Ok(c) => (Some(c), None),
                Err(why) => (None, Some(why)),
            };
            (at.params, at.wrt, cov, why)
        }
        None => (model.nominal(), Vec::new(), None, None),
    };
    refuse_identified_sets(args, &model, &wrt)?;
    apply_sets(&model, &args.set, &mut params)?;
    let excitations = excitations(args, &model)?;
    let mut outputs = sensors(args, &model)?;
    for spec in &args.at {
        outputs.push(point(&model, spec, args.quantity)?);
    }
    let data = data_sets(args, &base, &model, ui)?;
    if let Some(d) = &args.data {
        files.push(d.clone());
    }
    let frequencies = grid(args, &model, &params, &data)?;
    Ok(Inputs {
        model,
        params,
        wrt,
        covariance,
        band_error,
        excitations,
        outputs,
        frequencies,
        data,
        segment: args.segment,
        files,
    })
}

/// With a result, `--set` may not name a parameter it identified (its
/// value is the estimate, and the band is about it).
fn refuse_identified_sets(args: &FrfArgs, model: &Model, wrt: &[usize]) -> Result<(), Failure> {
    for s in &args.set {
        let name = s.split('=').next().unwrap_or("").trim();
        if model
            .parameter_index(name)
            .is_some_and(|i| wrt.contains(&i))
        {
            return Err(Failure::input_msg(format!(
                "--set {s}: '{name}' was identified in {}; the FRF is at its estimate (drop --result to set it)",
                args.result.as_ref().map_or(String::new(), |p| p.display().to_string())
            )));
        }
    }
    Ok(())
}

/// The excitations asked for: `--excitation`, else all.
fn excitations(args: &FrfArgs, model: &Model) -> Result<Vec<usize>, Failure> {
    let names: Vec<&str> = model.excitations.iter().map(|e| e.name.as_str()).collect();
    if names.is_empty() {
        return Err(Failure::input_msg(format!(
            "{}: the model has no [[excitation]]: an FRF is a response per newton of one",
            args.model.display()
        )));
    }
    match &args.excitation {
        None => Ok((0..names.len()).collect()),
        Some(n) => names
            .iter()
            .position(|x| x == n)
            .map(|e| vec![e])
            .ok_or_else(|| {
                Failure::input_msg(format!(
                    "--excitation {n}: {} has no such excitation (it has: {})",
                    args.model.display(),
                    names.join(", ")
                ))
            }),
    }
}

/// The sensors asked for: `--sensor`, else all.
fn sensors(args: &FrfArgs, model: &Model) -> Result<Vec<Output>, Failure> {
    let all = Output::sensors(model);
    if args.sensor.is_empty() {
        return Ok(all);
    }
    args.sensor
        .iter()
        .map(|n| {
            all.iter().find(|o| &o.name == n).cloned().ok_or_else(|| {
                let names: Vec<&str> = all.iter().map(|o| o.name.as_str()).collect();
                Failure::input_msg(format!(
                    "--sensor {n}: {} has no such sensor (it has: {})",
                    args.model.display(),
                    names.join(", ")
                ))
            })
        })
        .collect()
}

/// A `--at NAME=BODY@X,Y,Z/DX,DY,DZ` point.
fn point(model: &Model, spec: &str, q: Quantity) -> Result<Output, Failure> {
    let bad = |why: &str| {
        Failure::input_msg(format!(
            "--at {spec}: {why} (expected NAME=BODY@X,Y,Z/DX,DY,DZ, e.g. tool=knee@0.1,0.9,0.8/0,0,1)"
        ))
    };
    let (name, rest) = spec.split_once('=').ok_or_else(|| bad("no '='"))?;
    let (body, rest) = rest
        .split_once('@')
        .ok_or_else(|| bad("no '@' after the body"))?;
    let (at, dir) = rest
        .split_once('/')
        .ok_or_else(|| bad("no '/' before the direction"))?;
    let (name, body) = (name.trim(), body.trim());
    if name.is_empty() {
        return Err(bad("the name is empty"));
    }
    let b = model
        .bodies
        .iter()
        .position(|x| x.name == body)
        .ok_or_else(|| {
            let known: Vec<&str> = model.bodies.iter().map(|x| x.name.as_str()).collect();
            bad(&format!("no body '{body}' (bodies: {})", known.join(", ")))
        })?;
    let vector = |text: &str, what: &str| -> Result<Vector3<f64>, Failure> {
        let v: Vec<f64> = text
            .split(',')
            .map(|x| x.trim().parse::<f64>())
            .collect::<Result<_, _>>()
            .map_err(|_| bad(&format!("the {what} must be three numbers")))?;
        match v.as_slice() {
            [x, y, z] if v.iter().all(|c| c.is_finite()) => Ok(Vector3::new(*x, *y, *z)),
            _ => Err(bad(&format!("the {what} must be three finite numbers"))),
        }
    };
    let (at, dir) = (vector(at, "point")?, vector(dir, "direction")?);
    if dir.norm() == 0.0 {
        return Err(bad("the direction is zero"));
    }
    let kind = match q {
        Quantity::Displacement => SensorKind::Displacement,
        Quantity::Velocity => SensorKind::Velocity,
        Quantity::Acceleration => SensorKind::Acceleration,
    };
    Ok(Output::point(model, name, b, at, dir, kind))
}

/// The data sets: `--data`, else `--experiment`'s, else a campaign's every
/// experiment's, else none.
fn data_sets(args: &FrfArgs, base: &Model, model: &Model, ui: &Ui) -> Result<Vec<Data>, Failure> {
    let first = |m: &Model, from: f64| -> Result<usize, Failure> {
        let from = args.from.unwrap_or(from);
        if !(from >= 0.0 && from.is_finite()) {
            return Err(Failure::input_msg(format!(
                "--from {from}: must be a time ≥ 0 in seconds"
            )));
        }
        Ok(m.sampling.first_sample(from))
    };
    let experiment = |e: usize| -> Result<Data, Failure> {
        let m = base.for_experiment(e);
        let measured = experiment_data(base, &args.model, e, &m, ui)?;
        let first = first(&m, base.experiments[e].from)?;
        let label = base.experiments[e].name.clone();
        Ok(Data {
            label,
            model: m,
            measured,
            first,
            force: None,
        })
    };
    match (&args.data, &args.experiment) {
        (Some(path), _) => {
            let (measured, force) = match &args.force {
                Some(column) => {
                    let e = forced_excitation(args, model)?;
                    let (m, f) = load_with_force(path, model, column, ui)?;
                    (m, Some((e, f)))
                }
                None => (load_data(path, model, ui)?, None),
            };
            let first = first(model, 0.0)?;
            let label = "measured".to_owned();
            Ok(vec![Data {
                label,
                model: model.clone(),
                measured,
                first,
                force,
            }])
        }
        (None, Some(name)) => {
            let e = base
                .experiment_index(name)
                .expect("experiment_model checked the name");
            Ok(vec![experiment(e)?])
        }
        (None, None) => (0..base.experiments.len()).map(experiment).collect(),
    }
}

/// The excitation `--force` measures: `--excitation`'s, or the only one.
fn forced_excitation(args: &FrfArgs, model: &Model) -> Result<usize, Failure> {
    match (&args.excitation, model.excitations.len()) {
        (Some(n), _) => Ok(model.excitations.iter().position(|x| &x.name == n).unwrap_or(0)),
        (None, 1) => Ok(0),
        (None, k) => Err(Failure::input_msg(format!(
            "--force: the model has {k} excitations; name the one the force measures with --excitation"
        ))),
    }
}

/// The sensors' data and `--force`'s column from `path`, bad input naming
/// the file.
fn load_with_force(
    path: &std::path::Path,
    model: &Model,
    column: &str,
    ui: &Ui,
) -> Result<(Response, Vec<f64>), Failure> {
    let source = rfeid::model::DataSource::Column(column.to_owned());
    let (m, force) = rfeid::measurement::measured::measured_with_force(path, model, &source)
        .map_err(|e| Failure::input_msg(format!("--force {column}: {e}")))?;
    for note in m.notes {
        ui.note(format!("note: {note}"));
    }
    Ok((m.response, force))
}

/// The frequencies: Welch's grid of the one data set, else the model's
/// grid ([`rfeid::frf::grid`]).
fn grid(args: &FrfArgs, model: &Model, params: &[f64], data: &[Data]) -> Result<Vec<f64>, Failure> {
    let bad = |flag: &str, v: f64, why: &str| Failure::input_msg(format!("{flag} {v}: {why}"));
    let fmax = args.fmax.unwrap_or(model.sampling.sample_rate / 2.0);
    if !(fmax > 0.0 && fmax.is_finite()) {
        return Err(bad("--fmax", fmax, "must be a positive frequency in Hz"));
    }
    if let Some(n) = args.points.filter(|n| !(2..=100_000).contains(n)) {
        return Err(Failure::input_msg(format!(
            "--points {n}: must be from 2 to 100 000"
        )));
    }
    if let Some(f) = args.fmin.filter(|f| !(*f >= 0.0 && *f < fmax)) {
        return Err(bad(
            "--fmin",
            f,
            &format!("must be from 0 to below fmax ({fmax} Hz)"),
        ));
    }
    if args.spacing == SpacingArg::Log && args.fmin == Some(0.0) {
        return Err(bad(
            "--fmin",
            0.0,
            "a log grid starts above 0 Hz (or use --spacing linear)",
        ));
    }
    if let [d] = data {
        return welch_grid(args, d, fmax);
    }
    let spacing = match args.spacing {
        SpacingArg::Log => Spacing::Log,
        SpacingArg::Linear => Spacing::Linear,
    };
    Ok(rfeid::frf::grid(
        model,
        params,
        args.fmin,
        Some(fmax),
        args.points,
        spacing,
    ))
}

/// Welch's frequencies of data set `d` from `--fmin` to `fmax`.
fn welch_grid(args: &FrfArgs, d: &Data, fmax: f64) -> Result<Vec<f64>, Failure> {
    let n = d.measured.n_samples - d.first.min(d.measured.n_samples);
    let m = args.segment.unwrap_or_else(|| default_segment(n));
    if !m.is_power_of_two() || m < 8 || m > n {
        return Err(Failure::input_msg(format!(
            "--segment {m}: must be a power of two from 8 to the record's {n} samples"
        )));
    }
    let df = d.model.sampling.sample_rate / m as f64;
    let fmin = args.fmin.unwrap_or(0.0);
    let welch: Vec<f64> = (1..=m / 2)
        .map(|k| k as f64 * df)
        .filter(|f| *f >= fmin && *f <= fmax)
        .collect();
    match welch.is_empty() {
        true => Err(Failure::input_msg(format!(
            "--fmin/--fmax: no frequency of the data's grid (steps of {df} Hz) lies between them"
        ))),
        false => Ok(welch),
    }
}
