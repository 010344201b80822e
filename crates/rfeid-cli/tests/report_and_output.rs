//! `--report`, `rfeid report`, `simulate --plot`, `--json` and `--quiet`.
use crate::support;

use std::path::{Path, PathBuf};
use support::{flat, identify, oscillator_model, rfeid, scratch_dir, simulate_csv};

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("rfeid-cli-report-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// The report written by `demo --report` is rebuilt byte for byte by
/// `rfeid report RESULT.json` from the sources the result records.
#[test]
fn report_from_result_json_equals_the_demo_report() {
    let (result, dir1, dir2) = (scratch("r.json"), scratch("rep1"), scratch("rep2"));
    let st = rfeid()
        .args([
            "demo", "--plan", "8", "--noise", "0.02", "--seed", "3", "-q", "-o",
        ])
        .arg(&result)
        .arg("--report")
        .arg(&dir1)
        .status()
        .unwrap();
    assert!(st.success());
    let st = rfeid()
        .arg("report")
        .arg(&result)
        .arg("-o")
        .arg(&dir2)
        .arg("-q")
        .status()
        .unwrap();
    assert!(st.success());
    let a = std::fs::read(dir1.join("report.html")).unwrap();
    let b = std::fs::read(dir2.join("report.html")).unwrap();
    assert!(a == b, "the rebuilt report differs");
    let html = String::from_utf8(a).unwrap();
    for section in [
        "Identifiability warnings",
        "Measured and model response",
        "Residuals",
        "plan",
        "Correlation",
    ] {
        assert!(html.contains(section), "missing section {section}");
    }
    assert!(dir1.join("correlation.svg").exists());
}

/// `--json` prints parseable JSON; `--quiet` prints nothing on stderr.
#[test]
fn json_and_quiet() {
    let model = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/knee-column/model.toml");
    let out = rfeid()
        .arg("check")
        .arg(&model)
        .arg("--json")
        .output()
        .unwrap();
    assert!(out.status.success());
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("valid JSON");
    assert_eq!(v["degrees_of_freedom"], 12);
    let (csv, svg) = (scratch("s.csv"), scratch("s.svg"));
    let out = rfeid()
        .arg("simulate")
        .arg(&model)
        .arg("-o")
        .arg(&csv)
        .arg("--plot")
        .arg(&svg)
        .arg("-q")
        .output()
        .unwrap();
    assert!(out.status.success());
    assert!(
        out.stderr.is_empty(),
        "--quiet printed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let plot = std::fs::read_to_string(&svg).unwrap();
    assert!(plot.starts_with("<svg") && plot.contains("knee_az"));
}

/// `rfeid report` refuses a model file, signal table or data file that
/// changed since the identification (the report would draw the old fit
/// table beside the new signals), naming the file and writing nothing; the
/// unchanged files give the report.
#[test]
fn report_refuses_inputs_changed_since_the_fit() {
    let dir = scratch_dir("report-changed");
    let model = oscillator_model(&dir);
    let data = simulate_csv(&dir, &model);
    let result = dir.join("r.json");
    let o = identify(&model, &data, &result)
        .args(["--plan", "4", "-q"])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", flat(&o.stderr));
    let report = |name: &str| {
        rfeid()
            .arg("report")
            .arg(&result)
            .arg("-o")
            .arg(dir.join(name))
            .output()
            .unwrap()
    };
    assert!(report("rep-same").status.success());
    let original = std::fs::read(&data).unwrap();
    for (file, edit) in [(&data, "data.csv"), (&model, "oscillator.toml")] {
        let before = std::fs::read(file).unwrap();
        let mut changed = before.clone();
        changed.extend_from_slice(b"\n");
        std::fs::write(file, &changed).unwrap();
        let o = report("rep-changed");
        let msg = flat(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{edit}: {msg}");
        assert!(
            msg.contains(&format!("{edit} changed")) && msg.contains("r.json"),
            "{msg}"
        );
        assert!(!dir.join("rep-changed").exists());
        std::fs::write(file, &before).unwrap();
    }
    assert_eq!(std::fs::read(&data).unwrap(), original);
    assert!(report("rep-restored").status.success());
}
