//! `rfeid frf`: the README's FRF section end to end (a sweep test's H1 over
//! the demo's estimate and band), a measured force column against the
//! model's own table signal, and bad input exiting 2 without output files.
use crate::support;

use serde_json::Value;
use std::path::Path;
use support::*;

/// Runs rfeid with `args`, which must succeed.
fn ok(args: &[&std::ffi::OsStr]) -> std::process::Output {
    let o = rfeid().args(args).output().unwrap();
    assert!(finished(o.status), "{args:?}: {}", flat(&o.stderr));
    o
}

macro_rules! os {
    ($($a:expr),* $(,)?) => { &[$(std::ffi::OsStr::new($a)),*] };
}

/// The README's FRF test (1 cN random force, 2 % noise): H1 over the
/// demo's estimate, with a band, in the CSV, JSON and SVG; where the
/// coherence exceeds 0.9 the median misfit of H1 is within its random error.
#[test]
fn random_force_h1_over_the_demo_estimate_and_band() {
    let dir = scratch_dir("frf-sweep");
    let (test, demo) = (dir.join("frf-test.csv"), dir.join("demo.json"));
    let (csv, json, svg) = (
        dir.join("frf.csv"),
        dir.join("frf.json"),
        dir.join("frf.svg"),
    );
    let model = example_model("knee-column-frf");
    ok(os![
        "simulate",
        model.as_os_str(),
        "--noise",
        "0.02",
        "--seed",
        "1",
        "-o",
        test.as_os_str()
    ]);
    ok(os!["demo", "--noise", "0.02", "-o", demo.as_os_str()]);
    let out = ok(os![
        "frf",
        model.as_os_str(),
        "--result",
        demo.as_os_str(),
        "--data",
        test.as_os_str(),
        "-o",
        csv.as_os_str(),
        "--json-file",
        json.as_os_str(),
        "--plot",
        svg.as_os_str()
    ]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("linearised at rest"), "{text}");
    assert!(text.contains("95 % band"), "{text}");
    let v: Value = serde_json::from_slice(&std::fs::read(&json).unwrap()).unwrap();
    let pairs = v["pairs"].as_array().unwrap();
    assert_eq!(pairs.len(), 3);
    let rows = std::fs::read_to_string(&csv).unwrap();
    let header = rows.lines().next().unwrap();
    assert!(header.starts_with("excitation,output,curve,frequency_hz,magnitude"));
    let (mut coherent, mut ratios) = (0usize, Vec::new());
    for p in pairs {
        assert!(p["band"].is_object(), "a band with the demo's result");
        let m = &p["measured"][0];
        let f = |k: &str| -> Vec<f64> {
            m[k].as_array()
                .unwrap()
                .iter()
                .map(|x| x.as_f64().unwrap_or(f64::NAN))
                .collect()
        };
        let g = |k: &str| -> Vec<f64> {
            p[k].as_array()
                .unwrap()
                .iter()
                .map(|x| x.as_f64().unwrap())
                .collect()
        };
        let (re, im, g2, eps) = (f("real"), f("imag"), f("coherence"), f("random_error"));
        let (mre, mim) = (g("real"), g("imag"));
        for k in 0..re.len() {
            if g2[k] > 0.9 {
                coherent += 1;
                let d = ((re[k] - mre[k]).powi(2) + (im[k] - mim[k]).powi(2)).sqrt();
                let h = mre[k].hypot(mim[k]);
                ratios.push(d / h / eps[k]);
            }
        }
    }
    ratios.sort_by(f64::total_cmp);
    let median = ratios[ratios.len() / 2];
    eprintln!("{coherent} coherent bins, median |H1 − H|/(|H| ε) = {median:.2}");
    assert!(coherent > 100, "{coherent} coherent bins");
    // The median of a χ₂ variable (|e|/ε with both parts of sd ε) is 1.18.
    assert!(median < 2.0, "median misfit {median} ε");
    let svg = std::fs::read_to_string(&svg).unwrap();
    assert!(svg.starts_with("<svg") && svg.matches("<svg").count() == 4);
    std::fs::remove_dir_all(&dir).ok();
}

/// The Bouc–Wen benchmark's force is a table of its data file. With the
/// table read by linear interpolation (which gives the samples themselves
/// at the sample times), H1 from `--force u` (the column read directly)
/// equals H1 from the model's own table signal to rounding. (With the
/// example's band-limited interpolation the two differ by up to 1e-6
/// relative: that interpolant is evaluated, not the samples.)
#[test]
fn a_force_column_gives_the_h1_of_the_models_table_signal() {
    let dir = scratch_dir("frf-force");
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../data/bouc-wen/train.mat");
    let text = std::fs::read_to_string(example_model("bouc-wen")).unwrap();
    let table =
        r#"file = "../../data/bouc-wen/train.mat", variable = "u", interpolation = "band-limited""#;
    assert!(text.contains(table));
    let linear = format!(
        r#"file = "{}", variable = "u", interpolation = "linear""#,
        data.display()
    );
    let model = dir.join("model.toml");
    std::fs::write(&model, text.replace(table, &linear)).unwrap();
    let run = |extra: &[&str]| -> Value {
        let mut args: Vec<&std::ffi::OsStr> = os![
            "frf",
            model.as_os_str(),
            "--data",
            data.as_os_str(),
            "--json"
        ]
        .to_vec();
        args.extend(extra.iter().map(std::ffi::OsStr::new));
        serde_json::from_slice(&ok(&args).stdout).unwrap()
    };
    let (own, column) = (run(&[]), run(&["--force", "u"]));
    let h = |v: &Value| v["pairs"][0]["measured"][0]["magnitude"].clone();
    let (a, b) = (h(&own), h(&column));
    let (a, b) = (a.as_array().unwrap(), b.as_array().unwrap());
    assert_eq!(a.len(), b.len());
    for (x, y) in a.iter().zip(b) {
        let (x, y) = (x.as_f64().unwrap(), y.as_f64().unwrap());
        assert!((x - y).abs() <= 1e-12 * x.abs(), "{x} vs {y}");
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// Bad options exit 2 with the option named, and write no output file.
#[test]
fn bad_input_exits_2_without_output() {
    let dir = scratch_dir("frf-bad");
    let out = dir.join("frf.csv");
    let model = example_model("knee-column");
    for (extra, needle) in [
        (vec!["--at", "tool=knee"], "--at tool=knee"),
        (
            vec!["--at", "tool=spindle@0,0,0/0,0,1"],
            "no body 'spindle'",
        ),
        (vec!["--at", "tool=knee@0,0,0/0,0,0"], "direction is zero"),
        (vec!["--excitation", "hammer"], "--excitation hammer"),
        (vec!["--fmax=-3"], "--fmax -3"),
        (vec!["--points", "1"], "--points 1"),
        (vec!["--fmin", "0"], "--fmin 0"),
        (vec!["--set", "nope=1"], "nope"),
    ] {
        let mut args: Vec<&std::ffi::OsStr> =
            os!["frf", model.as_os_str(), "-o", out.as_os_str()].to_vec();
        args.extend(extra.iter().map(std::ffi::OsStr::new));
        let o = rfeid().args(&args).output().unwrap();
        let err = flat(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{extra:?}: {err}");
        assert!(err.contains(needle), "{extra:?}: {err}");
        assert!(!out.exists(), "{extra:?} left {}", out.display());
    }
    std::fs::remove_dir_all(&dir).ok();
}
