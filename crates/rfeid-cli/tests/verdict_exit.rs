//! A suspect result is written, printed with its reasons, and ends with exit
//! status 3; a trustworthy one exits 0.
use std::path::{Path, PathBuf};
use std::process::Command;

fn rfeid() -> Command {
    Command::new(env!("CARGO_BIN_EXE_rfeid"))
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("rfeid-cli-verdict-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

fn knee_column() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/knee-column/model.toml")
}

fn verdict(path: &Path) -> serde_json::Value {
    let text = std::fs::read_to_string(path).expect("the result is written");
    let r: serde_json::Value = serde_json::from_str(&text).expect("JSON");
    r["verdict"].clone()
}

/// Data made with a_t4 = 60 daN/µm, outside its box (13.5–40.5): the
/// estimate ends on the upper bound, the result is written all the same, and
/// the exit status is 3.
#[test]
fn a_truth_outside_the_box_exits_3_with_the_result_written() {
    let (data, result) = (scratch("outside.csv"), scratch("outside.json"));
    let st = rfeid()
        .arg("simulate")
        .arg(knee_column())
        .arg("-o")
        .arg(&data)
        .args(["--set", "a_t4=60 daN/um", "--noise", "0.01", "--seed", "1"])
        .output()
        .unwrap();
    assert!(
        st.status.success(),
        "{}",
        String::from_utf8_lossy(&st.stderr)
    );
    let out = rfeid()
        .arg("identify")
        .arg(knee_column())
        .arg("--data")
        .arg(&data)
        .arg("-o")
        .arg(&result)
        .args(["--plan", "16", "-q"])
        .output()
        .unwrap();
    assert_eq!(
        out.status.code(),
        Some(3),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.contains("verdict: SUSPECT"), "{stdout}");
    assert!(stdout.contains("a_t4 is on its upper bound"), "{stdout}");
    assert!(String::from_utf8_lossy(&out.stderr).contains("the result is suspect"));
    let v = verdict(&result);
    assert_eq!(v["trustworthy"], false);
    let on_bound = v["reasons"]
        .as_array()
        .unwrap()
        .iter()
        .any(|r| r["kind"] == "at_bound" && r["parameter"] == "a_t4" && r["side"] == "upper");
    assert!(on_bound, "{v}");
}

/// The noisy demo at the truth is trustworthy: exit 0, and the JSON says so.
#[test]
fn the_noisy_demo_is_trustworthy() {
    let result = scratch("demo.json");
    let out = rfeid()
        .args(["demo", "--noise", "0.02", "--seed", "3", "-q", "-o"])
        .arg(&result)
        .output()
        .unwrap();
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stdout)
    );
    assert!(String::from_utf8_lossy(&out.stdout).contains("verdict: trustworthy"));
    let v = verdict(&result);
    assert_eq!(v["trustworthy"], true);
    assert_eq!(v["sensors"].as_array().unwrap().len(), 3);
}

/// `--window` outside [0, 1) is bad input, before any output is written.
#[test]
fn a_window_outside_the_unit_interval_is_bad_input() {
    for w in ["1", "-0.1", "1.5"] {
        let result = scratch(&format!("window{w}.json"));
        let out = rfeid()
            .args(["demo", "-q", &format!("--window={w}"), "-o"])
            .arg(&result)
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(2), "--window {w}");
        assert!(String::from_utf8_lossy(&out.stderr).contains("--window"));
        assert!(!result.exists());
    }
}
