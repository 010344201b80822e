//! Data as acquisition systems write them: semicolon or tab separators,
//! columns in any order, extra channels, float32 time stamps, triggered
//! records starting at t0 ≠ 0 and records longer than the model's. Each is
//! read to exactly the samples of a clean CSV, hence the same estimates;
//! decimal commas, other sample rates, stamps off the grid and force tables
//! that stop inside the simulated time are errors that say so.
use crate::common;
use crate::import_common;

use import_common::*;
use rfeid::identification::output_error::OutputError;
use rfeid::identification::pipeline::{identify, Settings, Silent};
use rfeid::io::data_file::{read_measurement, DataRead};
use rfeid::io::model_file::load_model;
use rfeid::io::timeseries::{detect_separator, read_csv, DataError};
use rfeid::measurement::{match_data, Matched, MeasurementError, GRID_TOLERANCE};
use rfeid::model::{default_sources, Model};
use rfeid::simulation::Simulator;

/// The oscillator of the import fixtures (k and c identified), sampled at
/// 1000 Hz for `duration` s, with sensors `x`, `v`, `a` reading columns of
/// those names.
fn model(duration: f64) -> Model {
    let mut text = format!(
        r#"
[simulation]
duration = {duration}
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
ux = {{ k = "k", c = "c" }}

[[excitation]]
body = "mass"
at = [0.0, 0.0, 0.0]
direction = [1, 0, 0]
signal = {{ type = "sine", amplitude = 100.0, frequency = 30.0 }}
"#
    );
    for (name, kind) in ["x", "v", "a"]
        .iter()
        .zip(["displacement", "velocity", "acceleration"])
    {
        text += &format!(
            "\n[[sensor]]\nname = \"{name}\"\nbody = \"mass\"\nat = [0.0, 0.0, 0.0]\n\
             direction = [1, 0, 0]\nquantity = \"{kind}\"\n"
        );
    }
    common::model(&text)
}

/// One data file's text: `header` columns from `time`, `force`, `x`, `v`,
/// `a` (the reference signals, a 100 N force channel), rows `rows` of the
/// reference, separated by `sep`, time stamps through `stamp`.
fn file_text(header: &[&str], sep: &str, rows: usize, stamp: impl Fn(f64) -> String) -> String {
    let r = reference();
    let mut out = header.join(sep) + "\n";
    for k in 0..rows {
        let t = r.time[k];
        let cells: Vec<String> = header
            .iter()
            .map(|h| match *h {
                "time" => stamp(t),
                "force" => format!("{}", 100.0 * (2.0 * std::f64::consts::PI * 30.0 * t).sin()),
                "x" => format!("{}", r.columns[0][k]),
                "v" => format!("{}", r.columns[1][k]),
                "a" => format!("{}", r.columns[2][k]),
                other => panic!("no column {other}"),
            })
            .collect();
        out += &(cells.join(sep) + "\n");
    }
    out
}

/// The clean CSV's time stamp: the reference's, exactly.
fn clean(t: f64) -> String {
    format!("{t}")
}

/// A float32 stamp as a DAQ writes it: the float32 value printed in full
/// (0.001 becomes 0.0010000000474974513).
fn float32(t: f64) -> String {
    format!("{}", t as f32 as f64)
}

fn read(model: &Model, name: &str, text: &str) -> (DataRead, Result<Matched, MeasurementError>) {
    let path = scratch(name, text.as_bytes());
    let read = read_measurement(&path, model, &default_sources(model))
        .unwrap_or_else(|e| panic!("{name}: {e}"));
    let matched = match_data(model, &read.series);
    (read, matched)
}

fn bits(v: &[f64]) -> Vec<u64> {
    v.iter().map(|x| x.to_bits()).collect()
}

#[test]
fn a_daq_file_gives_the_estimates_of_a_clean_csv() {
    let model = model(0.05);
    let n = reference().time.len();
    assert_eq!(n, 50);
    let clean_text = file_text(&["time", "x", "v", "a"], ",", n, clean);
    let daq_text = file_text(&["force", "a", "time", "x", "v"], ";", n, float32);
    // The float32 stamps do differ from the grid.
    assert!(daq_text.contains(";0.0010000000474974513;"), "{daq_text}");
    let (clean_read, clean_matched) = read(&model, "clean.csv", &clean_text);
    let (daq_read, daq_matched) = read(&model, "daq.csv", &daq_text);
    assert!(clean_read.notes.is_empty(), "{:?}", clean_read.notes);
    assert_eq!(daq_read.notes.len(), 1);
    assert!(
        daq_read.notes[0].ends_with("daq.csv: column 'force' read by no sensor, ignored"),
        "{:?}",
        daq_read.notes
    );
    let (clean, daq) = (clean_matched.unwrap(), daq_matched.unwrap());
    assert!(clean.notes.is_empty() && daq.notes.is_empty());
    assert_eq!(bits(&daq.response.values), bits(&clean.response.values));
    let settings = Settings {
        plan_points: 16,
        starts: 1,
        ..Settings::default()
    };
    let run = |m: &Matched| {
        identify(
            OutputError::new(Simulator::new(&model), m.response.clone(), 0),
            &settings,
            &Silent,
        )
        .unwrap()
    };
    let (a, b) = (run(&clean), run(&daq));
    for (p, q) in a.parameters.iter().zip(&b.parameters) {
        assert_eq!(p.estimate.to_bits(), q.estimate.to_bits(), "{}", p.name);
    }
    // And they are the truth: the reference is the exact response.
    assert!((a.parameters[0].estimate / 2.0e5 - 1.0).abs() < 1e-4);
    assert!((a.parameters[1].estimate / 40.0 - 1.0).abs() < 1e-3);
}

#[test]
fn separators_are_detected_from_the_header() {
    assert_eq!(detect_separator("time,x,v"), b',');
    assert_eq!(detect_separator("time;x;v"), b';');
    assert_eq!(detect_separator("time\tx\tv"), b'\t');
    assert_eq!(detect_separator("time"), b',');
    // A comma inside a name does not outvote the semicolons.
    assert_eq!(detect_separator("time;force, N;x"), b';');
    let model = model(0.05);
    let clean_text = file_text(&["time", "x", "v", "a"], ",", 50, clean);
    let tab_text = file_text(&["v", "time", "a", "x"], "\t", 50, clean);
    let (_, clean) = read(&model, "clean.csv", &clean_text);
    let (_, tab) = read(&model, "tab.csv", &tab_text);
    assert_eq!(
        bits(&tab.unwrap().response.values),
        bits(&clean.unwrap().response.values)
    );
}

#[test]
fn a_triggered_record_is_shifted_to_start_at_zero_with_a_note() {
    let model = model(0.05);
    let clean_text = file_text(&["time", "x", "v", "a"], ",", 50, clean);
    let late = file_text(&["time", "x", "v", "a"], ",", 50, |t| {
        format!("{}", 1.2345 + t)
    });
    let (_, clean) = read(&model, "clean.csv", &clean_text);
    let (_, late) = read(&model, "late.csv", &late);
    let late = late.unwrap();
    assert_eq!(
        late.notes,
        ["the record starts at t = 1.2345 s; it is taken as starting at the model's t = 0"]
    );
    assert_eq!(
        bits(&late.response.values),
        bits(&clean.unwrap().response.values)
    );
    // float32 stamps of a triggered record: 1.2345 is not a float32, and
    // the stamps' rounding grows with t; still accepted.
    let late32 = file_text(&["time", "x", "v", "a"], ",", 50, |t| float32(1.2345 + t));
    let (_, late32) = read(&model, "late32.csv", &late32);
    assert_eq!(late32.unwrap().notes.len(), 1);
}

#[test]
fn a_longer_record_is_cut_with_a_note() {
    let model = model(0.04);
    let text = file_text(&["time", "x", "v", "a"], ",", 50, clean);
    let (_, m) = read(&model, "long.csv", &text);
    let m = m.unwrap();
    assert_eq!(
        m.notes,
        [
            "the record has 50 samples (0.05 s); the model uses the first 40 (0.04 s at 1000 Hz), \
          the other 10 are ignored"
        ]
    );
    let r = reference();
    assert_eq!(bits(m.response.sensor(2)), bits(&r.columns[2][..40]));
}

#[test]
fn the_grid_tolerance_is_a_thousandth_of_the_sample_interval() {
    let model = model(0.05);
    let dt = 1e-3;
    // Sample 10 (t = 0.01 s, where float32 rounding is 6e-10 s) moved by
    // 0.9 and 1.1 thousandths of dt.
    for (shift, ok) in [(0.9, true), (1.1, false), (-1.1, false)] {
        let text = file_text(&["time", "x", "v", "a"], ",", 50, |t| {
            if t == 0.01 {
                format!("{}", t + shift * GRID_TOLERANCE * dt)
            } else {
                clean(t)
            }
        });
        let (_, m) = read(&model, "shifted.csv", &text);
        match m {
            Ok(_) => assert!(ok, "{shift}"),
            Err(e) => {
                assert!(!ok, "{shift}: {e}");
                assert!(
                    matches!(e, MeasurementError::TimeMismatch { index: 10, .. }),
                    "{e:?}"
                );
                assert!(e.to_string().contains("to within 1.001e-6 s"), "{e}");
            }
        }
    }
}

#[test]
fn another_sample_rate_is_an_error_naming_both_rates() {
    let model = model(0.05);
    let r = reference();
    // Every other sample: 500 Hz.
    let mut text = String::from("time,x,v,a\n");
    for k in (0..50).step_by(2) {
        text += &format!(
            "{},{},{},{}\n",
            r.time[k], r.columns[0][k], r.columns[1][k], r.columns[2][k]
        );
    }
    let (_, m) = read(&model, "slow.csv", &text);
    let e = m.unwrap_err();
    assert_eq!(
        e.to_string(),
        "the data are sampled at 500 Hz, but the model samples at 1000 Hz: resample the data \
         to 1000 Hz (with an anti-aliasing filter when lowering the rate), or set \
         sample_rate = 500 Hz in [simulation]; rfeid does not resample"
    );
    // Time in ms: a rate a thousand times lower.
    let text = file_text(&["time", "x", "v", "a"], ",", 50, |t| {
        format!("{}", t * 1e3)
    });
    let (_, m) = read(&model, "ms.csv", &text);
    assert!(m
        .unwrap_err()
        .to_string()
        .starts_with("the data are sampled at 1 Hz, but the model samples at 1000 Hz"),);
}

#[test]
fn a_decimal_comma_is_named_as_such() {
    let text = "time;x\n0;0\n0,001;1,5\n";
    let path = scratch("comma.csv", text.as_bytes());
    let e = read_csv(&path).unwrap_err();
    assert!(
        matches!(e, DataError::DecimalComma { line: 3, .. }),
        "{e:?}"
    );
    assert_eq!(
        e.to_string(),
        format!(
            "{}: line 3, column 'time': '0,001' has a decimal comma; rfeid reads numbers with a \
             decimal point: export the file with '.' as the decimal separator",
            path.display()
        )
    );
    // No time column: the columns found are listed.
    let path = scratch("notime.csv", b"t;x\n0;1\n");
    assert_eq!(
        read_csv(&path).unwrap_err().to_string(),
        format!(
            "{}: no column 'time' (columns: t, x); the separator may be ',', ';' or a tab",
            path.display()
        )
    );
}

/// A model whose force is the table `rows` (time, force) of `force.csv`.
fn table_model(rows: &str) -> Result<Model, String> {
    let dir = std::env::temp_dir().join(format!("rfeid-lab-table-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("force.csv"), format!("time;push\n{rows}")).unwrap();
    let model = r#"
[simulation]
duration = 0.01
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
ux = { k = 2.0e5, c = 40.0 }

[[excitation]]
body = "mass"
at = [0.0, 0.0, 0.0]
direction = [1, 0, 0]
signal = { type = "table", file = "force.csv", column = "push" }

[[sensor]]
name = "x"
body = "mass"
at = [0.0, 0.0, 0.0]
direction = [1, 0, 0]
quantity = "displacement"
"#;
    std::fs::write(dir.join("model.toml"), model).unwrap();
    load_model(&dir.join("model.toml")).map_err(|e| e.to_string())
}

#[test]
fn a_force_table_must_cover_the_simulated_time() {
    // The simulation samples t = 0 … 0.009 s.
    table_model("0;1\n0.009;2\n").unwrap();
    // Ending at 0 early means "0 from there on" (SPEC §1).
    table_model("0;1\n0.005;0\n").unwrap();
    // Starting late at 0 likewise.
    table_model("0.002;0\n0.009;2\n").unwrap();
    // float32 stamps of the ends pass, and the table reaches the last
    // sample (0.009 as float32 is 0.008999999612569809, just before it).
    assert!(float32(0.009).parse::<f64>().unwrap() < 0.009);
    let m = table_model(&format!("{};1\n{};2\n", float32(1e-7), float32(0.009))).unwrap();
    let force = |t: f64| m.excitations[0].signal.at(t, &[]);
    assert_eq!(force(0.009), 2.0);
    assert_eq!(force(0.0), 1.0);
    // A short record ending at a nonzero value: the force would jump to 0.
    let e = table_model("0;1\n0.005;2\n").unwrap_err();
    assert!(e.contains("field 'signal.file'"), "{e}");
    assert!(e.contains("force.csv: column 'push'"), "{e}");
    assert!(
        e.contains(
            "the table spans t = 0 … 0.005 s, but the simulation samples t = 0 … 0.009 s; it ends at the value 2"
        ),
        "{e}"
    );
    // A triggered table starting inside the simulated time.
    let e = table_model("0.003;1\n0.009;2\n").unwrap_err();
    assert!(
        e.contains("the table spans t = 0.003 … 0.009 s, but the simulation samples t = 0 … 0.009 s; it starts at the value 1"),
        "{e}"
    );
}
