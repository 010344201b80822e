//! Bad input gets a clear message, exit status 2 and no output file
//! (issue: identification acceptance, "bad input").
use std::path::{Path, PathBuf};
use std::process::Command;

fn rfeid() -> Command {
    Command::new(env!("CARGO_BIN_EXE_rfeid"))
}

fn example() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/knee-column/model.toml")
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("rfeid-bad-input-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// Simulated data of the example, as CSV text.
fn example_data() -> String {
    let out = scratch("good.csv");
    let st = rfeid()
        .args(["simulate"])
        .arg(example())
        .arg("-o")
        .arg(&out)
        .status()
        .unwrap();
    assert!(st.success());
    std::fs::read_to_string(out).unwrap()
}

/// Runs `identify` on `csv` and checks exit status 2, the message, and that
/// no result file appears.
fn identify_fails(csv: &str, args: &[&str], expect: &str) {
    let data = scratch(&format!("data-{}.csv", expect.len()));
    std::fs::write(&data, csv).unwrap();
    let result = scratch(&format!("result-{}.json", expect.len()));
    let _ = std::fs::remove_file(&result);
    let out = rfeid()
        .arg("identify")
        .arg(example())
        .arg("--data")
        .arg(&data)
        .arg("-o")
        .arg(&result)
        .args(args)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "stderr: {stderr}");
    // The message as one line: the terminal's wrapping undone.
    let flat = stderr
        .replace('│', " ")
        .split_whitespace()
        .collect::<Vec<_>>()
        .join(" ");
    assert!(flat.contains(expect), "expected '{expect}' in: {stderr}");
    assert!(!result.exists(), "no partial output file");
}

#[test]
fn data_errors_exit_2_without_output() {
    let good = example_data();
    identify_fails(&good.replacen("knee_ay", "knee_yy", 1), &[], "knee_yy");
    let missing: String = good
        .lines()
        .map(|l| l.rsplit_once(',').unwrap().0.to_string() + "\n")
        .collect();
    identify_fails(&missing, &[], "no column for sensor 'knee_az'");
    let comma: String = good
        .lines()
        .map(|l| l.replace(',', ";").replace('.', ",") + "\n")
        .collect();
    identify_fails(
        &comma,
        &[],
        "has a decimal comma; rfeid reads numbers with a decimal point: export the file with '.' as the decimal separator",
    );
    let lines: Vec<&str> = good.lines().collect();
    identify_fails(
        &(lines[..1500].join("\n") + "\n"),
        &[],
        "the data has 1499 samples",
    );
    let mut nan = lines.clone();
    let bad = nan[10].replacen(",", ",NaN,", 1);
    let bad = bad
        .split(',')
        .filter(|s| !s.is_empty())
        .take(4)
        .collect::<Vec<_>>()
        .join(",");
    nan[10] = &bad;
    identify_fails(&(nan.join("\n") + "\n"), &[], "not a finite number");
    let slow: String = lines
        .iter()
        .enumerate()
        .map(|(i, l)| {
            if i == 0 {
                format!("{l}\n")
            } else {
                let (t, rest) = l.split_once(',').unwrap();
                format!("{},{rest}\n", t.parse::<f64>().unwrap() * 2.0)
            }
        })
        .collect();
    identify_fails(&slow, &[], "the data are sampled at 5000 Hz,");
    identify_fails(&good, &["--plan", "0"], "--plan 0");
    // Regression: --from near the end of the record underflowed the sample
    // count (or fitted nothing and exited 0).
    identify_fails(
        &good,
        &["--from", "0.29995"],
        "leaves 0 of the record's 3000 samples",
    );
    identify_fails(
        &good,
        &["--from", "0.2999"],
        "leaves 1 of the record's 3000 samples",
    );
}

#[test]
fn a_model_without_identified_parameters_exits_2() {
    let text = std::fs::read_to_string(example()).unwrap();
    // Fix every parameter: drop the boxes.
    let fixed: String = text
        .lines()
        .filter(|l| !l.starts_with("min =") && !l.starts_with("max ="))
        .map(|l| format!("{l}\n"))
        .collect();
    let model = scratch("fixed.toml");
    std::fs::write(&model, fixed).unwrap();
    let data = scratch("fixed.csv");
    assert!(rfeid()
        .arg("simulate")
        .arg(&model)
        .arg("-o")
        .arg(&data)
        .status()
        .unwrap()
        .success());
    let result = scratch("fixed.json");
    let out = rfeid()
        .arg("identify")
        .arg(&model)
        .arg("--data")
        .arg(&data)
        .arg("-o")
        .arg(&result)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("no identified parameters"));
    assert!(!result.exists());
}

#[test]
fn model_errors_name_file_entry_and_field() {
    let text = std::fs::read_to_string(example()).unwrap();
    let model = scratch("bad.toml");
    std::fs::write(&model, text.replace("mass = \"320 kg\"", "mass = -320.0")).unwrap();
    let out_csv = scratch("never.csv");
    let out = rfeid()
        .arg("simulate")
        .arg(&model)
        .arg("-o")
        .arg(&out_csv)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr.contains("bad.toml") && stderr.contains("body \"knee\"") && stderr.contains("mass"),
        "{stderr}"
    );
    assert!(!out_csv.exists());
}
