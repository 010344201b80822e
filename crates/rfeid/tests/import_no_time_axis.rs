//! MAT-files without a time axis (no `time`, `t`, `sample_rate` or `fs`
//! variable), as the Silverbox benchmark's: the samples are taken on the
//! model's grid from t = 0, with a note, for measured data and for `table`
//! excitation signals alike; a variable that looks like a time axis under
//! another name makes the instants ambiguous and is an error naming the file
//! and the variable.
use crate::common;
use crate::import_common;

use import_common::*;
use rfeid::io::data_file::{read_measurement, DataFileError};
use rfeid::io::model_file::load_model;
use rfeid::measurement::{match_data, MeasurementError};
use rfeid::model::{DataSource, Model};
use std::path::{Path, PathBuf};

/// A single oscillator sampled at 1 kHz for `samples` samples, with a
/// displacement sensor `x` and a `table` force from `signal`.
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

/// A force that starts and ends at 0: n samples of a windowed sine.
fn force(n: usize) -> Vec<f64> {
    (0..n)
        .map(|k| {
            let s = k as f64 / (n - 1) as f64;
            100.0 * (std::f64::consts::PI * s).sin() * (40.0 * s).sin()
        })
        .collect()
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

#[test]
fn a_table_reads_a_mat_variable_like_the_same_csv_column() {
    let dir = folder("table");
    let n = 200;
    let f = force(n);
    let mut csv = String::from("time,push\n");
    for (k, v) in f.iter().enumerate() {
        csv += &format!("{:?},{v:?}\n", k as f64 / 1000.0);
    }
    std::fs::write(dir.join("force.csv"), csv).unwrap();
    let from_csv = load(
        &dir,
        n,
        r#"{ type = "table", file = "force.csv", column = "push", amplitude = 2.0 }"#,
    );
    // Without a time axis: on the model's grid, with a note naming the file.
    std::fs::write(dir.join("force.mat"), mat_bytes(&[("push", &f)])).unwrap();
    let signal = r#"{ type = "table", file = "force.mat", variable = "push", amplitude = 2.0 }"#;
    let from_mat = load(&dir, n, signal);
    assert_eq!(from_mat.notes.len(), 1, "{:?}", from_mat.notes);
    assert!(
        from_mat.notes[0].contains("force.mat") && from_mat.notes[0].contains("no time axis"),
        "{:?}",
        from_mat.notes
    );
    assert!(from_csv.notes.is_empty());
    assert_eq!(from_mat.files, vec![dir.join("force.mat")]);
    let a = common::simulate_nominal(&from_csv, None);
    let b = common::simulate_nominal(&from_mat, None);
    assert_eq!(bits(a.sensor(0)), bits(b.sensor(0)));
    // With a time vector: that axis, and no note.
    let t: Vec<f64> = (0..n).map(|k| k as f64 / 1000.0).collect();
    std::fs::write(dir.join("force.mat"), mat_bytes(&[("t", &t), ("push", &f)])).unwrap();
    let timed = load(&dir, n, signal);
    assert!(timed.notes.is_empty(), "{:?}", timed.notes);
    let c = common::simulate_nominal(&timed, None);
    assert_eq!(bits(a.sensor(0)), bits(c.sensor(0)));
}

/// Loads a model whose table reads `force.mat` with `signal`, expecting an
/// error; returns its message.
fn table_error(dir: &Path, signal: &str) -> String {
    let path = dir.join("model.toml");
    std::fs::write(&path, model_text(200, signal)).unwrap();
    load_model(&path).unwrap_err().to_string()
}

#[test]
fn table_errors_name_the_file_and_the_variable() {
    let dir = folder("table-errors");
    let f = force(200);
    let ms: Vec<f64> = (0..200).map(|k| k as f64).collect();
    std::fs::write(dir.join("force.mat"), mat_bytes(&[("push", &f)])).unwrap();
    // A variable the file does not hold: the field, the file and the variables.
    let msg = table_error(
        &dir,
        r#"{ type = "table", file = "force.mat", variable = "pull" }"#,
    );
    assert!(
        msg.contains("signal.variable")
            && msg.contains("force.mat")
            && msg.contains("no variable 'pull' (variables: push)"),
        "{msg}"
    );
    // `column` names a CSV column, not a MAT-file's variable.
    let msg = table_error(
        &dir,
        r#"{ type = "table", file = "force.mat", column = "push" }"#,
    );
    assert!(
        msg.contains("signal.column") && msg.contains("write variable = \"…\""),
        "{msg}"
    );
    // A NaN sample.
    let mut bad = f.clone();
    bad[7] = f64::NAN;
    std::fs::write(dir.join("force.mat"), mat_bytes(&[("push", &bad)])).unwrap();
    let msg = table_error(
        &dir,
        r#"{ type = "table", file = "force.mat", variable = "push" }"#,
    );
    assert!(
        msg.contains("force.mat: variable 'push', sample 7 is NaN, not a finite number"),
        "{msg}"
    );
    // A time axis under another name: ambiguous.
    std::fs::write(
        dir.join("force.mat"),
        mat_bytes(&[("push", &f), ("stamp", &ms)]),
    )
    .unwrap();
    let msg = table_error(
        &dir,
        r#"{ type = "table", file = "force.mat", variable = "push" }"#,
    );
    assert!(
        msg.contains("signal.file")
            && msg.contains("force.mat")
            && msg.contains("variable 'stamp' increases like a time axis"),
        "{msg}"
    );
    // A time vector in another unit (µs read as s): the table stops inside
    // the simulated time.
    let us: Vec<f64> = ms.iter().map(|k| k * 1e-6).collect();
    std::fs::write(
        dir.join("force.mat"),
        mat_bytes(&[("push", &f), ("time", &us)]),
    )
    .unwrap();
    let msg = table_error(
        &dir,
        r#"{ type = "table", file = "force.mat", variable = "push" }"#,
    );
    assert!(
        msg.contains("force.mat: variable 'push': the table spans"),
        "{msg}"
    );
}
