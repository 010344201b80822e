//! Inputs of a campaign (SPEC §5): each experiment's model and measured
//! data, with every problem naming the model file, the experiment and its
//! field.
use crate::diagnostics::Failure;
use crate::ui::Ui;
use rfeid::io::data_file::read_measurement;
use rfeid::measurement::match_data;
use rfeid::model::{Experiment, Model};
use rfeid::simulation::Response;
use std::path::Path;

/// Every experiment's model (its settings applied) and measured data.
pub fn campaign_data(
    model: &Model,
    path: &Path,
    ui: &Ui,
) -> Result<(Vec<Model>, Vec<Response>), Failure> {
    let models: Vec<Model> = (0..model.experiments.len())
        .map(|e| model.for_experiment(e))
        .collect();
    let measured = models
        .iter()
        .enumerate()
        .map(|(e, m)| experiment_data(model, path, e, m, ui))
        .collect::<Result<Vec<_>, _>>()?;
    Ok((models, measured))
}

/// Experiment e's measured data on its model `m`'s sensors and sampling;
/// every problem names the model file, the experiment and its field.
pub fn experiment_data(
    model: &Model,
    path: &Path,
    e: usize,
    m: &Model,
    ui: &Ui,
) -> Result<Response, Failure> {
    let x = &model.experiments[e];
    let field = if x.sensors.is_some() {
        "sensors"
    } else {
        "data"
    };
    let fail = |msg: String| {
        Failure::input_msg(format!(
            "{}: experiment \"{}\", field '{field}': {msg}",
            path.display(),
            x.name
        ))
    };
    check_exists(path, x)?;
    let sources: Vec<_> = m.sensors.iter().map(|s| s.data.clone()).collect();
    let read = read_measurement(&x.data, m, &sources).map_err(|err| fail(err.to_string()))?;
    let matched =
        match_data(m, &read.series).map_err(|err| fail(format!("{}: {err}", x.data.display())))?;
    for note in read.notes.iter().chain(&matched.notes) {
        ui.note(format!("note: experiment \"{}\": {note}", x.name));
    }
    Ok(matched.response)
}

/// A missing data file is bad input naming the model file (`path`), the
/// experiment and its field.
pub fn check_exists(path: &Path, x: &Experiment) -> Result<(), Failure> {
    if !x.data.is_file() {
        return Err(Failure::input_msg(format!(
            "{}: experiment \"{}\", field 'data': cannot read {}: no such file",
            path.display(),
            x.name,
            x.data.display()
        )));
    }
    Ok(())
}

/// The model as experiment `name` sees it; an unknown name is bad input
/// that lists the experiments.
pub fn experiment_model(model: &Model, path: &Path, name: &str) -> Result<Model, Failure> {
    let e = model.experiment_index(name).ok_or_else(|| {
        let known: Vec<&str> = model.experiments.iter().map(|e| e.name.as_str()).collect();
        Failure::input_msg(format!(
            "--experiment {name}: {} has no such [[experiment]] ({})",
            path.display(),
            if known.is_empty() {
                "it has none".to_string()
            } else {
                format!("experiments: {}", known.join(", "))
            }
        ))
    })?;
    Ok(model.for_experiment(e))
}
