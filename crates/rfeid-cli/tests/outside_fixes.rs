//! Findings of the outside test of 2026-11-27 ("WRONG"): `design
//! --threads` checked as identify's, `design --set` refused where it would
//! be ignored or overridden, and `simulate --noise` beyond what `identify`
//! reads refused, each with exit status 2 and nothing written.
use crate::support;

use std::path::Path;
use support::*;

/// Runs `rfeid COMMAND MODEL ARGS…`; (exit status, standard error on one
/// line).
fn run(command: &str, model: &Path, args: &[&str]) -> (Option<i32>, String) {
    let o = rfeid().arg(command).arg(model).args(args).output().unwrap();
    (o.status.code(), flat(&o.stderr))
}

#[test]
fn design_threads_out_of_range_is_refused() {
    let dir = scratch_dir("design-threads");
    let out = dir.join("design.json");
    let model = example_model("knee-column");
    for t in ["0", "1025", "99999999999"] {
        let (code, err) = run(
            "design",
            &model,
            &["--threads", t, "-o", out.to_str().unwrap()],
        );
        assert_eq!(code, Some(2), "--threads {t}: {err}");
        assert!(
            err.contains(&format!("--threads {t}: must be 1 to 1024")),
            "{err}"
        );
        assert!(!out.exists(), "--threads {t} wrote {}", out.display());
    }
}

#[test]
fn design_set_of_a_campaign_parameter_is_refused() {
    let model = example_model("knee-column-campaign");
    let (code, err) = run("design", &model, &["--threads", "1", "--set", "P0=1 daN"]);
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("P0 is set by the experiment"), "{err}");
}

#[test]
fn design_set_given_twice_is_refused() {
    let model = example_model("knee-column");
    let (code, err) = run(
        "design",
        &model,
        &[
            "--threads",
            "1",
            "--set",
            "a_n1=380 daN/um^2",
            "--set",
            "a_n1=400 daN/um^2",
        ],
    );
    assert_eq!(code, Some(2), "{err}");
    assert!(
        err.contains("a_n1 is already set by --set 'a_n1=380"),
        "{err}"
    );
}

#[test]
fn simulate_noise_beyond_readable_data_is_refused() {
    let dir = scratch_dir("simulate-big-noise");
    let out = dir.join("big.csv");
    let model = example_model("knee-column");
    let (code, err) = run(
        "simulate",
        &model,
        &[
            "-o",
            out.to_str().unwrap(),
            "--noise",
            "1e160",
            "--seed",
            "1",
        ],
    );
    assert_eq!(code, Some(2), "{err}");
    assert!(
        err.contains("--noise") && err.contains("overflows"),
        "{err}"
    );
    assert!(!out.exists());
}

/// One body whose x spring is two parameters that act only as their sum
/// (k1 + k2), and one candidate: F is singular whatever is chosen.
const SINGULAR_MODEL: &str = "[simulation]\n\
         duration = 0.1\n\
         sample_rate = 1000.0\n\
         substeps = 20\n\
         \n\
         [[body]]\n\
         name = \"mass\"\n\
         mass = 10.0\n\
         inertia = [0.1, 0.2, 0.3]\n\
         com = [0.0, 0.0, 0.0]\n\
         \n\
         [[parameter]]\n\
         name = \"k1\"\n\
         value = 1.0e5\n\
         min = 0.5e5\n\
         max = 2.0e5\n\
         \n\
         [[parameter]]\n\
         name = \"k2\"\n\
         value = 1.0e5\n\
         min = 0.5e5\n\
         max = 2.0e5\n\
         \n\
         [[element]]\n\
         name = \"e1\"\n\
         body = \"mass\"\n\
         to = \"ground\"\n\
         at = [0.0, 0.0, 0.0]\n\
         ux = { k = \"k1\", c = 20.0 }\n\
         uy = { k = 1e5, c = 20.0 }\n\
         uz = { k = 1e5, c = 20.0 }\n\
         rx = { k = 1e4, c = 2.0 }\n\
         ry = { k = 1e4, c = 2.0 }\n\
         rz = { k = 1e4, c = 2.0 }\n\
         \n\
         [[element]]\n\
         name = \"e2\"\n\
         body = \"mass\"\n\
         to = \"ground\"\n\
         at = [0.0, 0.0, 0.0]\n\
         ux = { k = \"k2\" }\n\
         \n\
         [[excitation]]\n\
         body = \"mass\"\n\
         at = [0.0, 0.0, 0.0]\n\
         direction = [1, 0, 0]\n\
         signal = { type = \"sine\", amplitude = 100.0, frequency = 25.0 }\n\
         \n\
         [[sensor]]\n\
         name = \"ax\"\n\
         body = \"mass\"\n\
         at = [0.0, 0.0, 0.0]\n\
         direction = [1, 0, 0]\n\
         quantity = \"acceleration\"\n\
         noise = \"1e-3 m/s^2\"\n\
         \n\
         [[sensor]]\n\
         name = \"cand_y\"\n\
         body = \"mass\"\n\
         at = [0.0, 0.0, 0.0]\n\
         direction = [0, 1, 0]\n\
         quantity = \"acceleration\"\n\
         noise = \"1e-3 m/s^2\"\n\
         candidate = true\n";

#[test]
fn design_over_box_with_a_singular_fisher_matrix_says_so() {
    let dir = scratch_dir("design-singular");
    let model = dir.join("base.toml");
    std::fs::write(&model, SINGULAR_MODEL).unwrap();
    let o = rfeid()
        .args(["design".as_ref(), model.as_os_str()])
        .args(["--threads", "1", "--choose", "1", "--over-box", "8"])
        .output()
        .unwrap();
    let out = String::from_utf8_lossy(&o.stdout);
    assert_eq!(o.status.code(), Some(0), "{}", flat(&o.stderr));
    for bad in ["NaN", "= -inf", "above inf", "number inf", "e^", "0.0000"] {
        assert!(!out.contains(bad), "'{bad}' in:\n{out}");
    }
    assert!(out.contains("8 of 8 points would choose it"), "{out}");
    assert!(out.contains("singular at 8 of 8 points"), "{out}");
    assert!(out.contains("k1, k2 cannot be told apart"), "{out}");
}
