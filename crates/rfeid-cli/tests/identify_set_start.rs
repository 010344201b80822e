//! `identify --set NAME=VALUE` fixes a parameter for one run, exactly as a
//! model file without its box would; `--start values` runs one local search
//! from the parameters' values instead of the plan. Their misuse is bad
//! input (exit 2, no output).
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn rfeid() -> Command {
    Command::new(env!("CARGO_BIN_EXE_rfeid"))
}

fn signals() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../rfeid/tests/data/import/signals.csv")
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("rfeid-cli-set-start-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// The oscillator behind signals.csv (m = 2 kg, k = 2e5 N/m, c = 40 N·s/m);
/// k identified from `k0`, c as `c_entry` says.
fn model_file(tag: &str, k0: f64, c_entry: &str) -> PathBuf {
    let mut text = format!(
        "[simulation]\nduration = 0.05\nsample_rate = 1000.0\nsubsteps = 20\n\n\
         [[body]]\nname = \"mass\"\nmass = 2.0\ninertia = [0.1, 0.2, 0.3]\ncom = [0.0, 0.0, 0.0]\n\n\
         [[parameter]]\nname = \"k\"\nvalue = {k0:e}\nmin = 1.0e5\nmax = 3.0e5\n\n\
         [[parameter]]\nname = \"c\"\n{c_entry}\n\n\
         [[element]]\nname = \"spring\"\nbody = \"mass\"\nto = \"ground\"\nat = [0.0, 0.0, 0.0]\nux = {{ k = \"k\", c = \"c\" }}\n\n\
         [[excitation]]\nbody = \"mass\"\nat = [0.0, 0.0, 0.0]\ndirection = [1, 0, 0]\n\
         signal = {{ type = \"sine\", amplitude = 100.0, frequency = 30.0 }}\n"
    );
    for (name, kind) in [
        ("disp_x", "displacement"),
        ("vel_x", "velocity"),
        ("acc_x", "acceleration"),
    ] {
        text += &format!(
            "\n[[sensor]]\nname = \"{name}\"\nbody = \"mass\"\nat = [0.0, 0.0, 0.0]\ndirection = [1, 0, 0]\nquantity = \"{kind}\"\n"
        );
    }
    let path = scratch(&format!("{tag}.toml"));
    std::fs::write(&path, text).unwrap();
    path
}

const C_BOX: &str = "value = 30.0\nmin = 10.0\nmax = 80.0";

fn identify(model: &Path, tag: &str, args: &[&str]) -> (Output, PathBuf) {
    let result = scratch(&format!("{tag}.json"));
    let _ = std::fs::remove_file(&result);
    let out = rfeid()
        .arg("identify")
        .arg(model)
        .arg("--data")
        .arg(signals())
        .arg("-o")
        .arg(&result)
        .args(args)
        .output()
        .unwrap();
    (out, result)
}

fn json(path: &Path) -> serde_json::Value {
    serde_json::from_slice(&std::fs::read(path).unwrap()).unwrap()
}

#[test]
fn set_fixes_a_parameter_as_the_model_file_would() {
    let boxed = model_file("boxed", 1.6e5, C_BOX);
    let (out, with_set) = identify(&boxed, "with-set", &["--set", "c=40 N*s/m", "--plan", "8"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        out.status.code().is_some_and(|c| c == 0 || c == 3),
        "{stderr}"
    );
    let fixed = model_file("fixed", 1.6e5, "value = 40.0");
    let (out, in_file) = identify(&fixed, "in-file", &["--plan", "8"]);
    assert!(out.status.code().is_some_and(|c| c == 0 || c == 3));
    let (a, b) = (json(&with_set), json(&in_file));
    let names: Vec<&str> = a["parameters"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p["name"].as_str().unwrap())
        .collect();
    assert_eq!(names, ["k"]);
    assert_eq!(
        a["parameters"][0]["estimate"].as_f64().unwrap().to_bits(),
        b["parameters"][0]["estimate"].as_f64().unwrap().to_bits()
    );
    let k = a["parameters"][0]["estimate"].as_f64().unwrap();
    assert!((k / 2.0e5 - 1.0).abs() < 1e-6, "k = {k}");
    assert_eq!(a["source"]["set"], serde_json::json!(["c=40 N*s/m"]));
    assert!(b["source"].get("set").is_none());
    // The report applies the setting again.
    let dir = scratch("report");
    let out = rfeid()
        .arg("report")
        .arg(&with_set)
        .arg("-o")
        .arg(&dir)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn start_values_searches_once_from_the_values_without_the_plan() {
    let model = model_file("values", 1.9e5, C_BOX);
    let (out, result) = identify(&model, "values", &["--start", "values", "--plan", "500"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        out.status.code().is_some_and(|c| c == 0 || c == 3),
        "{stderr}"
    );
    let r = json(&result);
    assert_eq!(r["plan"]["points"], 1, "{}", r["plan"]);
    let k = r["parameters"][0]["estimate"].as_f64().unwrap();
    let c = r["parameters"][1]["estimate"].as_f64().unwrap();
    assert!((k / 2.0e5 - 1.0).abs() < 1e-6, "k = {k}");
    assert!((c / 40.0 - 1.0).abs() < 1e-4, "c = {c}");
    // Far fewer simulations than a plan of 500 points.
    assert!(
        r["simulations"].as_u64().unwrap() < 100,
        "{}",
        r["simulations"]
    );
}

#[test]
fn misuse_exits_2_without_output() {
    let model = model_file("misuse", 1.6e5, C_BOX);
    for (args, expect) in [
        (
            &["--set", "q=1"][..],
            "--set: unknown parameter 'q' (parameters: k, c)",
        ),
        (
            &["--set", "c=40 N"][..],
            "--set c: '40 N' has the dimension",
        ),
        (&["--set", "c"][..], "--set 'c': expected NAME=VALUE"),
        (
            &["--start", "values", "--starts", "2"][..],
            "--starts 2 with a start from the values",
        ),
        (
            &["--set", "c=40", "--shard", "0/2"][..],
            "--set or --start values with --shard",
        ),
        (
            &["--set", "c=40", "--set", "c=50"][..],
            "--set 'c=50': c is already set by --set 'c=40'; give each parameter once",
        ),
        (
            &["--shard", "-1/3"][..],
            "--shard '-1/3': expected K/N with 0 <= K < N",
        ),
        (
            &["--tolerance", "0.00000000000001"][..],
            "--tolerance 1e-14: must be",
        ),
    ] {
        let (out, result) = identify(&model, "misuse", args);
        let stderr = String::from_utf8_lossy(&out.stderr);
        let flat = stderr
            .replace('│', " ")
            .split_whitespace()
            .collect::<Vec<_>>()
            .join(" ");
        assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(flat.contains(expect), "{args:?}: {stderr}");
        assert!(!result.exists(), "{args:?}");
    }
}
