//! Measured data for a model from CSV, MAT-files and universal files: the
//! sensors' sources (`data = { column | variable | record }`), the time
//! axis of each format, and the issue's acceptance: the same data read from
//! CSV, .mat or UFF gives the same identification result.
use crate::common;
use crate::import_common;

use import_common::*;
use rfeid::identification::output_error::OutputError;
use rfeid::identification::pipeline::{identify, Settings, Silent};
use rfeid::io::data_file::{read_measurement, DataFileError};
use rfeid::io::mat::MatError;
use rfeid::io::timeseries::TimeSeries;
use rfeid::io::uff::UffError;
use rfeid::measurement::match_data;
use rfeid::model::{default_sources, DataSource, Model, RecordRef};
use rfeid::simulation::Simulator;
use std::f64::consts::PI;
use std::path::Path;

/// The oscillator the fixtures' signals come from (m = 2 kg, k = 2e5 N/m,
/// c = 40 N·s/m, 100 N at 30 Hz), with k and c to identify, sensors named
/// `sensors` (displacement, velocity, acceleration along X).
fn model_named(sensors: [&str; 3]) -> Model {
    let kinds = ["displacement", "velocity", "acceleration"];
    let mut text = String::from(
        r#"
[simulation]
duration = 0.05
sample_rate = 1000.0
substeps = 20

[[body]]
name = "mass"
mass = 2.0
inertia = [0.1, 0.2, 0.3]
com = [0.0, 0.0, 0.0]

[[parameter]]
name = "k"
value = 1.6e5
min = 1.0e5
max = 3.0e5

[[parameter]]
name = "c"
value = 30.0
min = 10.0
max = 80.0

[[element]]
name = "spring"
body = "mass"
to = "ground"
at = [0.0, 0.0, 0.0]
ux = { k = "k", c = "c" }

[[excitation]]
body = "mass"
at = [0.0, 0.0, 0.0]
direction = [1, 0, 0]
signal = { type = "sine", amplitude = 100.0, frequency = 30.0 }
"#,
    );
    for (name, kind) in sensors.iter().zip(kinds) {
        text += &format!(
            "\n[[sensor]]\nname = \"{name}\"\nbody = \"mass\"\nat = [0.0, 0.0, 0.0]\n\
             direction = [1, 0, 0]\nquantity = \"{kind}\"\n"
        );
    }
    common::model(&text)
}

/// Sensors named otherwise than the files' signals, each with a source.
fn mapped() -> (Model, Vec<DataSource>) {
    let sources = vec![
        DataSource::Column("disp_x".into()),
        DataSource::Variable("vel_x".into()),
        DataSource::Record(RecordRef::Name("acc_x".into())),
    ];
    (model_named(["x", "v", "a"]), sources)
}

fn bits(v: &[f64]) -> Vec<u64> {
    v.iter().map(|x| x.to_bits()).collect()
}

const FILES: [&str; 5] = [
    "signals.csv",
    "signals.mat",
    "signals_compressed.mat",
    "signals_ascii.uff",
    "signals_binary.uff",
];

#[test]
fn the_reference_signals_are_the_closed_form_response() {
    let csv = reference();
    let omega = 2.0 * PI * 30.0;
    for (c, name) in ["disp_x", "vel_x", "acc_x"].into_iter().enumerate() {
        let exact: Vec<f64> = csv
            .time
            .iter()
            .map(|&t| {
                let (x, v, a) = common::sdof_forced(2.0, 40.0, 2.0e5, 100.0, omega, t);
                [x, v, a][c]
            })
            .collect();
        // 12 significant digits written, so 1e-11 of the scale.
        let err = common::rel_max_err(csv.column(name).unwrap(), &exact);
        assert!(err < 1e-11, "{name}: {err:e}");
    }
}

#[test]
fn every_format_gives_the_same_time_series() {
    let (model, sources) = mapped();
    let csv = read_measurement(&fixture("signals.csv"), &model, &sources)
        .unwrap()
        .series;
    assert_eq!(csv.names, ["x", "v", "a"]);
    let reference = reference();
    for (c, name) in ["disp_x", "vel_x", "acc_x"].into_iter().enumerate() {
        assert_eq!(bits(&csv.columns[c]), bits(reference.column(name).unwrap()));
    }
    for file in FILES {
        let ts = read_measurement(&fixture(file), &model, &sources)
            .unwrap_or_else(|e| panic!("{file}: {e}"))
            .series;
        assert_eq!(ts.names, csv.names, "{file}");
        for c in 0..3 {
            assert_eq!(bits(&ts.columns[c]), bits(&csv.columns[c]), "{file}: {c}");
        }
        // k / 1000 (from fs) and 0 + k · 0.001 (CSV, UFF) may differ in
        // the last bit.
        for (a, b) in ts.time.iter().zip(&csv.time) {
            assert!((a - b).abs() <= 1e-17, "{file}: {a} vs {b}");
        }
    }
}

#[test]
fn the_same_data_in_every_format_gives_the_same_identification() {
    let (model, sources) = mapped();
    let settings = Settings {
        plan_points: 16,
        starts: 1,
        ..Settings::default()
    };
    let mut results = Vec::new();
    for file in FILES {
        let ts = read_measurement(&fixture(file), &model, &sources)
            .unwrap()
            .series;
        let measured = match_data(&model, &ts)
            .unwrap_or_else(|e| panic!("{file}: {e}"))
            .response;
        let r = identify(
            OutputError::new(Simulator::new(&model), measured, 0),
            &settings,
            &Silent,
        )
        .unwrap_or_else(|e| panic!("{file}: {e}"));
        results.push((file, r));
    }
    let (_, first) = &results[0];
    // The data are the exact response (to 12 digits): the truth is found.
    let k = first.parameters[0].estimate;
    let c = first.parameters[1].estimate;
    assert!((k / 2.0e5 - 1.0).abs() < 1e-4, "k = {k}");
    assert!((c / 40.0 - 1.0).abs() < 1e-3, "c = {c}");
    for (file, r) in &results[1..] {
        for (p, q) in r.parameters.iter().zip(&first.parameters) {
            assert_eq!(
                p.estimate.to_bits(),
                q.estimate.to_bits(),
                "{file}: {}",
                p.name
            );
        }
        assert_eq!(r.criterion.to_bits(), first.criterion.to_bits(), "{file}");
        assert_eq!(r.iterations, first.iterations, "{file}");
    }
}

#[test]
fn by_default_each_sensor_reads_the_signal_named_like_it() {
    let model = model_named(["disp_x", "vel_x", "acc_x"]);
    let sources = default_sources(&model);
    assert_eq!(sources[2], DataSource::Column("acc_x".into()));
    let csv: TimeSeries = read_measurement(&fixture("signals.csv"), &model, &sources)
        .unwrap()
        .series;
    // Exactly what read_csv gives, as before sources existed.
    assert_eq!(csv, reference());
    for file in FILES {
        let ts = read_measurement(&fixture(file), &model, &sources)
            .unwrap()
            .series;
        assert_eq!(bits(&ts.columns[2]), bits(&csv.columns[2]), "{file}");
    }
    // Record numbers work in universal files only.
    let by_number: Vec<DataSource> = (1..=3)
        .map(|n| DataSource::Record(RecordRef::Index(n)))
        .collect();
    let ts = read_measurement(&fixture("signals_binary.uff"), &model, &by_number)
        .unwrap()
        .series;
    assert_eq!(bits(&ts.columns[1]), bits(&csv.columns[1]));
    let e = read_measurement(&fixture("signals.mat"), &model, &by_number).unwrap_err();
    assert!(
        matches!(e, DataFileError::RecordNumber { record: 1, .. }),
        "{e:?}"
    );
    assert!(e.to_string().contains("only universal files"), "{e}");
}

#[test]
fn mat_time_axes_come_from_t_or_a_sample_rate() {
    let model = model_named(["x", "v", "a"]);
    // mixed_classes.mat: time from `t`; vel single, acceleration in counts.
    let sources = vec![
        DataSource::Variable("disp_x".into()),
        DataSource::Variable("vel_x".into()),
        DataSource::Variable("acc_counts".into()),
    ];
    let ts = read_measurement(&fixture("mixed_classes.mat"), &model, &sources)
        .unwrap()
        .series;
    assert_eq!(bits(&ts.time), bits(&reference().time));
    // Neither a time vector nor a rate: an error listing the variables.
    let b = patch(&bytes("signals.mat"), b"time", b"tick");
    let path = scratch("no_time.mat", &b);
    let e = read_measurement(&path, &model, &mapped().1).unwrap_err();
    assert!(matches!(e, DataFileError::NoTimeAxis { .. }), "{e:?}");
    assert!(
        e.to_string()
            .contains("(variables: tick, disp_x, vel_x, acc_x)"),
        "{e}"
    );
}

#[test]
fn mat_variable_errors_name_the_sensor_the_file_and_the_variable() {
    let model = model_named(["x", "v", "a"]);
    let with = |last: &str| {
        vec![
            DataSource::Variable("disp_x".into()),
            DataSource::Variable("vel_x".into()),
            DataSource::Variable(last.into()),
        ]
    };
    let path = fixture("mixed_classes.mat");
    let cases = [
        (
            "note",
            "variable 'note' is a char array, not a numeric vector",
        ),
        ("grid", "variable 'grid' is a 2×3 matrix, not a vector"),
        ("cplx", "variable 'cplx' is complex"),
        ("acc_x", "no variable 'acc_x' (variables: t, disp_x"),
    ];
    for (var, says) in cases {
        let e = read_measurement(&path, &model, &with(var)).unwrap_err();
        assert!(matches!(e, DataFileError::SensorVariable { .. }), "{e:?}");
        let msg = e.to_string();
        assert!(msg.starts_with("sensor 'a': "), "{msg}");
        assert!(
            msg.contains("mixed_classes.mat") && msg.contains(says),
            "{msg}"
        );
    }
    let e = read_measurement(&path, &model, &with("i8")).unwrap_err();
    assert!(
        e.to_string().contains(
            "sensor 'a' (variable 'i8') has 3 samples, the time axis (variable 't') has 50"
        ),
        "{e}"
    );
    // A NaN in the data.
    let disp5 = reference().column("disp_x").unwrap()[5].to_le_bytes();
    let b = patch(&bytes("signals.mat"), &disp5, &f64::NAN.to_le_bytes());
    let e = read_measurement(&scratch("nan.mat", &b), &model, &mapped().1).unwrap_err();
    assert!(
        e.to_string()
            .contains("sensor 'x' (variable 'disp_x'): sample 5 is NaN, not a finite number"),
        "{e}"
    );
    // A malformed file as a whole: the reader's error.
    let e = read_measurement(
        &scratch("cut.mat", &bytes("signals.mat")[..1000]),
        &model,
        &mapped().1,
    )
    .unwrap_err();
    assert!(
        matches!(e, DataFileError::Mat(MatError::Truncated { .. })),
        "{e:?}"
    );
}

#[test]
fn uff_record_errors_name_the_sensor_the_file_and_the_record() {
    let (model, sources) = mapped();
    let by = |r: RecordRef| {
        vec![
            sources[0].clone(),
            sources[1].clone(),
            DataSource::Record(r),
        ]
    };
    // Complex data.
    let e =
        read_measurement(&fixture("complex.uff"), &model, &by(RecordRef::Index(1))).unwrap_err();
    // The first sensor's name is looked up first: not there.
    assert!(
        matches!(&e, DataFileError::SensorRecord { source, .. } if matches!(**source, UffError::UnknownRecord { .. })),
        "{e:?}"
    );
    let one: Vec<DataSource> = vec![DataSource::Record(RecordRef::Index(1)); 3];
    let e = read_measurement(&fixture("complex.uff"), &model, &one).unwrap_err();
    assert!(
        e.to_string().starts_with("sensor 'x': ")
            && e.to_string()
                .contains("complex.uff: record 1 ('H11') holds complex data"),
        "{e}"
    );
    // An unknown record.
    let e = read_measurement(
        &fixture("signals_ascii.uff"),
        &model,
        &by(RecordRef::Index(7)),
    )
    .unwrap_err();
    let msg = e.to_string();
    assert!(
        msg.contains("sensor 'a': ") && msg.contains("signals_ascii.uff: no function record 7"),
        "{msg}"
    );
    // A record that is not a time response (function type 4, an FRF).
    let text = bytes("signals_ascii.uff");
    let b = patch(
        &text,
        b"    1         0    0         0       NONE         1   3",
        b"    4         0    0         0       NONE         1   3",
    );
    let e = read_measurement(&scratch("frf.uff", &b), &model, &sources).unwrap_err();
    assert!(
        matches!(
            e,
            DataFileError::NotTimeResponse {
                record: 3,
                function_type: 4,
                ..
            }
        ),
        "{e:?}"
    );
    // Records with different time axes.
    let b = patch_nth(&text, b"1.00000e-03", b"2.00000e-03", 1);
    let e = read_measurement(&scratch("dt.uff", &b), &model, &sources).unwrap_err();
    assert!(
        matches!(
            e,
            DataFileError::AbscissaMismatch {
                first: 1,
                other: 2,
                ..
            }
        ),
        "{e:?}"
    );
    // An uneven abscissa agrees with the even ones.
    let uneven = by(RecordRef::Index(4));
    let uneven = vec![uneven[2].clone(), uneven[1].clone(), sources[2].clone()];
    let ts = read_measurement(&fixture("signals_ascii.uff"), &model, &uneven)
        .unwrap()
        .series;
    assert_eq!(
        bits(&ts.columns[0]),
        bits(reference().column("disp_x").unwrap())
    );
    // A truncated record: the reader's error, naming the record.
    let e = read_measurement(&scratch("cut.uff", &text[..3000]), &model, &sources).unwrap_err();
    assert!(
        matches!(e, DataFileError::Uff(UffError::Truncated { .. })),
        "{e:?}"
    );
    assert!(e.to_string().contains("cut.uff: record 2"), "{e}");
}

#[test]
fn csv_columns_not_read_are_noted_and_read_ones_must_be_present() {
    let path = fixture("signals.csv");
    let two = model_named(["x", "v", "a"]);
    let mut sources = mapped().1;
    sources[2] = DataSource::Column("disp_x".into());
    let read = read_measurement(&path, &two, &sources).unwrap();
    assert_eq!(
        read.notes,
        [format!(
            "{}: column 'acc_x' read by no sensor, ignored",
            path.display()
        )]
    );
    assert_eq!(read.series.columns[2], read.series.columns[0]);
    sources[2] = DataSource::Column("acc_x".into());
    sources[0] = DataSource::Column("vel_x".into());
    let read = read_measurement(&path, &two, &sources).unwrap();
    assert_eq!(
        read.notes,
        [format!(
            "{}: column 'disp_x' read by no sensor, ignored",
            path.display()
        )]
    );
    let e = read_measurement(&path, &two, &sources[..2]).unwrap_err();
    assert!(
        matches!(
            e,
            DataFileError::SourceCount {
                sources: 2,
                sensors: 3,
                ..
            }
        ),
        "{e:?}"
    );
    let e = read_measurement(Path::new("data.txt"), &two, &mapped().1).unwrap_err();
    assert_eq!(
        e.to_string(),
        "data.txt: unknown data format '.txt' (expected .csv, .mat, .uff, .unv or .58)"
    );
    // A missing column, with a mapping: both names are said.
    let csv = "time,disp_x,vel_x\n0,0,0\n0.001,1,2\n";
    let e = read_measurement(&scratch("two.csv", csv.as_bytes()), &two, &mapped().1).unwrap_err();
    assert!(
        e.to_string()
            .contains("no column 'acc_x' for sensor 'a' (columns: disp_x, vel_x)"),
        "{e}"
    );
}

#[test]
fn sources_deserialize_from_the_model_file_syntax() {
    #[derive(serde::Deserialize)]
    struct Sensor {
        data: DataSource,
    }
    let read = |s: &str| toml::from_str::<Sensor>(s).map(|x| x.data);
    assert_eq!(
        read(r#"data = { column = "knee_ax" }"#).unwrap(),
        DataSource::Column("knee_ax".into())
    );
    assert_eq!(
        read(r#"data = { variable = "acc_x" }"#).unwrap(),
        DataSource::Variable("acc_x".into())
    );
    assert_eq!(
        read("data = { record = 3 }").unwrap(),
        DataSource::Record(RecordRef::Index(3))
    );
    assert_eq!(
        read(r#"data = { record = "acc_x" }"#).unwrap(),
        DataSource::Record(RecordRef::Name("acc_x".into()))
    );
    let e = read("data = { record = 0 }").unwrap_err().to_string();
    assert!(e.contains("records are numbered from 1"), "{e}");
    let e = read(r#"data = { colum = "x" }"#).unwrap_err().to_string();
    assert!(
        e.contains("unknown field `colum`, expected one of `column`, `variable`, `record`"),
        "{e}"
    );
    let e = read(r#"data = { column = "a", variable = "b" }"#)
        .unwrap_err()
        .to_string();
    assert!(e.contains("not both 'column' and 'variable'"), "{e}");
    let e = read("data = {}").unwrap_err().to_string();
    assert!(e.contains("give column, variable or record"), "{e}");
    let e = read(r#"data = "acc_x""#).unwrap_err().to_string();
    assert!(e.contains("expected a table with one key"), "{e}");
    let e = read("data = { column = 3 }").unwrap_err().to_string();
    assert!(e.contains("expected a string"), "{e}");
    assert!(DataSource::Column(" ".into()).check().is_err());
    assert!(DataSource::Record(RecordRef::Index(0)).check().is_err());
    assert!(DataSource::Record(RecordRef::Index(2)).check().is_ok());
}
