//! `rfeid identify --data` with CSV, MAT and UFF files of the same signals
//! gives the same estimates; a damaged file is bad input (exit 2, no output).
use crate::support;

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
        .arg(model_file(&data.file_name().unwrap().to_string_lossy()))
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
    support::estimate_bits(&v)
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

/// signals.csv as an acquisition system writes it: semicolons, the columns
/// shuffled, an extra force channel, float32 time stamps printed in full.
fn daq_text() -> String {
    let text = std::fs::read_to_string(fixtures().join("signals.csv")).unwrap();
    let mut out = String::from("force;acc_x;time;disp_x;vel_x\n");
    for line in text.lines().skip(1) {
        let f: Vec<f64> = line.split(',').map(|x| x.parse().unwrap()).collect();
        let force = 100.0 * (2.0 * std::f64::consts::PI * 30.0 * f[0]).sin();
        let t32 = f[0] as f32 as f64;
        out += &format!("{force};{};{t32};{};{}\n", f[3], f[1], f[2]);
    }
    out
}

#[test]
fn a_daq_file_gives_the_estimates_of_the_clean_csv_with_a_note() {
    let daq = scratch("daq.csv");
    std::fs::write(&daq, daq_text()).unwrap();
    assert_eq!(estimates(&daq), estimates(&fixtures().join("signals.csv")));
    // The ignored column is named on the terminal.
    let result = scratch("daq-note.json");
    let out = rfeid()
        .arg("identify")
        .arg(model_file("note"))
        .arg("--data")
        .arg(&daq)
        .arg("-o")
        .arg(&result)
        .args(["--plan", "4"])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        out.status.code().is_some_and(|c| c == 0 || c == 3),
        "{stderr}"
    );
    assert!(
        stderr.contains(&format!(
            "note: {}: column 'force' read by no sensor, ignored",
            daq.display()
        )),
        "{stderr}"
    );
}

#[test]
fn lab_file_errors_exit_2_naming_file_and_field_without_output() {
    let daq = daq_text();
    let cases = [
        (
            "comma.csv",
            daq.replace('.', ","),
            "line 3, column 'force': '18,73813145857246' has a decimal comma",
        ),
        (
            "halfrate.csv",
            daq.lines()
                .enumerate()
                .filter(|(i, _)| i % 2 == 0 || *i == 0)
                .map(|(_, l)| format!("{l}\n"))
                .collect::<String>(),
            "the data are sampled at 500 Hz, but the model samples at 1000 Hz",
        ),
    ];
    for (name, text, expect) in cases {
        let data = scratch(name);
        std::fs::write(&data, text).unwrap();
        let result = scratch(&format!("{name}.json"));
        let out = rfeid()
            .arg("identify")
            .arg(model_file(name))
            .arg("--data")
            .arg(&data)
            .arg("-o")
            .arg(&result)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{stderr}");
        // The message as one line: the terminal's wrapping undone.
        let flat = stderr
            .replace('│', " ")
            .split_whitespace()
            .collect::<Vec<_>>()
            .join(" ");
        assert!(flat.contains(&data.display().to_string()), "{stderr}");
        assert!(flat.contains(expect), "{name}: {stderr}");
        assert!(!result.exists(), "{name}");
    }
}
