//! `--profiles` and `--profile-points` on the command line: the table after
//! the parameter table, with `--set` (one parameter left: its profile is J
//! itself), and their misuse as bad input (exit 2, no output).
use crate::support;

use std::path::Path;
use support::*;

/// The oscillator's data with 1 % noise, in `dir`.
fn noisy_data(dir: &Path, model: &Path) -> std::path::PathBuf {
    let out = dir.join("noisy.csv");
    let st = rfeid()
        .args(["simulate", "-q", "--noise", "0.01", "--seed", "4", "-o"])
        .arg(&out)
        .arg(model)
        .status()
        .unwrap();
    assert!(st.success());
    out
}

#[test]
fn profiles_are_tabled_and_recorded() {
    let dir = scratch_dir("profiles-table");
    let model = oscillator_model(&dir);
    let data = noisy_data(&dir, &model);
    let out = dir.join("r.json");
    let o = identify(&model, &data, &out)
        .args(["--plan", "20", "--profiles=c", "--profile-points", "8"])
        .output()
        .unwrap();
    assert!(finished(o.status), "{}", flat(&o.stderr));
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(
        text.contains("profile likelihoods: 95 % intervals"),
        "{text}"
    );
    assert!(
        text.contains("Wald 95 %") && text.contains("profile 95 %"),
        "{text}"
    );
    let r: serde_json::Value = serde_json::from_slice(&std::fs::read(&out).unwrap()).unwrap();
    let p = &r["profiles"][0];
    assert_eq!(p["name"], "c");
    assert_eq!(p["points"].as_array().unwrap().len(), 9);
    assert!(r["timings"]["profiles"].as_f64().unwrap() > 0.0);
    assert_eq!(r["profiles"].as_array().unwrap().len(), 1);
}

#[test]
fn with_set_one_parameter_is_left_and_its_profile_is_the_criterion() {
    let dir = scratch_dir("profiles-set");
    let model = oscillator_model(&dir);
    let data = noisy_data(&dir, &model);
    let out = dir.join("r.json");
    let o = identify(&model, &data, &out)
        .args(["-q", "--plan", "20", "--set", "k=1.6e5", "--profiles"])
        .output()
        .unwrap();
    assert!(finished(o.status), "{}", flat(&o.stderr));
    let r: serde_json::Value = serde_json::from_slice(&std::fs::read(&out).unwrap()).unwrap();
    let p = &r["profiles"][0];
    assert_eq!(p["name"], "c");
    let points = p["points"].as_array().unwrap();
    assert_eq!(points.len(), 21);
    assert!(points.iter().all(|q| q["criterion"].is_f64()), "{p}");
}

#[test]
fn misused_profile_options_are_bad_input() {
    let dir = scratch_dir("profiles-bad");
    let model = oscillator_model(&dir);
    let data = simulate_csv(&dir, &model);
    let out = dir.join("r.json");
    let cases: [(&[&str], &str); 4] = [
        (&["--profiles=k9"], "'k9'"),
        (&["--profile-points", "5"], "--profiles"),
        (
            &["--profiles", "--profile-points", "1"],
            "--profile-points 1",
        ),
        (&["--profiles", "--shard", "0/2"], "--shard"),
    ];
    for (args, says) in cases {
        let o = identify(&model, &data, &out)
            .args(["-q", "--plan", "4"])
            .args(args)
            .output()
            .unwrap();
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", flat(&o.stderr));
        assert!(
            flat(&o.stderr).contains(says),
            "{args:?}: {}",
            flat(&o.stderr)
        );
        assert!(!out.exists(), "{args:?}");
    }
}
