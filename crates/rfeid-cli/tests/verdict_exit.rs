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

/// Coloured noise (`simulate --noise-corner`) on a correct model: the
/// default autoregressive noise model leaves white residuals, so the result
/// is trustworthy (exit 0) with each sensor's noise model in RESULT.json;
/// the same data with `--noise-model white` fail the whiteness test at a
/// minimum the starts agree on: the white noise model is the model error
/// (exit 4).
#[test]
fn coloured_noise_is_trustworthy_with_the_noise_model_and_suspect_without() {
    let (data, result) = (scratch("coloured.csv"), scratch("coloured.json"));
    let st = rfeid()
        .arg("simulate")
        .arg(knee_column())
        .arg("-o")
        .arg(&data)
        .args(["--noise", "0.02", "--noise-corner", "1000", "--seed", "2"])
        .output()
        .unwrap();
    assert!(
        st.status.success(),
        "{}",
        String::from_utf8_lossy(&st.stderr)
    );
    let run = |extra: &[&str]| {
        rfeid()
            .arg("identify")
            .arg(knee_column())
            .arg("--data")
            .arg(&data)
            .arg("-o")
            .arg(&result)
            .arg("-q")
            .args(extra)
            .output()
            .unwrap()
    };
    let out = run(&[]);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let r: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&result).unwrap()).unwrap();
    let noise = r["noise"].as_array().expect("the noise models");
    assert_eq!(noise.len(), 3);
    assert!(
        noise.iter().all(|n| n["order"].as_u64().unwrap() > 0),
        "{noise:?}"
    );
    assert_eq!(r["std_errors_cover"], "noise");
    let out = run(&["--noise-model", "white"]);
    assert_eq!(
        out.status.code(),
        Some(4),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v = verdict(&result);
    let kinds: Vec<&str> = v["reasons"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| r["kind"].as_str().unwrap())
        .collect();
    assert!(kinds.contains(&"not_white"), "{kinds:?}");
}

/// A one-body oscillator, `k` and `c` identified on log scales over wide
/// boxes, driven by a 30 Hz sine; `cubic` adds a hardening spring the
/// identified model lacks.
fn oscillator(cubic: Option<f64>) -> String {
    let mut text = String::from(
        "[simulation]\nduration = 1.0\nsample_rate = 1000.0\n\n\
         [[body]]\nname = \"mass\"\nmass = 2.0\ninertia = [0.1, 0.2, 0.3]\ncom = [0.0, 0.0, 0.0]\n\n\
         [[parameter]]\nname = \"k\"\nvalue = 1.6e5\nmin = 2.0e4\nmax = 1.0e6\nscale = \"log\"\n\n\
         [[parameter]]\nname = \"c\"\nvalue = 30.0\nmin = 1.0\nmax = 1000.0\nscale = \"log\"\n\n\
         [[element]]\nname = \"spring\"\nbody = \"mass\"\nto = \"ground\"\nat = [0.0, 0.0, 0.0]\nux = { k = \"k\", c = \"c\" }\n\n\
         [[excitation]]\nbody = \"mass\"\nat = [0.0, 0.0, 0.0]\ndirection = [1, 0, 0]\n\
         signal = { type = \"sine\", amplitude = 100.0, frequency = 30.0 }\n\n\
         [[sensor]]\nname = \"disp_x\"\nbody = \"mass\"\nat = [0.0, 0.0, 0.0]\ndirection = [1, 0, 0]\nquantity = \"displacement\"\n",
    );
    if let Some(a) = cubic {
        text += &format!(
            "\n[[element]]\nname = \"cubic\"\nbody = \"mass\"\nto = \"ground\"\nat = [0.0, 0.0, 0.0]\nux = {{ law = \"power\", a = {a:e}, m = 3.0 }}\n"
        );
    }
    text
}

/// Data of an oscillator with a hardening spring, identified with a linear
/// one: the starts agree on the minimum, the misfit (the third harmonic)
/// follows the input's cube, the verdict names model error alone (exit 4),
/// the standard errors are labelled as covering the noise only, and the hint
/// does not send the user to a larger plan.
#[test]
fn a_missing_nonlinearity_exits_4_naming_model_error() {
    let (truth, model) = (scratch("cubic.toml"), scratch("linear.toml"));
    std::fs::write(&truth, oscillator(Some(5e10))).unwrap();
    std::fs::write(&model, oscillator(None)).unwrap();
    let (data, result) = (scratch("cubic.csv"), scratch("cubic.json"));
    let st = rfeid()
        .arg("simulate")
        .arg(&truth)
        .arg("-o")
        .arg(&data)
        .args(["--noise", "0.01", "--seed", "1", "-q"])
        .output()
        .unwrap();
    assert!(
        st.status.success(),
        "{}",
        String::from_utf8_lossy(&st.stderr)
    );
    let out = rfeid()
        .arg("identify")
        .arg(&model)
        .arg("--data")
        .arg(&data)
        .arg("-o")
        .arg(&result)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(
        out.status.code(),
        Some(4),
        "{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(stdout.contains("model error:"), "{stdout}");
    assert!(stdout.contains("std. error (noise only)"), "{stdout}");
    assert!(!stdout.contains("a larger plan with more"), "{stdout}");
    let r: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&result).unwrap()).unwrap();
    assert_eq!(r["std_errors_cover"], "noise_only");
    let kinds: Vec<&str> = r["verdict"]["reasons"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| r["kind"].as_str().unwrap())
        .collect();
    assert_eq!(kinds[0], "model_error", "{kinds:?}");
}
