//! Regression tests: how outputs are written and how failures stay
//! contained, one test per defect found by the reliability campaign.
//!
//! Set `RFEID_TEST_BIN` to run them against another build of `rfeid` (an
//! older one, to see each test fail without its fix).
#![cfg(unix)]
use crate::support;

use std::path::Path;
use std::time::Duration;
use support::{
    finished, flat, identify, oscillator_model, rfeid, scratch_dir, simulate_csv, temporaries,
};

/// `simulate model.toml -o model.toml` replaced the model; `identify … -o
/// data.csv` replaced the data. Both are refused (exit 2), also through a
/// symbolic link, and the inputs stay as they were.
#[test]
fn an_output_equal_to_an_input_is_refused() {
    let dir = scratch_dir("same-as-input");
    let model = oscillator_model(&dir);
    let data = simulate_csv(&dir, &model);
    let model_text = std::fs::read(&model).unwrap();
    let data_text = std::fs::read(&data).unwrap();
    let out = rfeid()
        .arg("simulate")
        .arg(&model)
        .arg("-o")
        .arg(&model)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2), "{out:?}");
    assert!(flat(&out.stderr).contains("input"));
    let link = dir.join("link.csv");
    std::os::unix::fs::symlink(&data, &link).unwrap();
    for target in [&data, &link] {
        let out = identify(&model, &data, target)
            .args(["--plan", "4", "-q"])
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(2), "{out:?}");
    }
    assert_eq!(std::fs::read(&model).unwrap(), model_text);
    assert_eq!(std::fs::read(&data).unwrap(), data_text);
}

/// `-o` replaced whatever was at the path: a symbolic link became a regular
/// file, a FIFO (or device) was replaced, permissions 0600 became 0644.
/// Now: the link is followed and its target replaced, a FIFO is written
/// into, and permissions survive. A hard link is broken (documented).
#[test]
fn output_keeps_links_special_files_and_permissions() {
    use std::os::unix::fs::PermissionsExt;
    let dir = scratch_dir("keeps");
    let model = oscillator_model(&dir);
    let fresh = simulate_csv(&dir, &model);
    let expected = std::fs::read(&fresh).unwrap();
    let run = |out: &Path| {
        let st = rfeid()
            .arg("simulate")
            .arg(&model)
            .arg("-o")
            .arg(out)
            .arg("-q")
            .status()
            .unwrap();
        assert!(st.success(), "{st:?}");
    };
    // A symbolic link stays a link; its target gets the output.
    let target = dir.join("target.csv");
    std::fs::write(&target, "old").unwrap();
    let link = dir.join("link.csv");
    std::os::unix::fs::symlink("target.csv", &link).unwrap();
    run(&link);
    assert!(std::fs::symlink_metadata(&link)
        .unwrap()
        .file_type()
        .is_symlink());
    assert_eq!(std::fs::read(&target).unwrap(), expected);
    // Permissions survive.
    let private = dir.join("private.csv");
    std::fs::write(&private, "old").unwrap();
    std::fs::set_permissions(&private, std::fs::Permissions::from_mode(0o600)).unwrap();
    run(&private);
    let mode = std::fs::metadata(&private).unwrap().permissions().mode() & 0o777;
    assert_eq!(mode, 0o600);
    assert_eq!(std::fs::read(&private).unwrap(), expected);
    // A FIFO is written into, not replaced.
    let fifo = dir.join("fifo");
    let st = std::process::Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .unwrap();
    assert!(st.success());
    let reader = {
        let fifo = fifo.clone();
        std::thread::spawn(move || std::fs::read(fifo).unwrap())
    };
    run(&fifo);
    assert_eq!(reader.join().unwrap(), expected);
    use std::os::unix::fs::FileTypeExt;
    assert!(std::fs::symlink_metadata(&fifo)
        .unwrap()
        .file_type()
        .is_fifo());
    // A hard link: the path gets the new file, the other name keeps the old.
    let a = dir.join("a.csv");
    let b = dir.join("b.csv");
    std::fs::write(&a, "old").unwrap();
    std::fs::hard_link(&a, &b).unwrap();
    run(&a);
    assert_eq!(std::fs::read(&a).unwrap(), expected);
    assert_eq!(std::fs::read(&b).unwrap(), b"old");
}

/// `identify --report BAD` exited 2 having written the result; `simulate
/// --plot BAD` left the CSV; a report failing part-way left 9 of its 10
/// files. Now nothing is written when any output cannot be.
#[test]
fn no_output_is_left_when_another_output_fails() {
    let dir = scratch_dir("left-on-failure");
    let model = oscillator_model(&dir);
    let data = simulate_csv(&dir, &model);
    let result = dir.join("result.json");
    let not_a_dir = dir.join("file");
    std::fs::write(&not_a_dir, "x").unwrap();
    let out = identify(&model, &data, &result)
        .arg("--report")
        .arg(&not_a_dir)
        .args(["--plan", "4", "-q"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2), "{out:?}");
    assert!(!result.exists(), "the result was written");
    let csv = dir.join("sim.csv");
    let out = rfeid()
        .arg("simulate")
        .arg(&model)
        .arg("-o")
        .arg(&csv)
        .arg("--plot")
        .arg(dir.join("missing/plot.svg"))
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2), "{out:?}");
    assert!(!csv.exists(), "the CSV was written");
    // A report directory where one figure cannot be written (a directory
    // holds its name): nothing of the new report appears.
    let report = dir.join("report");
    std::fs::create_dir_all(report.join("plan.svg")).unwrap();
    let out = identify(&model, &data, &result)
        .arg("--report")
        .arg(&report)
        .args(["--plan", "4", "-q"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2), "{out:?}");
    let names: Vec<_> = std::fs::read_dir(&report)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(names, ["plan.svg"], "the report was partly written");
    assert!(!result.exists(), "the result was written");
    assert_eq!(temporaries(&dir), Vec::<String>::new());
}

/// A missing output directory was found only after the whole
/// identification; `--report` created missing folders and `-o` did not.
/// Now every output is checked first, by one rule: its directory must
/// exist.
#[test]
fn output_locations_are_checked_before_computing() {
    let dir = scratch_dir("checked-first");
    let model = oscillator_model(&dir);
    let data = simulate_csv(&dir, &model);
    for (result, report) in [
        (dir.join("missing/r.json"), None),
        (dir.join("r.json"), Some(dir.join("missing/report"))),
    ] {
        let mut cmd = rfeid();
        cmd.arg("identify")
            .arg(&model)
            .arg("--data")
            .arg(&data)
            .arg("-o")
            .arg(&result)
            .args(["--plan", "4"]);
        if let Some(r) = &report {
            cmd.arg("--report").arg(r);
        }
        let out = cmd.output().unwrap();
        let stderr = flat(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{stderr}");
        assert!(stderr.contains("does not exist"), "{stderr}");
        assert!(
            !stderr.contains("local search"),
            "the identification ran before the check: {stderr}"
        );
        assert!(!dir.join("missing").exists(), "a folder was created");
    }
}

/// Output names of 244–255 bytes were refused because the temporary name
/// added about 12 bytes to them.
#[test]
fn temporary_names_keep_long_names_legal() {
    let dir = scratch_dir("long-names");
    let model = oscillator_model(&dir);
    let name = format!("{}.csv", "n".repeat(251));
    assert_eq!(name.len(), 255);
    let out = rfeid()
        .arg("simulate")
        .arg(&model)
        .arg("-o")
        .arg(dir.join(&name))
        .arg("-q")
        .output()
        .unwrap();
    assert!(out.status.success(), "{out:?}");
    assert!(dir.join(&name).exists());
}

/// A report written over an earlier one kept the earlier one's other
/// figures: folders mixed old and new. Now the folder is replaced whole.
#[test]
fn a_report_replaces_the_old_one_whole() {
    let dir = scratch_dir("report-whole");
    let model = oscillator_model(&dir);
    let data = simulate_csv(&dir, &model);
    let report = dir.join("report");
    std::fs::create_dir(&report).unwrap();
    std::fs::write(report.join("response-9-old.svg"), "<svg/>").unwrap();
    std::fs::write(report.join("report.html"), "old").unwrap();
    let st = identify(&model, &data, dir.join("r.json"))
        .arg("--report")
        .arg(&report)
        .args(["--plan", "4", "-q"])
        .status()
        .unwrap();
    assert!(finished(st));
    assert!(
        !report.join("response-9-old.svg").exists(),
        "old figure kept"
    );
    assert_ne!(std::fs::read(report.join("report.html")).unwrap(), b"old");
    assert_eq!(temporaries(&dir), Vec::<String>::new());
}

/// SIGINT or SIGTERM during a run left hidden temporaries; now the run
/// ends with 128 + the signal's number and leaves none.
#[test]
fn an_interrupted_run_exits_cleanly() {
    let dir = scratch_dir("interrupted");
    let model = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/knee-column/model.toml");
    let data = dir.join("data.csv");
    let st = rfeid()
        .arg("simulate")
        .arg(&model)
        .arg("-o")
        .arg(&data)
        .arg("-q")
        .status()
        .unwrap();
    assert!(st.success());
    for (signal, code) in [(libc::SIGINT, 130), (libc::SIGTERM, 143)] {
        let child = identify(&model, &data, dir.join("r.json"))
            .arg("--report")
            .arg(dir.join("report"))
            .args(["--plan", "5000", "-q", "--threads", "1"])
            .spawn()
            .unwrap();
        std::thread::sleep(Duration::from_millis(300));
        // SAFETY: signalling our own child by its id.
        unsafe { libc::kill(child.id() as i32, signal) };
        let out = child.wait_with_output().unwrap();
        assert_eq!(out.status.code(), Some(code), "{out:?}");
        assert!(!dir.join("r.json").exists());
        assert_eq!(temporaries(&dir), Vec::<String>::new());
    }
}

/// `--plan 4294967296` died with SIGABRT ("memory allocation failed").
/// Limits are checked up front, exit 2, naming the limit.
#[test]
fn absurd_sizes_are_refused_up_front() {
    let dir = scratch_dir("limits");
    let model = oscillator_model(&dir);
    let data = simulate_csv(&dir, &model);
    for (args, limit) in [
        (["--plan", "4294967296"], "1000000"),
        (["--starts", "5000"], "1000"),
        (["--threads", "100000"], "1024"),
    ] {
        let out = identify(&model, &data, dir.join("r.json"))
            .args(args)
            .args(
                ["--plan", "100000"]
                    .iter()
                    .filter(|_| args[0] == "--starts"),
            )
            .output()
            .unwrap();
        let stderr = flat(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(stderr.contains(limit), "{args:?}: {stderr}");
    }
}

/// `--threads 400` under a process limit panicked (exit 101): the failed
/// thread-pool build was ignored. Now it is a clear error, exit 1. Needs
/// root (to run as `nobody` under `prlimit`); skipped otherwise.
#[test]
fn a_thread_pool_that_cannot_start_is_a_clear_error() {
    // SAFETY: geteuid has no preconditions.
    if unsafe { libc::geteuid() } != 0 || !Path::new("/usr/bin/setpriv").exists() {
        eprintln!("skipped: needs root and setpriv");
        return;
    }
    let dir = scratch_dir("threads");
    let model = oscillator_model(&dir);
    let data = simulate_csv(&dir, &model);
    let bin = support::binary();
    let out = std::process::Command::new("setpriv")
        .args([
            "--reuid=65534",
            "--regid=65534",
            "--clear-groups",
            "--",
            "prlimit",
            "--nproc=6",
            "--",
        ])
        .arg(bin)
        .arg("identify")
        .arg(&model)
        .arg("--data")
        .arg(&data)
        .args(["-o", "-", "--plan", "4", "--threads", "400", "-q"])
        .output()
        .unwrap();
    let stderr = flat(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("worker threads"), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
}

/// Huge but finite data (1e154) gave exit 1 "all plan points failed …
/// overflows". It is bad input: exit 2, naming the column and the sample.
#[test]
fn huge_finite_data_is_bad_input() {
    let dir = scratch_dir("huge");
    let model = oscillator_model(&dir);
    let data = simulate_csv(&dir, &model);
    let text = std::fs::read_to_string(&data).unwrap();
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    let mut cells: Vec<String> = lines[8].split(',').map(String::from).collect();
    cells[2] = "1e154".into();
    lines[8] = cells.join(",");
    let huge = dir.join("huge.csv");
    std::fs::write(&huge, lines.join("\n") + "\n").unwrap();
    let result = dir.join("r.json");
    let out = identify(&model, &huge, &result)
        .args(["--plan", "4", "-q"])
        .output()
        .unwrap();
    let stderr = flat(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("vel_x") && stderr.contains("sample 7"),
        "{stderr}"
    );
    assert!(!result.exists());
}

/// A value of the wrong type said "data did not match any variant of
/// untagged enum RawNum": now the message names the field.
#[test]
fn a_wrong_type_names_the_field() {
    let dir = scratch_dir("wrong-type");
    let model = oscillator_model(&dir);
    let text = std::fs::read_to_string(&model)
        .unwrap()
        .replace("mass = 2.0", "mass = true");
    std::fs::write(&model, text).unwrap();
    let out = rfeid().arg("check").arg(&model).output().unwrap();
    let stderr = flat(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("field 'mass'"), "{stderr}");
    assert!(!stderr.contains("untagged"), "{stderr}");
}

/// All-zero or constant data "converged" onto a bound with no word that
/// they carry no information: now refused.
#[test]
fn constant_data_are_refused() {
    let dir = scratch_dir("constant");
    let model = oscillator_model(&dir);
    let data = simulate_csv(&dir, &model);
    let text = std::fs::read_to_string(&data).unwrap();
    let zero: Vec<String> = text
        .lines()
        .enumerate()
        .map(|(k, l)| {
            if k == 0 {
                l.to_string()
            } else {
                let t = l.split(',').next().unwrap();
                format!("{t},0,0,0")
            }
        })
        .collect();
    let zero_csv = dir.join("zero.csv");
    std::fs::write(&zero_csv, zero.join("\n") + "\n").unwrap();
    let result = dir.join("r.json");
    let out = identify(&model, &zero_csv, &result)
        .args(["--plan", "4", "-q"])
        .output()
        .unwrap();
    let stderr = flat(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("no information"), "{stderr}");
    assert!(!result.exists());
}

/// A 3 MB compressed .mat could inflate to 2.6 GB before failing. A
/// compressed element that declares more than its bytes can hold is
/// refused before it is inflated.
#[test]
fn mat_inflation_is_capped_by_what_the_file_claims() {
    use std::io::Write;
    let dir = scratch_dir("mat-bomb");
    let model = oscillator_model(&dir);
    // An miMATRIX tag that declares 600 MB, then 20 MB of zeros: about
    // 20 kB compressed, which deflate cannot inflate to 600 MB.
    let mut z = flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::best());
    z.write_all(&14u32.to_le_bytes()).unwrap();
    z.write_all(&600_000_000u32.to_le_bytes()).unwrap();
    let zeros = vec![0u8; 1 << 20];
    for _ in 0..20 {
        z.write_all(&zeros).unwrap();
    }
    let stream = z.finish().unwrap();
    let mut file = vec![b' '; 128];
    file[..10].copy_from_slice(b"MATLAB 5.0");
    file[124..126].copy_from_slice(&0x0100u16.to_le_bytes());
    file[126..128].copy_from_slice(b"IM");
    file.extend_from_slice(&15u32.to_le_bytes());
    file.extend_from_slice(&(stream.len() as u32).to_le_bytes());
    file.extend_from_slice(&stream);
    let mat = dir.join("bomb.mat");
    std::fs::write(&mat, file).unwrap();
    let out = identify(&model, &mat, dir.join("r.json"))
        .args(["--plan", "4", "-q"])
        .output()
        .unwrap();
    let stderr = flat(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("1032:1"), "{stderr}");
}

/// `--noise 1e308` silently left a channel without noise. Noise that would
/// overflow, or vanish in the rounding, is refused.
#[test]
fn noise_that_adds_nothing_is_refused() {
    let dir = scratch_dir("noise");
    let model = oscillator_model(&dir);
    for noise in ["1e308", "1e-300"] {
        let csv = dir.join("n.csv");
        let out = rfeid()
            .arg("simulate")
            .arg(&model)
            .arg("-o")
            .arg(&csv)
            .args(["--noise", noise])
            .output()
            .unwrap();
        let stderr = flat(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{noise}: {stderr}");
        assert!(stderr.contains("--noise"), "{stderr}");
        assert!(!csv.exists());
    }
}

/// `-o -` writes the CSV or the result to standard output (tables then go
/// to standard error).
#[test]
fn dash_writes_to_standard_output() {
    let dir = scratch_dir("stdout");
    let model = oscillator_model(&dir);
    let data = simulate_csv(&dir, &model);
    let out = rfeid()
        .arg("simulate")
        .arg(&model)
        .args(["-o", "-", "-q"])
        .output()
        .unwrap();
    assert!(out.status.success());
    assert_eq!(out.stdout, std::fs::read(&data).unwrap());
    let out = rfeid()
        .arg("identify")
        .arg(&model)
        .arg("--data")
        .arg(&data)
        .args(["-o", "-", "--plan", "4"])
        .output()
        .unwrap();
    assert!(finished(out.status));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON on stdout");
    assert_eq!(v["parameters"].as_array().unwrap().len(), 2);
    assert!(flat(&out.stderr).contains("criterion J"));
    assert!(!dir.join("-").exists());
}

/// A signal table the model reads is one of the run's inputs, and its
/// values are data: `-o` onto it is refused, and a huge value in it is bad
/// input naming the file, column and sample.
#[test]
fn a_signal_table_is_an_input_and_its_values_are_checked() {
    let dir = scratch_dir("table");
    let model = oscillator_model(&dir);
    let text = std::fs::read_to_string(&model).unwrap().replace(
        "signal = { type = \"sine\", amplitude = 100.0, frequency = 30.0 }",
        "signal = { type = \"table\", file = \"force.csv\", column = \"f\" }",
    );
    std::fs::write(&model, text).unwrap();
    let table: String = (0..=60)
        .map(|k| format!("{},{}\n", k as f64 * 1e-3, (k as f64 * 0.2).sin() * 100.0))
        .collect();
    let force = dir.join("force.csv");
    std::fs::write(&force, format!("time,f\n{table}")).unwrap();
    let out = rfeid()
        .arg("simulate")
        .arg(&model)
        .arg("-o")
        .arg(&force)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2), "{}", flat(&out.stderr));
    assert!(flat(&out.stderr).contains("input"));
    assert!(std::fs::read_to_string(&force)
        .unwrap()
        .starts_with("time,f\n"));
    let huge = format!("time,f\n{}", table.replacen(",0\n", ",1e154\n", 1));
    std::fs::write(&force, huge).unwrap();
    let out = rfeid().arg("check").arg(&model).output().unwrap();
    let stderr = flat(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("column 'f', sample 0 is 1e154"), "{stderr}");
}

/// Hidden temporaries that a killed earlier run left in a report folder do
/// not stop the next report from replacing it, and go with the old folder.
#[test]
fn debris_of_a_killed_run_does_not_block_the_next_report() {
    let dir = scratch_dir("debris");
    let model = oscillator_model(&dir);
    let data = simulate_csv(&dir, &model);
    let report = dir.join("report");
    std::fs::create_dir(&report).unwrap();
    std::fs::write(report.join(".plan.svg.tmp-12345"), "x").unwrap();
    std::fs::write(report.join(".rfeid-12345-3.tmp"), "x").unwrap();
    let st = identify(&model, &data, dir.join("r.json"))
        .arg("--report")
        .arg(&report)
        .args(["--plan", "4", "-q"])
        .status()
        .unwrap();
    assert!(finished(st));
    assert_eq!(temporaries(&dir), Vec::<String>::new());
}

/// `--threads` takes effect when the demo's data are simulated first: the
/// step choice runs its two step counts in parallel, which used to start
/// the default worker pool before the command started its own, so `demo
/// --noise … --threads 1` failed with "could not start 1 worker threads".
/// The estimates do not depend on the thread count.
#[test]
fn demo_threads_take_effect_after_its_data_are_simulated() {
    let estimates = |threads: &str| {
        let o = rfeid()
            .args(["demo", "--plan", "8", "--noise", "0.02", "--seed", "3"])
            .args(["-q", "--json", "--threads", threads])
            .output()
            .unwrap();
        assert!(
            o.status.success(),
            "--threads {threads}: {}",
            flat(&o.stderr)
        );
        let r: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        r["parameters"].clone()
    };
    assert_eq!(estimates("1"), estimates("2"));
}
