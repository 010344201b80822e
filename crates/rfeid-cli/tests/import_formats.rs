//! `rfeid identify --data` with CSV, MAT and UFF files of the same signals
//! gives the same estimates; a damaged file is bad input (exit 2, no output).
use std::path::{Path, PathBuf};
use std::process::Command;

fn rfeid() -> Command {
    Command::new(env!("CARGO_BIN_EXE_rfeid"))
}

fn fixtures() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../rfeid/tests/data/import")
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("rfeid-cli-import-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// The oscillator behind the fixtures (tools/fixtures/make_import_fixtures.py),
/// k and c identified; sensors named like the files' signals.
fn model_file(tag: &str) -> PathBuf {
    let mut text = String::from(
        "[simulation]\nduration = 0.05\nsample_rate = 1000.0\nsubsteps = 20\n\n\
         [[body]]\nname = \"mass\"\nmass = 2.0\ninertia = [0.1, 0.2, 0.3]\ncom = [0.0, 0.0, 0.0]\n\n\
         [[parameter]]\nname = \"k\"\nvalue = 1.6e5\nmin = 1.0e5\nmax = 3.0e5\n\n\
         [[parameter]]\nname = \"c\"\nvalue = 30.0\nmin = 10.0\nmax = 80.0\n\n\
         [[element]]\nname = \"spring\"\nbody = \"mass\"\nto = \"ground\"\nat = [0.0, 0.0, 0.0]\nux = { k = \"k\", c = \"c\" }\n\n\
         [[excitation]]\nbody = \"mass\"\nat = [0.0, 0.0, 0.0]\ndirection = [1, 0, 0]\n\
         signal = { type = \"sine\", amplitude = 100.0, frequency = 30.0 }\n",
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
    let path = scratch(&format!("oscillator-{tag}.toml"));
    std::fs::write(&path, text).unwrap();
    path
}

fn estimates(data: &Path) -> Vec<(String, u64)> {
    let out_json = scratch(&format!(
        "{}.json",
        data.file_name().unwrap().to_string_lossy()
    ));
    let out = rfeid()
        .arg("identify")
        .arg(model_file("formats"))
        .arg("--data")
        .arg(data)
        .arg("-o")
        .arg(&out_json)
        .args(["--plan", "8", "-q", "--json"])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    v["parameters"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| {
            (
                p["name"].as_str().unwrap().to_string(),
                p["estimate"].as_f64().unwrap().to_bits(),
            )
        })
        .collect()
}

#[test]
fn csv_mat_and_uff_give_identical_estimates() {
    let csv = estimates(&fixtures().join("signals.csv"));
    for f in [
        "signals.mat",
        "signals_compressed.mat",
        "signals_ascii.uff",
        "signals_binary.uff",
    ] {
        assert_eq!(estimates(&fixtures().join(f)), csv, "{f}");
    }
}

#[test]
fn a_truncated_mat_file_exits_2_without_output() {
    let bytes = std::fs::read(fixtures().join("signals.mat")).unwrap();
    let cut = scratch("cut.mat");
    std::fs::write(&cut, &bytes[..bytes.len() / 2]).unwrap();
    let result = scratch("cut.json");
    let out = rfeid()
        .arg("identify")
        .arg(model_file("cut"))
        .arg("--data")
        .arg(&cut)
        .arg("-o")
        .arg(&result)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("cut.mat"), "{stderr}");
    assert!(!result.exists());
}
