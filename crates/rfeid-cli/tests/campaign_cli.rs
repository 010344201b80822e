//! Campaigns on the command line (SPEC §5): a validation experiment left
//! out of the fit, `rfeid validate`, and every campaign input mistake
//! exiting 2 with file, entry and field named and no output written.
use crate::support;

use serde_json::Value;
use std::path::{Path, PathBuf};
use support::*;

/// The oscillator with its excitation amplitude a fixed parameter `P`, and
/// `experiments` (TOML) appended.
fn campaign_model(dir: &Path, experiments: &str) -> PathBuf {
    campaign_model_as(dir, experiments, "campaign.toml")
}

/// [`campaign_model`] written as `dir/file`.
fn campaign_model_as(dir: &Path, experiments: &str, file: &str) -> PathBuf {
    let base = oscillator_model(dir);
    let text = std::fs::read_to_string(&base)
        .unwrap()
        .replace("amplitude = 100.0", "amplitude = \"P\"")
        + "\n[[parameter]]\nname = \"P\"\nvalue = 100.0\n"
        + experiments;
    let path = dir.join(file);
    std::fs::write(&path, text).unwrap();
    path
}

const THREE: &str = "\n[[experiment]]\nname = \"a\"\ndata = \"a.csv\"\nset = { P = 100.0 }\n\
     \n[[experiment]]\nname = \"b\"\ndata = \"b.csv\"\nset = { P = 40.0 }\n\
     \n[[experiment]]\nname = \"v\"\ndata = \"v.csv\"\nset = { P = 70.0 }\nuse = \"validation\"\n";

/// Simulates experiment `name` of `model` into `dir/NAME.csv`, 1 % noise.
fn simulate_experiment(dir: &Path, model: &Path, name: &str, seed: u32) {
    simulate_with(dir, model, name, &[], seed);
}

/// `rfeid identify MODEL -o OUT -q` with `extra` options, which must
/// finish; RESULT.json.
fn identify_campaign(model: &Path, out: &Path, extra: &[&str]) -> Value {
    let o = rfeid()
        .arg("identify")
        .arg(model)
        .arg("-o")
        .arg(out)
        .arg("-q")
        .args(extra)
        .output()
        .unwrap();
    assert!(finished(o.status), "{}", flat(&o.stderr));
    json(out)
}

fn json(path: &Path) -> Value {
    serde_json::from_slice(&std::fs::read(path).unwrap()).unwrap()
}

/// A validation experiment changes nothing in the fit (estimates bit for
/// bit those of the campaign without it) and its fit is reported; `rfeid
/// validate` gives the fits identify reported, for a fitted and for the
/// validation experiment.
#[test]
fn validation_experiment_and_validate_command() {
    let dir = scratch_dir("campaign-validate");
    let model = campaign_model(&dir, THREE);
    for (k, name) in ["a", "b", "v"].iter().enumerate() {
        simulate_experiment(&dir, &model, name, k as u32 + 1);
    }
    let out = dir.join("r.json");
    identify_campaign(&model, &out, &["--plan", "20"]);
    let with_v = json(&out);
    let fitted_only = campaign_model_as(
        &dir,
        &THREE[..THREE.find("\n[[experiment]]\nname = \"v\"").unwrap()],
        "fitted.toml",
    );
    let out2 = dir.join("r2.json");
    identify_campaign(&fitted_only, &out2, &["--plan", "20"]);
    assert_eq!(estimate_bits(&with_v), estimate_bits(&json(&out2)));
    let experiments = with_v["experiments"].as_array().unwrap();
    let v = experiments.iter().find(|e| e["name"] == "v").unwrap();
    assert_eq!(v["role"], "validation");
    let fits: Vec<f64> = v["fits"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f.as_f64().unwrap())
        .collect();
    assert_eq!(fits.len(), 3);
    assert!(fits.iter().all(|f| *f > 95.0), "{fits:?}");

    for name in ["b", "v"] {
        let o = rfeid()
            .arg("validate")
            .arg(&model)
            .arg(&out)
            .args(["--experiment", name, "--json", "-q"])
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", flat(&o.stderr));
        let got: Value = serde_json::from_slice(&o.stdout).unwrap();
        let reported = &experiments.iter().find(|e| e["name"] == name).unwrap()["fits"];
        for (g, r) in got[0]["fit_percent"]
            .as_array()
            .unwrap()
            .iter()
            .zip(reported.as_array().unwrap())
        {
            let (g, r) = (g.as_f64().unwrap(), r.as_f64().unwrap());
            assert!((g - r).abs() < 1e-6, "{name}: validate {g} vs identify {r}");
        }
    }
    // `rfeid report` rebuilds a campaign's report from RESULT.json, with
    // each experiment's fits.
    let rep = dir.join("report");
    let o = rfeid()
        .arg("report")
        .arg(&out)
        .arg("-o")
        .arg(&rep)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", flat(&o.stderr));
    let html = std::fs::read_to_string(rep.join("report.html")).unwrap();
    assert!(
        html.contains("experiments (fit per sensor"),
        "no experiment fits"
    );
    assert!(html.contains("a (fitted)") && html.contains("v (validation"));
    // Every experiment at once, as a table.
    let o = rfeid()
        .arg("validate")
        .arg(&model)
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success());
    let table = String::from_utf8_lossy(&o.stdout);
    assert!(
        table.contains("v (validation)") && table.contains("a (fit)"),
        "{table}"
    );
    // `validate --report` on one experiment of a campaign result: a fitted
    // one and the validation one, each with its own sensors' signals.
    for name in ["b", "v"] {
        let rep = dir.join(format!("validate-{name}"));
        let o = rfeid()
            .arg("validate")
            .arg(&model)
            .arg(&out)
            .args(["--experiment", name, "--report"])
            .arg(&rep)
            .output()
            .unwrap();
        assert!(o.status.success(), "{name}: {}", flat(&o.stderr));
        let html = std::fs::read_to_string(rep.join("report.html")).unwrap();
        assert!(
            html.contains(&format!("acc_x[{name}]")),
            "{name}: no acc_x[{name}]"
        );
        assert!(
            !html.contains("acc_x[a]"),
            "{name}: another experiment's sensor"
        );
    }
    // A data file that changed since the fit: `report` refuses it, naming
    // the file, and writes nothing.
    simulate_experiment(&dir, &model, "b", 9);
    let rep = dir.join("report-after-change");
    let o = rfeid()
        .arg("report")
        .arg(&out)
        .arg("-o")
        .arg(&rep)
        .output()
        .unwrap();
    let msg = flat(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{msg}");
    assert!(
        msg.contains("b.csv changed") && msg.contains("r.json"),
        "{msg}"
    );
    assert!(!rep.exists());
    // `validate` compares with data of its choosing, the changed file too;
    // a changed model file is named in a warning.
    let edited = dir.join("edited.toml");
    std::fs::write(
        &edited,
        std::fs::read_to_string(&model).unwrap() + "\n# edited\n",
    )
    .unwrap();
    let o = rfeid()
        .arg("validate")
        .arg(&edited)
        .arg(&out)
        .args(["--experiment", "b"])
        .output()
        .unwrap();
    let msg = flat(&o.stderr);
    assert!(o.status.success(), "{msg}");
    assert!(
        msg.contains("warning: the model file") && msg.contains("edited.toml"),
        "{msg}"
    );
}

/// Runs `args` and checks exit 2, that stderr names every one of `names`,
/// and that `out` was not written.
fn refused(args: &[&std::ffi::OsStr], names: &[&str], out: &Path) {
    let o = rfeid().args(args).output().unwrap();
    let msg = flat(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{args:?}: {msg}");
    for n in names {
        assert!(msg.contains(n), "{args:?}: '{n}' not in: {msg}");
    }
    assert!(!out.exists(), "{args:?} wrote {}", out.display());
    assert!(temporaries(out.parent().unwrap()).is_empty());
}

#[test]
fn campaign_mistakes_exit_2_naming_file_entry_and_field() {
    let dir = scratch_dir("campaign-bad");
    let out = dir.join("r.json");
    let os = |s: &str| std::ffi::OsString::from(s);
    let id = |m: &Path| {
        vec![
            os("identify"),
            m.as_os_str().to_owned(),
            os("-o"),
            out.as_os_str().to_owned(),
        ]
    };
    let call = |v: &[std::ffi::OsString], names: &[&str]| {
        let v: Vec<&std::ffi::OsStr> = v.iter().map(|s| s.as_os_str()).collect();
        refused(&v, names, &out);
    };

    // `set` naming an unknown parameter.
    let m = campaign_model(
        &dir,
        "\n[[experiment]]\nname = \"a\"\ndata = \"a.csv\"\nset = { Q = 1.0 }\n",
    );
    call(&id(&m), &["campaign.toml", "experiment", "set", "Q"]);

    // A missing data file: identify and check refuse it alike.
    let m = campaign_model(&dir, THREE);
    // --set of a parameter the experiments set: they would override it.
    let mut v = id(&m);
    v.extend([os("--set"), os("P=50")]);
    call(&v, &["--set 'P=50'", "experiments a, b, v", "override"]);
    simulate_experiment(&dir, &m, "a", 1);
    simulate_experiment(&dir, &m, "v", 3);
    call(&id(&m), &["campaign.toml", "\"b\"", "data", "b.csv"]);
    call(
        &[os("check"), m.as_os_str().to_owned()],
        &["campaign.toml", "\"b\"", "data", "b.csv"],
    );

    // Data lacking a sensor the experiment names.
    let text = std::fs::read_to_string(dir.join("a.csv")).unwrap();
    let cut: String = text
        .lines()
        .map(|l| l.rsplit_once(',').unwrap().0.to_string() + "\n")
        .collect();
    std::fs::write(dir.join("b.csv"), cut).unwrap();
    call(&id(&m), &["campaign.toml", "\"b\"", "data", "acc_x"]);
    call(
        &[os("check"), m.as_os_str().to_owned()],
        &["campaign.toml", "\"b\"", "data", "acc_x"],
    );

    // --window with a campaign: refused, not ignored.
    simulate_experiment(&dir, &m, "b", 2);
    let mut v = id(&m);
    v.extend([os("--window"), os("0.3")]);
    call(&v, &["--window 0.3", "campaign", "whole records"]);

    // --data with a model that lists experiments.
    let mut v = id(&m);
    v.extend([os("--data"), dir.join("a.csv").into_os_string()]);
    call(&v, &["--data", "experiment"]);

    // An unknown experiment.
    let sim_out = dir.join("s.csv");
    let v = [
        os("simulate"),
        m.as_os_str().to_owned(),
        os("--experiment"),
        os("zz"),
        os("-o"),
        sim_out.as_os_str().to_owned(),
    ];
    let vv: Vec<&std::ffi::OsStr> = v.iter().map(|s| s.as_os_str()).collect();
    refused(&vv, &["zz"], &sim_out);

    // validate: a result of another model, and an unknown experiment.
    let plain = oscillator_model(&dir);
    let data = simulate_csv(&dir, &plain);
    let r = dir.join("plain.json");
    assert!(finished(
        identify(&plain, &data, &r)
            .args(["--plan", "8", "-q"])
            .status()
            .unwrap()
    ));
    let other = dir.join("other.toml");
    std::fs::write(
        &other,
        std::fs::read_to_string(&plain)
            .unwrap()
            .replace("\"k\"", "\"k2\""),
    )
    .unwrap();
    let rep = dir.join("rep");
    let v = [
        os("validate"),
        other.as_os_str().to_owned(),
        r.as_os_str().to_owned(),
        os("--data"),
        data.as_os_str().to_owned(),
        os("--report"),
        rep.as_os_str().to_owned(),
    ];
    let vv: Vec<&std::ffi::OsStr> = v.iter().map(|s| s.as_os_str()).collect();
    refused(
        &vv,
        &["plain.json", "parameters", "'k'", "other.toml"],
        &rep,
    );
    // A result with an estimate deleted, or listed twice.
    let full: Value = json(&r);
    for (edit, says) in [(0, "'c', identified in"), (1, "'k' is listed twice")] {
        let mut v = full.clone();
        let list = v["parameters"].as_array_mut().unwrap();
        match edit {
            0 => list.retain(|p| p["name"] != "c"),
            _ => {
                let k = list.iter().find(|p| p["name"] == "k").unwrap().clone();
                list.push(k);
            }
        }
        let edited = dir.join("edited.json");
        std::fs::write(&edited, serde_json::to_vec(&v).unwrap()).unwrap();
        let args = [
            os("validate"),
            plain.as_os_str().to_owned(),
            edited.as_os_str().to_owned(),
            os("--data"),
            data.as_os_str().to_owned(),
            os("--report"),
            rep.as_os_str().to_owned(),
        ];
        let vv: Vec<&std::ffi::OsStr> = args.iter().map(|s| s.as_os_str()).collect();
        refused(&vv, &["edited.json", "parameters", says], &rep);
    }
    let v = [
        os("validate"),
        m.as_os_str().to_owned(),
        r.as_os_str().to_owned(),
        os("--experiment"),
        os("zz"),
    ];
    let vv: Vec<&std::ffi::OsStr> = v.iter().map(|s| s.as_os_str()).collect();
    refused(&vv, &["zz", "campaign.toml"], &rep);
}

/// Identifies `model` (a campaign) with the default settings and returns
/// the worst |estimate − truth| / s.e. over `truth` (name, true value).
fn worst_deviation(dir: &Path, model: &Path, truth: &[(&str, f64)]) -> f64 {
    let out = dir.join("per.json");
    let v = identify_campaign(model, &out, &[]);
    let params = v["parameters"].as_array().unwrap();
    truth
        .iter()
        .map(|(name, value)| {
            let p = params
                .iter()
                .find(|p| p["name"] == *name)
                .unwrap_or_else(|| panic!("no {name} in {params:?}"));
            let (est, se) = (
                p["estimate"].as_f64().unwrap(),
                p["std_error"].as_f64().unwrap(),
            );
            println!("{name}: {est} ± {se} (truth {value})");
            (est - value).abs() / se
        })
        .fold(0.0, f64::max)
}

/// Simulates experiment `name` with `sets` (NAME=VALUE) into `dir/NAME.csv`.
fn simulate_with(dir: &Path, model: &Path, name: &str, sets: &[&str], seed: u32) {
    let mut cmd = rfeid();
    cmd.arg("simulate")
        .arg(model)
        .args(["--experiment", name, "--noise", "0.01", "--seed"])
        .arg(seed.to_string());
    for s in sets {
        cmd.args(["--set", s]);
    }
    let st = cmd
        .arg("-o")
        .arg(dir.join(format!("{name}.csv")))
        .arg("-q")
        .status()
        .unwrap();
    assert!(st.success());
}

/// An excitation gain per experiment (`per_experiment = true`): each
/// test's amplitude recovered, within 3 standard errors, with k and c.
#[test]
fn an_excitation_gain_per_experiment_is_recovered() {
    let dir = scratch_dir("campaign-gain");
    let model = campaign_model(
        &dir,
        "\n[[experiment]]\nname = \"a\"\ndata = \"a.csv\"\n\
         \n[[experiment]]\nname = \"b\"\ndata = \"b.csv\"\n",
    );
    let text = std::fs::read_to_string(&model).unwrap().replace(
        "name = \"P\"\nvalue = 100.0\n",
        "name = \"P\"\nvalue = 100.0\nmin = 50.0\nmax = 150.0\nper_experiment = true\n",
    );
    std::fs::write(&model, text).unwrap();
    simulate_with(&dir, &model, "a", &["P=80", "k=1.7e5", "c=35"], 1);
    simulate_with(&dir, &model, "b", &["P=120", "k=1.7e5", "c=35"], 2);
    let z = worst_deviation(
        &dir,
        &model,
        &[("P[a]", 80.0), ("P[b]", 120.0), ("k", 1.7e5), ("c", 35.0)],
    );
    assert!(z <= 3.0, "worst {z:.2} standard errors");
}

/// A sensor offset per experiment (`offset = "off"` on a sensor): each
/// test's offset recovered within 3 standard errors.
#[test]
fn a_sensor_offset_per_experiment_is_recovered() {
    let dir = scratch_dir("campaign-offset");
    let model = campaign_model(
        &dir,
        "\n[[experiment]]\nname = \"a\"\ndata = \"a.csv\"\nset = { P = 100.0 }\n\
         \n[[experiment]]\nname = \"b\"\ndata = \"b.csv\"\nset = { P = 60.0 }\n\
         \n[[parameter]]\nname = \"off\"\nvalue = 0.0\nmin = -0.01\nmax = 0.01\nper_experiment = true\n",
    );
    let text = std::fs::read_to_string(&model).unwrap().replacen(
        "quantity = \"displacement\"\n",
        "quantity = \"displacement\"\noffset = \"off\"\n",
        1,
    );
    std::fs::write(&model, text).unwrap();
    simulate_with(&dir, &model, "a", &["off=0.002", "k=1.7e5"], 1);
    simulate_with(&dir, &model, "b", &["off=-0.003", "k=1.7e5"], 2);
    let z = worst_deviation(
        &dir,
        &model,
        &[("off[a]", 0.002), ("off[b]", -0.003), ("k", 1.7e5)],
    );
    assert!(z <= 3.0, "worst {z:.2} standard errors");
}

/// `--profiles` on a campaign: every identified parameter profiled on the
/// experiments fitted together, its intervals in RESULT.json and the table
/// on the terminal.
#[test]
fn a_campaign_is_profiled() {
    let dir = scratch_dir("campaign-profiles");
    let model = campaign_model(&dir, THREE);
    for (k, name) in ["a", "b", "v"].iter().enumerate() {
        simulate_experiment(&dir, &model, name, k as u32 + 1);
    }
    let out = dir.join("r.json");
    let r = identify_campaign(
        &model,
        &out,
        &["--plan", "20", "--profiles", "--profile-points", "6"],
    );
    let profiles = r["profiles"].as_array().unwrap();
    let names: Vec<&str> = profiles
        .iter()
        .map(|p| p["name"].as_str().unwrap())
        .collect();
    assert_eq!(names, ["k", "c"]);
    for p in profiles {
        assert_eq!(p["points"].as_array().unwrap().len(), 7, "{p}");
        assert_eq!(p["lower"]["kind"], "crossed", "{p}");
        assert_eq!(p["upper"]["kind"], "crossed", "{p}");
    }
}
