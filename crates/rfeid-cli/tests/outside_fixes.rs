//! Findings of the outside test of 2026-11-27 ("WRONG"): `design
//! --threads` checked as identify's, `design --set` refused where it would
//! be ignored or overridden, and `simulate --noise` beyond what `identify`
//! reads refused, each with exit status 2 and nothing written.
use crate::support;

use std::path::{Path, PathBuf};
use support::*;

fn example(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("../../examples/{name}/model.toml"))
}

/// Runs rfeid with `args`; (exit status, standard error on one line).
fn run(args: &[&std::ffi::OsStr]) -> (Option<i32>, String) {
    let o = rfeid().args(args).output().unwrap();
    (o.status.code(), flat(&o.stderr))
}

#[test]
fn design_threads_out_of_range_is_refused() {
    let dir = scratch_dir("design-threads");
    let out = dir.join("design.json");
    let model = example("knee-column");
    for t in ["0", "1025", "99999999999"] {
        let (code, err) = run(&[
            "design".as_ref(),
            model.as_os_str(),
            "--threads".as_ref(),
            t.as_ref(),
            "-o".as_ref(),
            out.as_os_str(),
        ]);
        assert_eq!(code, Some(2), "--threads {t}: {err}");
        assert!(err.contains(&format!("--threads {t}: must be 1 to 1024")), "{err}");
        assert!(!out.exists(), "--threads {t} wrote {}", out.display());
    }
}

#[test]
fn design_set_of_a_campaign_parameter_is_refused() {
    let model = example("knee-column-campaign");
    let (code, err) = run(&[
        "design".as_ref(),
        model.as_os_str(),
        "--threads".as_ref(),
        "1".as_ref(),
        "--set".as_ref(),
        "P0=1 daN".as_ref(),
    ]);
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("P0 is set by the experiment"), "{err}");
}

#[test]
fn design_set_given_twice_is_refused() {
    let model = example("knee-column");
    let (code, err) = run(&[
        "design".as_ref(),
        model.as_os_str(),
        "--threads".as_ref(),
        "1".as_ref(),
        "--set".as_ref(),
        "a_n1=380 daN/um^2".as_ref(),
        "--set".as_ref(),
        "a_n1=400 daN/um^2".as_ref(),
    ]);
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("a_n1 is already set by --set 'a_n1=380"), "{err}");
}

#[test]
fn simulate_noise_beyond_readable_data_is_refused() {
    let dir = scratch_dir("simulate-big-noise");
    let out = dir.join("big.csv");
    let model = example("knee-column");
    let (code, err) = run(&[
        "simulate".as_ref(),
        model.as_os_str(),
        "-o".as_ref(),
        out.as_os_str(),
        "--noise".as_ref(),
        "1e160".as_ref(),
        "--seed".as_ref(),
        "1".as_ref(),
    ]);
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("--noise") && err.contains("overflows"), "{err}");
    assert!(!out.exists());
}
