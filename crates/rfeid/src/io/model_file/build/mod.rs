//! From the raw file to a validated [`Model`], one section of the file after
//! another.
mod bodies;
mod component;
mod ctx;
mod elements;
mod excitations;
mod experiments;
mod parameters;
mod rules;
mod sensors;
mod signal;
mod simulation;
mod table;

use crate::io::model_file::raw::*;
use crate::model::*;
use crate::units::Dimension;
use bodies::bodies;
use ctx::*;
use elements::elements;
use excitations::excitations;
use nalgebra::Vector3;
use parameters::{finish_parameters, read_parameters};
use sensors::sensors;
use simulation::sampling;
use std::collections::HashMap;
use std::path::Path;
use std::sync::Arc;

/// Reads and checks a model file's text, section by section, for
/// `purpose` (whether a placed sensor is needed).
pub(super) fn build(text: &str, path: &Path, purpose: super::Purpose) -> Result<Model> {
    let mut ctx = new_ctx(text, path);
    let raw: RawFile = toml::from_str(text).map_err(|e| toml_error(&ctx, text, &e))?;
    // Parameters first, so that fields can name them.
    read_parameters(&mut ctx, &raw)?;
    let bodies = bodies(&mut ctx, &raw)?;
    let elements = elements(&mut ctx, &raw, &bodies)?;
    let excitations = excitations(&mut ctx, &raw, &bodies)?;
    let (sensors, candidates) = sensors(&mut ctx, &raw, &bodies, purpose)?;
    let sampling = sampling(&ctx, &raw)?;
    let gravity = gravity(&ctx, &raw)?;
    let parameters = finish_parameters(&ctx)?;
    let experiments = experiments::experiments(
        &ctx,
        &raw,
        &parameters,
        &excitations,
        (&sensors, &candidates),
        &sampling,
    )?;
    Ok(Model {
        experiments,
        bodies: bodies.list,
        elements,
        parameters,
        excitations,
        sensors,
        candidates,
        sampling,
        gravity,
        files: ctx.files.take(),
        notes: ctx.notes.take(),
    })
}

/// An empty context for the model file at `path`.
fn new_ctx(text: &str, path: &Path) -> Ctx {
    Ctx {
        path: path.into(),
        dir: path.parent().map(Path::to_path_buf).unwrap_or_default(),
        text: Arc::from(text),
        params: Vec::new(),
        param_index: HashMap::new(),
        files: Default::default(),
        notes: Default::default(),
    }
}

/// The optional `gravity` vector, an acceleration.
fn gravity(ctx: &Ctx, raw: &RawFile) -> Result<Option<Vector3<f64>>> {
    match &raw.gravity {
        None => Ok(None),
        Some(g) => Ok(Some(ctx.vec3(
            g,
            Dimension::LENGTH.div(Dimension::TIME.powf(2.0)),
            "gravity",
            "gravity",
        )?)),
    }
}
