//! Inputs of a campaign (SPEC §5) as the commands read them: the library's
//! [`read_campaign`] and [`read_experiment`], their notes shown and their
//! errors as failures, every problem naming the model file, the
//! experiment and its field.
use crate::diagnostics::Failure;
use crate::run::failures::failure;
use crate::ui::Ui;
use rfeid::identification::campaign::{
    read_campaign, read_experiment, CampaignData, CampaignError,
};
use rfeid::measurement::measured::Source;
use rfeid::model::Model;
use rfeid::simulation::Response;
use std::path::Path;

/// Every experiment's model (its settings applied) and measured data, each
/// from the data file the experiment names.
pub fn campaign_data(
    model: &Model,
    path: &Path,
    ui: &Ui,
) -> Result<(Vec<Model>, Vec<Response>), Failure> {
    let data = campaign(model, path, ui)?;
    Ok((data.models, data.measured))
}

/// [`campaign_data`] as the library returns it, with the data's sources.
pub fn campaign(model: &Model, path: &Path, ui: &Ui) -> Result<CampaignData, Failure> {
    let data =
        read_campaign(model, &path.display().to_string(), Vec::new()).map_err(campaign_failure)?;
    for note in &data.notes {
        ui.note(format!("note: {note}"));
    }
    Ok(data)
}

/// Experiment e's measured data on its model `m`'s sensors and sampling.
pub fn experiment_data(
    model: &Model,
    path: &Path,
    e: usize,
    m: &Model,
    ui: &Ui,
) -> Result<Response, Failure> {
    let source = Source::File(model.experiments[e].data.clone());
    let (measured, notes) = read_experiment(model, &path.display().to_string(), e, m, &source)
        .map_err(campaign_failure)?;
    for note in notes {
        ui.note(format!("note: {note}"));
    }
    Ok(measured)
}

/// A campaign's error as a failure ([`failure`]).
pub fn campaign_failure(e: CampaignError) -> Failure {
    failure(e)
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

/// A missing data file is bad input naming the model file (`path`), the
/// experiment and its field (before the outputs are checked, which would
/// name the file alone).
pub fn check_exists(path: &Path, x: &rfeid::model::Experiment) -> Result<(), Failure> {
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
