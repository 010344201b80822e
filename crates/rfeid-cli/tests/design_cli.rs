//! `rfeid design` on the knee–column (SPEC §6): the prediction against the
//! standard errors `identify` reports on seeded simulated data, the chosen
//! sensors simulated, identified and compared with their prediction, and
//! bad input exiting 2 with file, entry and field named.
use crate::support;

use serde_json::Value;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use support::*;

/// Seeds of the simulated tests.
const SEEDS: [u32; 4] = [1, 2, 3, 4];

fn example() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/knee-column/model.toml")
}

/// Runs rfeid with `args`, which must succeed; its standard output.
fn ok(args: &[&std::ffi::OsStr]) -> Vec<u8> {
    let o = rfeid().args(args).output().unwrap();
    assert!(finished(o.status), "{args:?}: {}", flat(&o.stderr));
    o.stdout
}

/// The model text with every `[[sensor]]` block passed through `edit`
/// (its name, its text).
fn edit_sensors(text: &str, edit: impl Fn(&str, &str) -> String) -> String {
    let mut parts = text.split("[[sensor]]");
    let mut out = parts.next().unwrap().to_string();
    for block in parts {
        // A block ends where the next section starts.
        let end = block.find("\n# ----").unwrap_or(block.len());
        let (body, rest) = block.split_at(end);
        let name = body
            .lines()
            .find_map(|l| l.strip_prefix("name = \""))
            .and_then(|l| l.split('"').next())
            .unwrap();
        out += "[[sensor]]";
        out += &edit(name, body);
        out += rest;
    }
    out
}

/// Simulates `model` with 2 % noise and `seed` and identifies it: the
/// estimates and standard errors by parameter name.
fn identify_seed(dir: &Path, model: &Path, seed: u32) -> HashMap<String, (f64, f64)> {
    let data = dir.join(format!("d{seed}.csv"));
    let out = dir.join(format!("r{seed}.json"));
    let os = |s: &str| std::ffi::OsString::from(s);
    ok(&[
        os("simulate").as_os_str(),
        model.as_os_str(),
        os("-o").as_os_str(),
        data.as_os_str(),
        os("--noise").as_os_str(),
        os("0.02").as_os_str(),
        os("--seed").as_os_str(),
        os(&seed.to_string()).as_os_str(),
        os("-q").as_os_str(),
    ]);
    let o = identify(model, &data, &out)
        .args(["--plan", "16", "-q"])
        .output()
        .unwrap();
    assert!(finished(o.status), "{}", flat(&o.stderr));
    let r: Value = serde_json::from_slice(&std::fs::read(&out).unwrap()).unwrap();
    r["parameters"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| {
            (
                p["name"].as_str().unwrap().to_string(),
                (
                    p["estimate"].as_f64().unwrap(),
                    p["std_error"].as_f64().unwrap(),
                ),
            )
        })
        .collect()
}

/// `rfeid design MODEL --json` with `extra`: the design.
fn design(model: &Path, extra: &[&str]) -> Value {
    let mut cmd = rfeid();
    cmd.arg("design")
        .arg(model)
        .args(["--json", "-q"])
        .args(extra);
    let o = cmd.output().unwrap();
    assert!(o.status.success(), "{}", flat(&o.stderr));
    serde_json::from_slice(&o.stdout).unwrap()
}

/// Each parameter's mean standard error over the seeds against the
/// prediction, and every estimate within 3 standard errors of the truth.
fn compare(design: &Value, runs: &[HashMap<String, (f64, f64)>], what: &str) {
    for p in design["parameters"].as_array().unwrap() {
        let name = p["name"].as_str().unwrap();
        let (value, predicted) = (
            p["value"].as_f64().unwrap(),
            p["std_error"].as_f64().unwrap(),
        );
        let mean = runs.iter().map(|r| r[name].1).sum::<f64>() / runs.len() as f64;
        let ratio = mean / predicted;
        eprintln!(
            "{what}: {name}: predicted {predicted:.4e}, identify's mean {mean:.4e} ({ratio:.3})"
        );
        assert!((ratio - 1.0).abs() <= 0.10, "{what}: {name}: ratio {ratio}");
        for r in runs {
            let (est, se) = r[name];
            assert!(
                (est - value).abs() <= 3.0 * se,
                "{what}: {name}: {est} vs {value} (s.e. {se})"
            );
        }
    }
}

#[test]
fn predicted_standard_errors_match_identification_on_seeded_data() {
    let dir = scratch_dir("design-placed");
    let model = example();
    let d = design(&model, &[]);
    assert_eq!(d["chosen"].as_array().unwrap().len(), 0);
    let runs: Vec<_> = SEEDS
        .iter()
        .map(|&s| identify_seed(&dir, &model, s))
        .collect();
    compare(&d, &runs, "placed");
}

#[test]
fn the_chosen_sensors_give_the_predicted_standard_errors() {
    let dir = scratch_dir("design-chosen");
    let text = std::fs::read_to_string(example()).unwrap();
    // Every candidate measured, noise-free: each one's RMS.
    let all = dir.join("all.toml");
    std::fs::write(&all, text.replace("candidate = true\n", "")).unwrap();
    let clean = dir.join("clean.csv");
    let os = |s: &str| std::ffi::OsString::from(s);
    ok(&[
        os("simulate").as_os_str(),
        all.as_os_str(),
        os("-o").as_os_str(),
        clean.as_os_str(),
        os("-q").as_os_str(),
    ]);
    let csv = std::fs::read_to_string(&clean).unwrap();
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    let rms = |c: usize| (rows.iter().map(|r| r[c] * r[c]).sum::<f64>() / rows.len() as f64).sqrt();
    let sigma: HashMap<String, f64> = (1..header.len())
        .map(|c| (header[c].to_string(), 0.02 * rms(c)))
        .collect();
    // The candidates' noise as `simulate --noise 0.02` will make it.
    let noisy = edit_sensors(&text, |name, body| {
        body.lines()
            .map(
                |l| match l.starts_with("noise = ") && body.contains("candidate = true") {
                    true => format!("noise = {:e}", sigma[name]),
                    false => l.to_string(),
                },
            )
            .collect::<Vec<_>>()
            .join("\n")
    });
    let model = dir.join("design.toml");
    std::fs::write(&model, &noisy).unwrap();
    let d = design(&model, &["--choose", "3"]);
    let chosen: Vec<String> = d["chosen"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_str().unwrap().to_string())
        .collect();
    assert_eq!(chosen.len(), 3);
    assert_eq!(d["choice"]["search"], "exhaustive");
    // The choice and every number do not depend on the thread count.
    assert_eq!(d, design(&model, &["--choose", "3", "--threads", "1"]));
    // The chosen ones placed for the test.
    let placed = edit_sensors(&noisy, |name, body| {
        match chosen.iter().any(|c| c == name) {
            true => body.replace("candidate = true\n", ""),
            false => body.to_string(),
        }
    });
    let test_model = dir.join("test.toml");
    std::fs::write(&test_model, placed).unwrap();
    let runs: Vec<_> = SEEDS
        .iter()
        .map(|&s| identify_seed(&dir, &test_model, s))
        .collect();
    compare(&d, &runs, "chosen");
    // The placed sensors' prediction comes along, and is worse.
    assert!(d["log_det"].as_f64().unwrap() > d["placed"]["log_det"].as_f64().unwrap());
}

#[test]
fn design_mistakes_exit_2_naming_file_entry_and_field() {
    let dir = scratch_dir("design-bad");
    let text = std::fs::read_to_string(example()).unwrap();
    let cases: Vec<(String, Vec<&str>, Vec<&str>)> = vec![
        // A placed sensor without noise.
        (
            text.replacen("noise = \"6.6e-4 m/s^2\"", "", 1),
            vec![],
            vec!["sensor \"knee_ax\"", "`noise`", "m.toml"],
        ),
        // A candidate without a body.
        (
            text.replacen(
                "body = \"knee\"\nat = [0.25, 0.9, 0.9]",
                "at = [0.25, 0.9, 0.9]",
                1,
            ),
            vec![],
            vec!["k1x", "body", "m.toml"],
        ),
        // A noise that is not a positive standard deviation.
        (
            text.replacen("noise = \"1.0e-3 m/s^2\"", "noise = \"-1 m/s^2\"", 1),
            vec![],
            vec!["k1x", "noise", "m.toml"],
        ),
        // A candidate's gain naming a parameter (nothing could identify it).
        (
            text.replacen(
                "noise = \"1.0e-3 m/s^2\"\ncandidate = true",
                "noise = \"1.0e-3 m/s^2\"\ngain = \"h_t3\"\ncandidate = true",
                1,
            ),
            vec![],
            vec!["k1x", "gain", "m.toml"],
        ),
        // A value outside its box.
        (
            text.clone(),
            vec!["--set", "h_t3=1"],
            vec!["--set h_t3", "outside its box"],
        ),
        // K beyond the candidates.
        (
            text.clone(),
            vec!["--choose", "22"],
            vec!["--choose 22", "21 candidate"],
        ),
        (
            text.clone(),
            vec!["--over-box", "4"],
            vec!["--over-box", "--choose"],
        ),
    ];
    for (k, (model_text, args, says)) in cases.into_iter().enumerate() {
        let m = dir.join("m.toml");
        std::fs::write(&m, model_text).unwrap();
        let out = dir.join(format!("out{k}.json"));
        let o = rfeid()
            .arg("design")
            .arg(&m)
            .args(&args)
            .arg("-o")
            .arg(&out)
            .output()
            .unwrap();
        let msg = flat(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "case {k}: {msg}");
        // Refused, not warned about and then refused.
        assert!(!msg.contains("warning"), "case {k}: {msg}");
        for s in says {
            assert!(msg.contains(s), "case {k}: '{s}' not in: {msg}");
        }
        assert!(!out.exists(), "case {k} wrote its output");
    }
}

/// Before a first test every sensor is a candidate: `design --choose 3`
/// chooses all three, says it compares with no sensor (text and JSON), and
/// the commands that need a measured sensor still refuse the model, naming
/// its file.
#[test]
fn design_with_no_placed_sensor_compares_with_no_sensor() {
    let dir = scratch_dir("design-unplaced");
    let text = std::fs::read_to_string(example()).unwrap();
    let unplaced = edit_sensors(&text, |_, body| match body.contains("candidate = true") {
        true => body.to_string(),
        false => body.replacen("\nnoise = ", "\ncandidate = true\nnoise = ", 1),
    });
    assert_eq!(unplaced.matches("candidate = true").count(), 24);
    let model = dir.join("unplaced.toml");
    std::fs::write(&model, unplaced).unwrap();
    let out = ok(&[
        "design".as_ref(),
        model.as_os_str(),
        "--choose".as_ref(),
        "3".as_ref(),
        "-q".as_ref(),
    ]);
    let out = String::from_utf8(out).unwrap();
    assert!(out.contains("placed sensors: none"), "{out}");
    assert!(out.contains("compared with no sensor"), "{out}");
    assert!(
        !out.contains("placed/chosen") && !out.contains("det ratio"),
        "{out}"
    );
    assert!(out.contains("D-efficiency is at least"), "{out}");
    let d = design(&model, &["--choose", "3"]);
    assert_eq!(d["compared_with"], "no_sensor");
    assert_eq!(d["placed"], Value::Null);
    assert_eq!(d["placed_sensors"].as_array().unwrap().len(), 0);
    assert_eq!(d["chosen"].as_array().unwrap().len(), 3);
    assert_eq!(d["choice"]["search"], "exhaustive");
    assert_eq!(d["choice"]["determinant_ratio_log"], Value::Null);
    assert!(d["parameters"][0]["std_error"].as_f64().unwrap() > 0.0);
    // Without --choose there is nothing to predict; and the commands that
    // measure refuse a model without a measured sensor.
    let data = dir.join("none.csv");
    let res = dir.join("r.json");
    let refused: [(&[&std::ffi::OsStr], &str); 4] = [
        (&["design".as_ref(), model.as_os_str()], "--choose K"),
        (
            &["check".as_ref(), model.as_os_str()],
            "every [[sensor]] is a candidate",
        ),
        (
            &[
                "simulate".as_ref(),
                model.as_os_str(),
                "-o".as_ref(),
                data.as_os_str(),
            ],
            "every [[sensor]] is a candidate",
        ),
        (
            &[
                "identify".as_ref(),
                model.as_os_str(),
                "--data".as_ref(),
                data.as_os_str(),
                "-o".as_ref(),
                res.as_os_str(),
            ],
            "every [[sensor]] is a candidate",
        ),
    ];
    for (args, says) in refused {
        let o = rfeid().args(args).output().unwrap();
        let msg = flat(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {msg}");
        assert!(
            msg.contains("unplaced.toml") && msg.contains(says),
            "{args:?}: {msg}"
        );
    }
    assert!(!data.exists() && !res.exists());
}
