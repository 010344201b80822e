//! SIGINT at seeded random moments of `identify --report`: afterwards the
//! result and the report are either both the complete old ones or both the
//! complete new ones, and no temporary file is left.
#![cfg(unix)]
use crate::support;

use std::path::{Path, PathBuf};
use std::time::Instant;
use support::{finished, flat, oscillator_model, rfeid, scratch_dir, simulate_csv, temporaries};

/// Interruptions tried.
const TRIES: usize = 16;

/// Runs `identify` with data file `data` into `dir`; returns the child.
fn start(dir: &Path, model: &Path, data: &Path) -> std::process::Child {
    rfeid()
        .arg("identify")
        .arg(model)
        .arg("--data")
        .arg(data)
        .arg("-o")
        .arg(dir.join("result.json"))
        .arg("--report")
        .arg(dir.join("report"))
        .args(["--plan", "64", "-q", "--threads", "1"])
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap()
}

/// The outputs' state: which data file the result names and which the
/// report's title names, after checking the report is complete.
fn state(dir: &Path, figures: &[String]) -> (String, String) {
    let json = std::fs::read_to_string(dir.join("result.json")).expect("a result");
    let v: serde_json::Value = serde_json::from_str(&json).expect("a complete result");
    let data = v["source"]["data"].as_str().unwrap().to_string();
    let html = std::fs::read_to_string(dir.join("report/report.html")).expect("a report");
    assert!(html.trim_end().ends_with("</html>"), "a truncated report");
    let mut names: Vec<String> = std::fs::read_dir(dir.join("report"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(names, figures, "the report's files");
    let titled = ["old.csv", "new.csv"]
        .into_iter()
        .find(|n| html.contains(n))
        .unwrap_or("neither")
        .to_string();
    (data, titled)
}

fn file_name(p: &Path) -> String {
    p.file_name().unwrap().to_string_lossy().into_owned()
}

#[test]
fn sigint_leaves_old_or_new_outputs_whole_and_no_temporaries() {
    let dir = scratch_dir("interruption");
    let model = oscillator_model(&dir);
    let data = simulate_csv(&dir, &model);
    let (old, new): (PathBuf, PathBuf) = (dir.join("old.csv"), dir.join("new.csv"));
    std::fs::copy(&data, &old).unwrap();
    std::fs::copy(&data, &new).unwrap();
    let out = dir.join("out");
    std::fs::create_dir(&out).unwrap();
    // The old outputs, kept aside to restore before each try.
    assert!(finished(start(&out, &model, &old).wait().unwrap()));
    let mut figures: Vec<String> = std::fs::read_dir(out.join("report"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    figures.sort();
    let saved = dir.join("saved");
    std::fs::create_dir(&saved).unwrap();
    std::fs::copy(out.join("result.json"), saved.join("result.json")).unwrap();
    std::fs::rename(out.join("report"), saved.join("report")).unwrap();
    // How long a new run takes: the shortest of three.
    let full = (0..3)
        .map(|_| {
            let t = Instant::now();
            assert!(finished(start(&out, &model, &new).wait().unwrap()));
            t.elapsed()
        })
        .min()
        .unwrap();
    let mut rng: u64 = 0x1e7e_0010;
    let (mut olds, mut news) = (0, 0);
    for k in 0..TRIES {
        // Restore the old outputs.
        let _ = std::fs::remove_dir_all(out.join("report"));
        std::fs::create_dir(out.join("report")).unwrap();
        for f in &figures {
            std::fs::copy(saved.join("report").join(f), out.join("report").join(f)).unwrap();
        }
        std::fs::copy(saved.join("result.json"), out.join("result.json")).unwrap();
        // A seeded moment between 20 % and 200 % of a full run (the machine
        // may be busier now than when the run was timed).
        rng = rng
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        let frac = 0.2 + 1.8 * ((rng >> 11) as f64 / (1u64 << 53) as f64);
        let delay = full.mul_f64(frac);
        let child = start(&out, &model, &new);
        std::thread::sleep(delay);
        // SAFETY: signalling our own child by its id.
        unsafe { libc::kill(child.id() as i32, libc::SIGINT) };
        let output = child.wait_with_output().unwrap();
        let status = output.status;
        eprintln!("try {k}: SIGINT after {delay:?}: {status:?}");
        assert!(
            finished(status) || status.code() == Some(130),
            "try {k} ({delay:?}): {status:?}"
        );
        let (data, titled) = state(&out, &figures);
        assert_eq!(
            file_name(Path::new(&data)),
            titled,
            "try {k} ({delay:?}): the result and the report come from different runs"
        );
        // An interruption says so, and whether the outputs were written.
        if status.code() == Some(130) {
            let msg = flat(&output.stderr);
            assert!(
                msg.contains("interrupted by SIGINT (exit status 130)"),
                "try {k}: {msg}"
            );
            assert_eq!(
                msg.contains("no output was written"),
                titled == "old.csv",
                "try {k}: {msg}"
            );
        }
        if titled == "old.csv" {
            olds += 1;
        } else {
            news += 1;
        }
        assert_eq!(temporaries(&dir), Vec::<String>::new(), "try {k}");
    }
    eprintln!(
        "{olds} interrupted runs left the old outputs, {news} the new (a run takes {full:?})"
    );
    assert_eq!(olds + news, TRIES);
}
