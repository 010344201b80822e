//! What the command-line tests share: the binary, scratch folders, a small
//! model and its data.
#![allow(dead_code)]
use std::path::{Path, PathBuf};
use std::process::Command;

/// The binary under test: `RFEID_TEST_BIN` if set, else this build's.
pub fn binary() -> PathBuf {
    std::env::var_os("RFEID_TEST_BIN")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_BIN_EXE_rfeid")))
}

/// A command running the binary under test.
pub fn rfeid() -> Command {
    Command::new(binary())
}

/// `rfeid identify MODEL --data DATA -o OUT`, for further options.
pub fn identify(
    model: impl AsRef<std::ffi::OsStr>,
    data: impl AsRef<std::ffi::OsStr>,
    out: impl AsRef<std::ffi::OsStr>,
) -> Command {
    let mut cmd = rfeid();
    cmd.arg("identify")
        .arg(model)
        .arg("--data")
        .arg(data)
        .arg("-o")
        .arg(out);
    cmd
}

/// The model file of `examples/NAME`.
pub fn example_model(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples")
        .join(name)
        .join("model.toml")
}

/// A new, empty scratch folder for one test.
pub fn scratch_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("rfeid-t-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A one-body oscillator (k and c identified; displacement, velocity and
/// acceleration sensors; 50 samples), written into `dir`.
pub fn oscillator_model(dir: &Path) -> PathBuf {
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
    let path = dir.join("oscillator.toml");
    std::fs::write(&path, text).unwrap();
    path
}

/// Simulates `model` into `dir/data.csv` (noise-free).
pub fn simulate_csv(dir: &Path, model: &Path) -> PathBuf {
    let out = dir.join("data.csv");
    let st = rfeid()
        .arg("simulate")
        .arg(model)
        .arg("-o")
        .arg(&out)
        .arg("-q")
        .status()
        .unwrap();
    assert!(st.success());
    out
}

/// Names of temporaries (`.rfeid-…` or `….tmp…`) anywhere under `dir`.
pub fn temporaries(dir: &Path) -> Vec<String> {
    let mut found = Vec::new();
    let Ok(entries) = std::fs::read_dir(dir) else {
        return found;
    };
    for e in entries.flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        if name.starts_with(".rfeid-") || name.contains(".tmp") {
            found.push(e.path().display().to_string());
        }
        if e.file_type().map(|t| t.is_dir()).unwrap_or(false) {
            found.extend(temporaries(&e.path()));
        }
    }
    found
}

/// A message on one line: miette's wrapping (line breaks, `│` gutters)
/// undone, so that phrases can be searched for.
pub fn flat(stderr: &[u8]) -> String {
    String::from_utf8_lossy(stderr)
        .replace('│', " ")
        .split_whitespace()
        .collect::<Vec<_>>()
        .join(" ")
}

/// Whether an identification finished and wrote its outputs: exit 0, or 3
/// (written, but the verdict is suspect).
pub fn finished(status: std::process::ExitStatus) -> bool {
    matches!(status.code(), Some(0) | Some(3) | Some(4))
}

/// Each estimate of a RESULT.json, by name, as bits (for exact comparisons).
pub fn estimate_bits(result: &serde_json::Value) -> Vec<(String, u64)> {
    result["parameters"]
        .as_array()
        .expect("parameters")
        .iter()
        .map(|p| {
            (
                p["name"].as_str().unwrap().to_string(),
                p["estimate"].as_f64().unwrap().to_bits(),
            )
        })
        .collect()
}
