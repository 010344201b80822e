//! `identify --shard K/N` and `rfeid merge`: three shards merged give the
//! single run's result bit for bit (all but the wall times and thread
//! count); a killed shard resumes without redoing finished points; shards of
//! different runs, missing or incomplete shards are refused.
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn rfeid() -> Command {
    Command::new(env!("CARGO_BIN_EXE_rfeid"))
}

fn scratch(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("rfeid-cli-shards-{}-{test}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn knee_column() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/knee-column/model.toml")
}

fn ok(out: Output) -> Output {
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

/// Noisy knee–column data in `dir`.
fn data(dir: &Path) -> PathBuf {
    let data = dir.join("data.csv");
    ok(rfeid()
        .arg("simulate")
        .arg(knee_column())
        .arg("-o")
        .arg(&data)
        .args(["--noise", "0.02", "--seed", "2", "-q"])
        .output()
        .unwrap());
    data
}

fn identify(data: &Path, extra: &[&str], out: &Path) -> Output {
    rfeid()
        .arg("identify")
        .arg(knee_column())
        .arg("--data")
        .arg(data)
        .args(["--plan", "24", "--starts", "2", "-q"])
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

/// RESULT.json without the wall times and the thread count.
fn comparable(path: &Path) -> Value {
    let mut v: Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    let o = v.as_object_mut().unwrap();
    o.remove("timings").expect("timings");
    o.remove("threads").expect("threads");
    v
}

#[test]
fn three_shards_merged_equal_the_single_run_bit_for_bit() {
    let dir = scratch("three");
    let data = data(&dir);
    ok(identify(&data, &[], &dir.join("single.json")));
    let shards: Vec<PathBuf> = (0..3).map(|k| dir.join(format!("s{k}.json"))).collect();
    // Out of order, on different thread counts: neither matters.
    for k in [2, 0, 1] {
        let threads = (k + 1).to_string();
        let spec = format!("{k}/3");
        ok(identify(
            &data,
            &["--shard", &spec, "--threads", &threads],
            &shards[k],
        ));
    }
    let s1: Value = serde_json::from_str(&std::fs::read_to_string(&shards[1]).unwrap()).unwrap();
    let indices: Vec<u64> = s1["points"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p["index"].as_u64().unwrap())
        .collect();
    assert_eq!(indices, vec![1, 4, 7, 10, 13, 16, 19, 22]);
    ok(merge(
        &[shards[1].clone(), shards[2].clone(), shards[0].clone()],
        &dir.join("merged.json"),
    ));
    let (a, b) = (
        comparable(&dir.join("single.json")),
        comparable(&dir.join("merged.json")),
    );
    // Exact equality of every number: serde_json reads floats back exactly.
    assert!(a == b, "the merged result differs from the single run");
    assert_eq!(a["plan"]["points"], 24);
    // The single run abandoned points of its plan's second batch; the
    // merge, whose shards simulated every point to the end, the same ones.
    assert!(a["plan"]["abandoned"]
        .as_array()
        .is_some_and(|v| !v.is_empty()));
}

#[test]
fn a_killed_shard_resumes_without_redoing_finished_points() {
    let dir = scratch("resume");
    let data = data(&dir);
    let full = dir.join("full.json");
    ok(identify(&data, &["--shard", "1/3"], &full));
    // What a shard killed after its first checkpoint leaves: some points,
    // not complete.
    let mut v: Value = serde_json::from_str(&std::fs::read_to_string(&full).unwrap()).unwrap();
    let points = v["points"].as_array_mut().unwrap();
    points.truncate(3);
    v["complete"] = Value::Bool(false);
    let partial = dir.join("partial.json");
    std::fs::write(&partial, serde_json::to_vec_pretty(&v).unwrap()).unwrap();
    // merge refuses it as it is.
    let out = merge(std::slice::from_ref(&partial), &dir.join("r.json"));
    assert_eq!(out.status.code(), Some(2));
    // (miette wraps long messages: compare the words.)
    let words = String::from_utf8_lossy(&out.stderr)
        .replace('│', " ")
        .split_whitespace()
        .collect::<Vec<_>>()
        .join(" ");
    assert!(words.contains("not complete"), "{words}");
    // Run again with the same -o: resumes.
    let out = rfeid()
        .arg("identify")
        .arg(knee_column())
        .arg("--data")
        .arg(&data)
        .args(["--plan", "24", "--starts", "2", "--shard", "1/3", "-o"])
        .arg(&partial)
        .output()
        .unwrap();
    assert!(out.status.success());
    let note = String::from_utf8_lossy(&out.stderr);
    assert!(
        note.contains("resuming, 3 of its 8 points already done"),
        "{note}"
    );
    let strip = |p: &Path| {
        let mut v: Value = serde_json::from_str(&std::fs::read_to_string(p).unwrap()).unwrap();
        v.as_object_mut().unwrap().remove("seconds");
        v
    };
    assert_eq!(strip(&partial), strip(&full));
}

#[test]
fn shards_of_different_runs_or_missing_shards_are_refused() {
    let dir = scratch("refuse");
    let data = data(&dir);
    let a0 = dir.join("a0.json");
    let a1 = dir.join("a1.json");
    let b1 = dir.join("b1.json");
    ok(identify(&data, &["--shard", "0/2"], &a0));
    ok(identify(&data, &["--shard", "1/2"], &a1));
    // Another run: other starts.
    ok(rfeid()
        .arg("identify")
        .arg(knee_column())
        .arg("--data")
        .arg(&data)
        .args([
            "--plan", "24", "--starts", "1", "--shard", "1/2", "-q", "-o",
        ])
        .arg(&b1)
        .output()
        .unwrap());
    let out = merge(&[a0.clone(), b1.clone()], &dir.join("r.json"));
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("belongs to another run"));
    let out = merge(std::slice::from_ref(&a0), &dir.join("r.json"));
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("shard 1/2 is missing"));
    let out = merge(&[a0.clone(), a0.clone()], &dir.join("r.json"));
    assert_eq!(out.status.code(), Some(2));
    assert!(!dir.join("r.json").exists());
    // A shard file of another run at -o is not silently replaced.
    let out = identify(&data, &["--shard", "1/2"], &b1);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("of another run"));
    // Changed data after the shards: refused by the hash.
    ok(merge(&[a0.clone(), a1.clone()], &dir.join("r.json")));
    let text = std::fs::read_to_string(&data).unwrap();
    std::fs::write(&data, text.replacen("e-", "E-", 1)).unwrap();
    let out = merge(&[a0, a1], &dir.join("r2.json"));
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("changed since the shards"));
}

#[test]
fn shard_auto_reads_the_slurm_array_variables_and_bad_specs_are_bad_input() {
    let dir = scratch("auto");
    let data = data(&dir);
    let out = dir.join("auto.json");
    ok(rfeid()
        .arg("identify")
        .arg(knee_column())
        .arg("--data")
        .arg(&data)
        .args(["--plan", "24", "--shard", "auto", "-q", "-o"])
        .arg(&out)
        .env("SLURM_ARRAY_TASK_ID", "3")
        .env("SLURM_ARRAY_TASK_MIN", "1")
        .env("SLURM_ARRAY_TASK_COUNT", "4")
        .output()
        .unwrap());
    let v: Value = serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    assert_eq!((v["shard"].as_u64(), v["of"].as_u64()), (Some(2), Some(4)));
    for spec in ["3/3", "1/0", "x", "auto"] {
        let o = rfeid()
            .arg("identify")
            .arg(knee_column())
            .arg("--data")
            .arg(&data)
            .args(["--shard", spec, "-o"])
            .arg(dir.join("bad.json"))
            .env_remove("SLURM_ARRAY_TASK_ID")
            .output()
            .unwrap();
        assert_eq!(o.status.code(), Some(2), "--shard {spec}");
        assert!(String::from_utf8_lossy(&o.stderr).contains("--shard"));
    }
}
