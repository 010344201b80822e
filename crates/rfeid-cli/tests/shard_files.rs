//! Shard files as an outside user (or a fuzzer) meets them: edited or
//! absurd shard files are refused naming the field, before anything is
//! sized by them; shard counts beyond the plan are refused; a shard goes to
//! `/dev/null` or a FIFO; a read-only output is refused, also as root; the
//! Slurm variables of stepped or list arrays get a hint.
use crate::support;

use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::Output;
use std::time::{Duration, Instant};
use support::{flat, rfeid, scratch_dir, simulate_csv};

fn knee_column() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/knee-column/model.toml")
}

/// `identify` of the knee–column on `data` with a plan of 8 and `extra`.
fn shard(data: &Path, extra: &[&str], out: &Path) -> Output {
    rfeid()
        .arg("identify")
        .arg(knee_column())
        .arg("--data")
        .arg(data)
        .args(["--plan", "8", "-q"])
        .args(extra)
        .arg("-o")
        .arg(out)
        .output()
        .unwrap()
}

fn merge(shards: &[PathBuf], out: &Path) -> Output {
    rfeid()
        .arg("merge")
        .args(shards)
        .arg("-o")
        .arg(out)
        .arg("-q")
        .output()
        .unwrap()
}

fn ok(o: Output) -> Output {
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    o
}

/// Knee–column data (noise-free: these tests are about files) in `dir`.
fn data(dir: &Path) -> PathBuf {
    simulate_csv(dir, &knee_column())
}

/// An edit of a shard file's JSON.
type Edit<'a> = Box<dyn Fn(&mut Value) + 'a>;

fn read(path: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// Merging shard 0/2 edited by `edit` with shard 1/2 is refused with exit
/// status 2 and a message holding `expect`, without an output file.
fn refused_after(dir: &Path, s0: &Path, s1: &Path, edit: impl Fn(&mut Value), expect: &str) {
    let mut v = read(s0);
    edit(&mut v);
    let edited = dir.join("edited.json");
    std::fs::write(&edited, serde_json::to_vec(&v).unwrap()).unwrap();
    let out = dir.join("merged.json");
    let o = merge(&[edited, s1.to_path_buf()], &out);
    let msg = flat(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{expect}: {msg}");
    assert!(msg.contains(expect), "expected '{expect}' in: {msg}");
    assert!(!out.exists(), "{expect}: an output was written");
}

#[test]
fn edited_shard_files_are_refused_naming_the_field() {
    let dir = scratch_dir("shard-edits");
    let data = data(&dir);
    let (s0, s1) = (dir.join("s0.json"), dir.join("s1.json"));
    ok(shard(&data, &["--shard", "0/2"], &s0));
    ok(shard(&data, &["--shard", "1/2"], &s1));
    let huge = Value::from(u64::MAX);
    let cases: Vec<(Edit, &str)> = vec![
        (
            Box::new(|v| v["of"] = huge.clone()),
            "`of` is 18446744073709551615",
        ),
        (Box::new(|v| v["of"] = 0.into()), "`of` is 0"),
        (
            Box::new(|v| v["search"]["plan"] = huge.clone()),
            "`search.plan` is 18446744073709551615",
        ),
        (
            Box::new(|v| v["search"]["plan"] = 1_000_000_000_000u64.into()),
            "`search.plan` is 1000000000000",
        ),
        (
            Box::new(|v| v["search"]["plan"] = 1_000_001.into()),
            "`search.plan` is 1000001: must be 1 to 1000000",
        ),
        (
            Box::new(|v| v["search"]["starts"] = 0.into()),
            "`search.starts` is 0",
        ),
        (Box::new(|v| v["shard"] = 2.into()), "`shard` is 2"),
        (
            Box::new(|v| v["seconds"] = (-1.0).into()),
            "`seconds` is -1",
        ),
        (
            Box::new(|v| v["points"][0]["cost"] = (-0.5).into()),
            "J = -0.5",
        ),
        (
            Box::new(|v| v["points"][0]["failure"] = "x".into()),
            "both of `cost` and `failure`",
        ),
        (
            Box::new(|v| v["points"][0]["index"] = 1.into()),
            "holds plan point 1, which is not in shard 0/2",
        ),
        (
            Box::new(|v| v["points"][0]["index"] = 8.into()),
            "holds plan point 8",
        ),
        (
            Box::new(|v| {
                let p = v["points"][1].clone();
                v["points"].as_array_mut().unwrap().push(p);
            }),
            "holds plan point 2 twice",
        ),
        (
            Box::new(|v| {
                v["points"].as_array_mut().unwrap().remove(1);
            }),
            "3 of its 4 points are done, 1 missing (the first: plan point 2)",
        ),
        (
            Box::new(|v| v["complete"] = false.into()),
            "not marked complete",
        ),
    ];
    for (edit, expect) in &cases {
        refused_after(&dir, &s0, &s1, edit, expect);
    }
    // Each time finite, their sum not.
    let mut v0 = read(&s0);
    let mut v1 = read(&s1);
    v0["seconds"] = 1e308.into();
    v1["seconds"] = 1e308.into();
    std::fs::write(&s0, serde_json::to_vec(&v0).unwrap()).unwrap();
    std::fs::write(&s1, serde_json::to_vec(&v1).unwrap()).unwrap();
    let o = merge(&[s0, s1], &dir.join("m.json"));
    assert_eq!(o.status.code(), Some(2), "{}", flat(&o.stderr));
    assert!(flat(&o.stderr).contains("`seconds` add up to inf"));
}

#[test]
fn shard_counts_beyond_the_plan_and_foreign_shards_at_the_output_are_refused() {
    let dir = scratch_dir("shard-counts");
    let data = data(&dir);
    for spec in ["0/18446744073709551615", "0/1099511627776", "3/9"] {
        let out = dir.join("huge.json");
        let o = shard(&data, &["--shard", spec], &out);
        let msg = flat(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{spec}: {msg}");
        assert!(msg.contains("use at most 8 shards"), "{spec}: {msg}");
        assert!(!out.exists());
    }
    // Shard 0/2 of this run at the output of shard 1/2: named as such.
    let s = dir.join("s.json");
    ok(shard(&data, &["--shard", "0/2"], &s));
    let o = shard(&data, &["--shard", "1/2"], &s);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        flat(&o.stderr).contains("holds shard 0/2 of this run, not 1/2"),
        "{}",
        flat(&o.stderr)
    );
}

#[cfg(unix)]
#[test]
fn a_shard_goes_to_dev_null_and_to_a_fifo() {
    let dir = scratch_dir("shard-special");
    let data = data(&dir);
    ok(shard(&data, &["--shard", "0/2"], Path::new("/dev/null")));
    let fifo = dir.join("fifo");
    let c = std::ffi::CString::new(fifo.to_str().unwrap()).unwrap();
    // SAFETY: `c` is a valid NUL-terminated path that outlives the call.
    assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o600) }, 0);
    let mut child = rfeid()
        .arg("identify")
        .arg(knee_column())
        .arg("--data")
        .arg(&data)
        .args(["--plan", "8", "-q", "--shard", "1/2", "-o"])
        .arg(&fifo)
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let reader = {
        let fifo = fifo.clone();
        std::thread::spawn(move || std::fs::read_to_string(fifo).unwrap())
    };
    let started = Instant::now();
    let status = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break s;
        }
        if started.elapsed() > Duration::from_secs(120) {
            child.kill().unwrap();
            // Unblock the reader, then fail.
            let _ = std::fs::write(&fifo, b"");
            panic!("identify --shard -o FIFO hangs");
        }
        std::thread::sleep(Duration::from_millis(50));
    };
    assert!(status.success());
    let text = reader.join().unwrap();
    let v: Value = serde_json::from_str(&text).unwrap();
    assert_eq!((v["shard"].as_u64(), v["of"].as_u64()), (Some(1), Some(2)));
}

#[cfg(unix)]
#[test]
fn a_read_only_output_is_refused_whoever_runs() {
    use std::os::unix::fs::PermissionsExt;
    let dir = scratch_dir("shard-readonly");
    let data = data(&dir);
    let out = dir.join("ro.json");
    std::fs::write(&out, "keep").unwrap();
    std::fs::set_permissions(&out, std::fs::Permissions::from_mode(0o444)).unwrap();
    for extra in [&["--shard", "0/2"][..], &["--starts", "1"][..]] {
        let o = shard(&data, extra, &out);
        assert_eq!(o.status.code(), Some(2), "{extra:?}: {}", flat(&o.stderr));
        assert!(flat(&o.stderr).contains("read-only"), "{}", flat(&o.stderr));
        assert_eq!(std::fs::read_to_string(&out).unwrap(), "keep");
    }
}

#[test]
fn shard_auto_names_what_is_unset_and_refuses_stepped_or_list_arrays() {
    let dir = scratch_dir("shard-slurm");
    let data = data(&dir);
    let out = dir.join("auto.json");
    let run = |vars: &[(&str, &str)]| {
        let mut cmd = rfeid();
        cmd.arg("identify")
            .arg(knee_column())
            .arg("--data")
            .arg(&data)
            .args(["--plan", "8", "-q", "--shard", "auto", "-o"])
            .arg(&out);
        for v in [
            "SLURM_ARRAY_TASK_ID",
            "SLURM_ARRAY_TASK_COUNT",
            "SLURM_ARRAY_TASK_MIN",
            "SLURM_ARRAY_TASK_MAX",
            "SLURM_ARRAY_TASK_STEP",
        ] {
            cmd.env_remove(v);
        }
        cmd.envs(vars.iter().copied());
        cmd.output().unwrap()
    };
    let cases: [(&[(&str, &str)], &str); 3] = [
        (
            &[("SLURM_ARRAY_TASK_ID", "1")],
            "SLURM_ARRAY_TASK_COUNT is not set",
        ),
        (
            &[
                ("SLURM_ARRAY_TASK_ID", "2"),
                ("SLURM_ARRAY_TASK_COUNT", "2"),
                ("SLURM_ARRAY_TASK_MIN", "0"),
                ("SLURM_ARRAY_TASK_MAX", "2"),
                ("SLURM_ARRAY_TASK_STEP", "2"),
            ],
            "steps by 2",
        ),
        (
            &[
                ("SLURM_ARRAY_TASK_ID", "7"),
                ("SLURM_ARRAY_TASK_COUNT", "3"),
                ("SLURM_ARRAY_TASK_MIN", "3"),
                ("SLURM_ARRAY_TASK_MAX", "9"),
            ],
            "are not 3 contiguous ones",
        ),
    ];
    for (vars, expect) in cases {
        let o = run(vars);
        let msg = flat(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{vars:?}: {msg}");
        assert!(msg.contains(expect), "expected '{expect}' in: {msg}");
    }
}

#[test]
fn a_shard_with_json_prints_its_summary_and_one_thread_is_singular() {
    let dir = scratch_dir("shard-json");
    let data = data(&dir);
    let out = dir.join("s.json");
    let o = rfeid()
        .arg("identify")
        .arg(knee_column())
        .arg("--data")
        .arg(&data)
        .args(["--plan", "8", "--shard", "1/2", "--json", "-o"])
        .arg(&out)
        .output()
        .unwrap();
    let o = ok(o);
    let v: Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!((v["shard"].as_u64(), v["of"].as_u64()), (Some(1), Some(2)));
    assert_eq!(v["points"].as_u64(), Some(4));
    let o = ok(shard(
        &data,
        &["--starts", "1", "--threads", "1", "--timings"],
        &dir.join("r.json"),
    ));
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(text.contains("(1 thread)"), "{text}");
}

#[test]
fn merge_elsewhere_names_the_recorded_path_and_takes_model_and_data() {
    let dir = scratch_dir("shard-elsewhere");
    let data = data(&dir);
    let (s0, s1) = (dir.join("s0.json"), dir.join("s1.json"));
    // Recorded relative to a working folder the merge does not run in.
    let run = |spec: &str, out: &Path| {
        ok(rfeid()
            .current_dir(dir.parent().unwrap())
            .arg("identify")
            .arg(knee_column())
            .arg("--data")
            .arg(Path::new(dir.file_name().unwrap()).join("data.csv"))
            .args(["--plan", "8", "-q", "--shard", spec, "-o"])
            .arg(out)
            .output()
            .unwrap())
    };
    run("0/2", &s0);
    run("1/2", &s1);
    // A byte-order mark is no reason to refuse a shard.
    let text = std::fs::read_to_string(&s1).unwrap();
    std::fs::write(&s1, format!("\u{feff}{text}")).unwrap();
    let elsewhere = scratch_dir("shard-elsewhere-cwd");
    let merged = dir.join("merged.json");
    let o = rfeid()
        .current_dir(&elsewhere)
        .arg("merge")
        .args([&s0, &s1])
        .arg("-o")
        .arg(&merged)
        .output()
        .unwrap();
    let msg = flat(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{msg}");
    assert!(
        msg.contains("records the file") && msg.contains("--data PATH"),
        "{msg}"
    );
    let o = rfeid()
        .current_dir(&elsewhere)
        .arg("merge")
        .args([&s0, &s1])
        .arg("--data")
        .arg(&data)
        .args(["-q", "-o"])
        .arg(&merged)
        .output()
        .unwrap();
    assert!(
        matches!(o.status.code(), Some(0 | 3 | 4)),
        "{}",
        flat(&o.stderr)
    );
    // A shard file is not a result.
    let o = rfeid()
        .arg("validate")
        .arg(knee_column())
        .arg(&s0)
        .arg("--data")
        .arg(&data)
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    assert!(
        flat(&o.stderr).contains("a shard file of `identify --shard`, not a result"),
        "{}",
        flat(&o.stderr)
    );
}
