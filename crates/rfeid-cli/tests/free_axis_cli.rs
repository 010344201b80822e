//! A model with a free axis (SPEC §1: a carriage held along x by a damper
//! only, or by nothing) through every command: `check` names the free
//! direction, `simulate`, `identify` (with `--report`), `modal` and `design`
//! succeed, also under gravity perpendicular to the axis, where `identify`
//! and `design` failed before ("the tangent stiffness at equilibrium is
//! singular"); gravity along the axis is bad input (exit 2) naming the
//! carriage and the direction.
use crate::support;

use std::path::{Path, PathBuf};
use support::*;

/// The carriage on its slideway (GRAVITY and UX_COMPONENT to be filled
/// in), a multisine force along x, three sensors with noise.
const MODEL: &str = r#"GRAVITY
[simulation]
duration = "0.2 s"
sample_rate = "2 kHz"

[[body]]
name = "carriage"
mass = "50 kg"
inertia = [1.0, 1.5, 2.0]
com = [0.0, 0.0, 0.2]

[[element]]
name = "slideway"
body = "carriage"
to = "ground"
at = [0.0, 0.0, 0.1]
UX_COMPONENT
uy = { k = "k_y", c = "2000 N*s/m" }
uz = { k = "2e8 N/m", c = "2000 N*s/m" }
rx = { k = "1e6 N*m/rad", c = "50 N*m*s/rad" }
ry = { k = "1e6 N*m/rad", c = "50 N*m*s/rad" }
rz = { k = "1e6 N*m/rad", c = "50 N*m*s/rad" }

[[parameter]]
name = "c_x"
value = "200 N*s/m"
min = "100 N*s/m"
max = "400 N*s/m"

[[parameter]]
name = "k_y"
value = "1e8 N/m"
min = "5e7 N/m"
max = "2e8 N/m"

[[excitation]]
name = "feed"
body = "carriage"
at = [0.0, 0.0, 0.2]
direction = [1, 0.05, 0]
signal = { type = "multisine", components = [{ amplitude = 100.0, frequency = 20.0 }, { amplitude = 50.0, frequency = 70.0 }] }

[[sensor]]
name = "x_pos"
body = "carriage"
at = [0.0, 0.0, 0.2]
direction = [1, 0, 0]
quantity = "displacement"
noise = "1e-6 m"

[[sensor]]
name = "x_acc"
body = "carriage"
at = [0.0, 0.0, 0.2]
direction = [1, 0, 0]
quantity = "acceleration"
noise = "0.01 m/s^2"

[[sensor]]
name = "y_acc"
body = "carriage"
at = [0.0, 0.0, 0.2]
direction = [0, 1, 0]
quantity = "acceleration"
noise = "1e-4 m/s^2"
"#;

/// [`MODEL`] with `ux` as the carriage's x component (empty: none, and no
/// parameter c_x) and `gravity` on top, written to `dir/name`.
fn write_model(dir: &Path, name: &str, ux: &str, gravity: &str) -> PathBuf {
    let text = MODEL
        .replace("GRAVITY", gravity)
        .replace("UX_COMPONENT", ux);
    // Without the damper, c_x is used nowhere: leave it out.
    let text = match ux.is_empty() {
        true => text.replace(
            "[[parameter]]\nname = \"c_x\"\nvalue = \"200 N*s/m\"\nmin = \"100 N*s/m\"\nmax = \"400 N*s/m\"\n",
            "",
        ),
        false => text,
    };
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

const DAMPER: &str = r#"ux = { c = "c_x" }"#;
const DOWNWARD: &str = "gravity = [0.0, 0.0, -9.81]";

/// Runs rfeid with `args`: (exit status, stdout, stderr).
fn run(args: &[&std::ffi::OsStr]) -> (Option<i32>, String, String) {
    let o = rfeid().args(args).output().unwrap();
    let text = |b: &[u8]| String::from_utf8_lossy(b).into_owned();
    (o.status.code(), text(&o.stdout), text(&o.stderr))
}

/// Runs rfeid with `args`, which must exit 0; its standard output.
fn ok(args: &[&std::ffi::OsStr]) -> String {
    let (code, out, err) = run(args);
    assert_eq!(code, Some(0), "{args:?}: {out}\n{err}");
    out
}

fn os(s: &str) -> &std::ffi::OsStr {
    s.as_ref()
}

#[test]
fn check_names_the_free_direction_and_every_command_runs() {
    let dir = scratch_dir("free-axis");
    for (name, ux, gravity) in [
        ("damper.toml", DAMPER, ""),
        ("gravity.toml", DAMPER, DOWNWARD),
        ("bare.toml", "", DOWNWARD),
    ] {
        let model = write_model(&dir, name, ux, gravity);
        let m = model.as_os_str();
        let out = ok(&[os("check"), m]);
        assert!(
            out.contains("carriage: free along x (no restoring force)"),
            "{name}: {out}"
        );
        let modes = ok(&[os("modal"), m]);
        assert!(
            modes.contains("0 (free)") && modes.contains("carriage: free along x"),
            "{modes}"
        );
        let data = dir.join(format!("{name}.csv"));
        ok(&[
            os("simulate"),
            m,
            os("-o"),
            data.as_os_str(),
            os("--noise"),
            os("0.01"),
            os("--seed"),
            os("1"),
            os("-q"),
        ]);
        let result = dir.join(format!("{name}.json"));
        let report = dir.join(format!("{name}-report"));
        ok(&[
            os("identify"),
            m,
            os("--data"),
            data.as_os_str(),
            os("-o"),
            result.as_os_str(),
            os("--plan"),
            os("20"),
            os("--report"),
            report.as_os_str(),
            os("-q"),
        ]);
        let json: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&result).unwrap()).unwrap();
        assert!(json["parameters"].as_array().is_some_and(|p| !p.is_empty()));
        let html = std::fs::read_to_string(report.join("report.html")).unwrap();
        assert!(
            html.contains("carriage: free along x"),
            "{name}: the report names it"
        );
        ok(&[
            os("report"),
            result.as_os_str(),
            os("-o"),
            dir.join(format!("{name}-r2")).as_os_str(),
        ]);
        ok(&[os("design"), m, os("-q")]);
    }
}

#[test]
fn gravity_along_the_free_axis_is_bad_input_naming_it() {
    let dir = scratch_dir("free-axis-slope");
    let model = write_model(&dir, "slope.toml", DAMPER, "gravity = [-1.0, 0.0, -9.76]");
    let m = model.as_os_str();
    let out = dir.join("out.csv");
    for args in [
        vec![os("check"), m],
        vec![os("simulate"), m, os("-o"), out.as_os_str()],
        vec![os("modal"), m],
        vec![os("design"), m],
    ] {
        let (code, stdout, stderr) = run(&args);
        assert_eq!(code, Some(2), "{args:?}: {stdout}\n{stderr}");
        let text = flat(stderr.as_bytes());
        assert!(
            text.contains("carriage is free along x") && text.contains("50.00 N"),
            "{args:?}: {text}"
        );
    }
    assert!(!out.exists(), "no partial output");
}
