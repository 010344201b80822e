//! MAT-files without a time axis (no `time`, `t`, `sample_rate` or `fs`
//! variable), as the Silverbox benchmark's: the samples are taken on the
//! model's grid from t = 0, with a note; a variable that looks like a time
//! axis under another name makes the instants ambiguous and is an error
//! naming the file and the variable.
mod common;
mod import_common;

use import_common::*;
use rfeid::io::data_file::{read_measurement, DataFileError};
use rfeid::io::model_file::load_model;
use rfeid::measurement::{match_data, MeasurementError};
use rfeid::model::{DataSource, Model};
use std::path::{Path, PathBuf};

/// A single oscillator sampled at 1 kHz for `samples` samples, with a
/// displacement sensor `x` and the force `signal`.
fn model_text(samples: usize, signal: &str) -> String {
    format!(
        r#"
[simulation]
duration = {}
sample_rate = 1000.0

[[body]]
name = "mass"
mass = 2.0
inertia = [0.1, 0.2, 0.3]
com = [0.0, 0.0, 0.0]

[[element]]
name = "spring"
body = "mass"
to = "ground"
at = [0.0, 0.0, 0.0]
ux = {{ k = 2.0e5, c = 40.0 }}

[[excitation]]
body = "mass"
at = [0.0, 0.0, 0.0]
direction = [1, 0, 0]
signal = {signal}

[[sensor]]
name = "x"
body = "mass"
at = [0.0, 0.0, 0.0]
direction = [1, 0, 0]
quantity = "displacement"
"#,
        samples as f64 / 1000.0
    )
}

/// A folder of its own for one test's files.
fn folder(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("rfeid-no-time-{}-{test}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("scratch dir");
    dir
}

fn load(dir: &Path, samples: usize, signal: &str) -> Model {
    let path = dir.join("model.toml");
    std::fs::write(&path, model_text(samples, signal)).expect("model write");
    load_model(&path).unwrap_or_else(|e| panic!("{e}"))
}

fn bits(v: &[f64]) -> Vec<u64> {
    v.iter().map(|x| x.to_bits()).collect()
}

#[test]
fn measured_data_without_a_time_axis_lie_on_the_models_grid_with_a_note() {
    let dir = folder("data");
    let model = load(
        &dir,
        50,
        r#"{ type = "sine", amplitude = 1.0, frequency = 30.0 }"#,
    );
    let y: Vec<f64> = (0..60).map(|k| (k as f64 * 0.3).sin()).collect();
    // Scalars (an overload flag) do not look like a time axis.
    let path = dir.join("signals.mat");
    std::fs::write(&path, mat_bytes(&[("Ovld", &[0.0]), ("y", &y)])).unwrap();
    let sources = [DataSource::Variable("y".into())];
    let read = read_measurement(&path, &model, &sources).unwrap();
    let grid: Vec<f64> = (0..60).map(|k| model.sampling.time(k)).collect();
    assert_eq!(bits(&read.series.time), bits(&grid));
    assert_eq!(bits(read.series.column("x").unwrap()), bits(&y));
    assert_eq!(read.notes.len(), 1, "{:?}", read.notes);
    let note = &read.notes[0];
    assert!(
        note.contains("signals.mat")
            && note.contains("no time axis")
            && note.contains("t = k / 1000 Hz"),
        "{note}"
    );
    // On the grid exactly, cut to the model's 50 samples with a note.
    let matched = match_data(&model, &read.series).unwrap();
    assert_eq!(bits(matched.response.sensor(0)), bits(&y[..50]));
    // Fewer samples than the model needs: the matching's error, as for a
    // record with a time axis.
    std::fs::write(&path, mat_bytes(&[("y", &y[..40])])).unwrap();
    let read = read_measurement(&path, &model, &sources).unwrap();
    let e = match_data(&model, &read.series).unwrap_err();
    assert!(
        matches!(
            e,
            MeasurementError::TooShort {
                found: 40,
                needed: 50,
                ..
            }
        ),
        "{e:?}"
    );
}

#[test]
fn a_vector_that_looks_like_a_time_axis_under_another_name_is_an_error() {
    let dir = folder("ambiguous");
    let model = load(
        &dir,
        50,
        r#"{ type = "sine", amplitude = 1.0, frequency = 30.0 }"#,
    );
    let y: Vec<f64> = (0..50).map(|k| (k as f64 * 0.3).sin()).collect();
    let ms: Vec<f64> = (0..50).map(|k| k as f64).collect();
    let path = dir.join("stamped.mat");
    std::fs::write(&path, mat_bytes(&[("y", &y), ("time_ms", &ms)])).unwrap();
    let e = read_measurement(&path, &model, &[DataSource::Variable("y".into())]).unwrap_err();
    assert!(matches!(e, DataFileError::NoTimeAxis { .. }), "{e:?}");
    let msg = e.to_string();
    assert!(
        msg.contains("stamped.mat")
            && msg.contains("variable 'time_ms' increases like a time axis")
            && msg.contains("(variables: y, time_ms)"),
        "{msg}"
    );
}

