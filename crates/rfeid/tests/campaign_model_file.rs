//! `[[experiment]]` entries (SPEC §5): what a campaign's model file says,
//! and every mistake in one named by its entry and field.
use rfeid::io::model_file::parse_model;
use rfeid::model::Role;
use std::path::{Path, PathBuf};

fn example() -> (String, PathBuf) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples/knee-column-campaign/model.toml");
    (std::fs::read_to_string(&path).expect("example"), path)
}

/// The example without its experiments, so that each case adds its own.
fn base() -> (String, PathBuf) {
    let (text, path) = example();
    let cut = text.find("[[experiment]]").expect("has experiments");
    (text[..cut].to_string(), path)
}

#[test]
fn the_campaign_example_reads_as_written() {
    let (text, path) = example();
    let m = parse_model(&text, &path).unwrap_or_else(|e| panic!("{e}"));
    let names: Vec<&str> = m.experiments.iter().map(|e| e.name.as_str()).collect();
    assert_eq!(names, ["low", "mid", "high"]);
    let p0 = m.parameter_index("P0").unwrap();
    let dir = path.parent().unwrap();
    for (e, (force, file)) in
        m.experiments
            .iter()
            .zip([(200.0, "low.csv"), (600.0, "mid.csv"), (1000.0, "high.csv")])
    {
        assert_eq!(e.set, [(p0, force)]);
        assert_eq!(e.data, dir.join(file));
        assert_eq!((e.role, e.weight, e.from), (Role::Fit, 1.0, 0.0));
    }
    let low = m.for_experiment(0);
    assert_eq!(low.parameters[p0].value, 200.0);
    assert!(low.experiments.is_empty());
    assert_eq!(low.sensors.len(), 3);
    assert_eq!(
        m.parameters[p0].value, 1000.0,
        "the model itself is unchanged"
    );
}

#[test]
fn optional_fields_select_sampling_excitations_and_sensors() {
    let (text, path) = base();
    let text = text
        + r#"
[[experiment]]
name = "short"
data = "sub/short.mat"
from = "0.05 s"
duration = "0.2 s"
sample_rate = "5 kHz"
excitations = []
sensors = ["knee_az", "knee_ax"]
use = "validation"
weight = 2.5

[[experiment]]
name = "fit"
data = "fit.uff"
"#;
    let m = parse_model(&text, &path).unwrap_or_else(|e| panic!("{e}"));
    let e = &m.experiments[0];
    assert_eq!(e.role, Role::Validation);
    assert_eq!(
        (e.from, e.duration, e.sample_rate, e.weight),
        (0.05, Some(0.2), Some(5000.0), 2.5)
    );
    assert_eq!(e.sensors, Some(vec![0, 2]), "in the model's order");
    let sub = m.for_experiment(0);
    assert_eq!(sub.sampling.n_samples(), 1000);
    assert!(sub.excitations.is_empty());
    let names: Vec<&str> = sub.sensors.iter().map(|s| s.name.as_str()).collect();
    assert_eq!(names, ["knee_ax", "knee_az"]);
    assert_eq!(m.fitted_experiments(), [1]);
}

#[test]
fn each_mistake_names_its_entry_and_field() {
    let cases: &[(&str, &str, &str, &str)] = &[
        (
            "name = \"a\"\ndata = \"a.csv\"\nset = { Q0 = \"20 daN\" }",
            "experiment \"a\"",
            "set.Q0",
            "unknown parameter 'Q0'",
        ),
        (
            "name = \"a\"\ndata = \"a.csv\"\nset = { a_n1 = \"300 daN/um^2\" }",
            "experiment \"a\"",
            "set.a_n1",
            "is identified",
        ),
        (
            "name = \"a\"\ndata = \"a.csv\"\nset = { P0 = \"20 mm\" }",
            "experiment \"a\"",
            "set.P0",
            "dimension",
        ),
        (
            "name = \"a\"",
            "experiment \"a\"",
            "data",
            "'data' is missing",
        ),
        (
            "name = \"a\"\ndata = \"a.csv\"\nsensors = [\"knee_bx\"]",
            "experiment \"a\"",
            "sensors",
            "unknown name 'knee_bx'",
        ),
        (
            "name = \"a\"\ndata = \"a.csv\"\nsensors = [\"cz\"]\n\n[[sensor]]\nname = \"cz\"\nbody = \"knee\"\nat = [0, 0, 0]\ndirection = [0, 0, 1]\nquantity = \"acceleration\"\nnoise = \"1e-3 m/s^2\"\ncandidate = true",
            "experiment \"a\"",
            "sensors",
            "'cz' is a candidate sensor (candidate = true), a place `rfeid design` may choose, not a measured one; a test's sensors are among knee_ax,",
        ),
        (
            "name = \"a\"\ndata = \"a.csv\"\nexcitations = [\"shaker\"]",
            "experiment \"a\"",
            "excitations",
            "unknown name 'shaker'",
        ),
        (
            "name = \"a\"\ndata = \"a.csv\"\nuse = \"test\"",
            "experiment \"a\"",
            "use",
            "unknown use",
        ),
        (
            "name = \"a\"\ndata = \"a.csv\"\nfrom = \"1 s\"",
            "experiment \"a\"",
            "from",
            "must lie in",
        ),
        (
            "name = \"a\"\ndata = \"a.csv\"\nweight = 0",
            "experiment \"a\"",
            "weight",
            "must be positive",
        ),
        (
            "name = \"a[1]\"\ndata = \"a.csv\"",
            "experiment \"a[1]\"",
            "name",
            "brackets",
        ),
        (
            "name = \"a\"\ndata = \"a.csv\"\ncolour = 1",
            "experiment \"a\"",
            "colour",
            "unknown field",
        ),
        (
            "name = \"a\"\ndata = \"a.csv\"\nexcitations = []",
            "experiment \"a\"",
            "excitations",
            "nothing excites this test",
        ),
    ];
    let (text, path) = base();
    for (body, entry, field, says) in cases {
        let t = format!("{text}\n[[experiment]]\n{body}\n");
        let e = parse_model(&t, &path).expect_err(body);
        assert_eq!(
            (e.entry.as_str(), e.field.as_str()),
            (*entry, *field),
            "{e}"
        );
        assert!(e.message.contains(says), "{body}: {e}");
        assert!(e.to_string().contains("model.toml"), "{e}");
    }
    let twice = format!(
        "{text}\n[[experiment]]\nname = \"a\"\ndata = \"a.csv\"\n[[experiment]]\nname = \"a\"\ndata = \"b.csv\"\n"
    );
    let e = parse_model(&twice, &path).unwrap_err();
    assert_eq!(
        (e.field.as_str(), e.message.contains("duplicate")),
        ("name", true)
    );
    // One table `[experiment]` beside `[[experiment]]` entries: named as
    // such, not as the key above it (a comment's or the last parameter's).
    let single = format!(
        "{text}\n[experiment]\nname = \"a\"\ndata = \"a.csv\"\n# x = 1\n[[experiment]]\nname = \"b\"\ndata = \"b.csv\"\n"
    );
    let e = parse_model(&single, &path).unwrap_err();
    assert_eq!(e.field, "experiment", "{e}");
    assert!(
        e.message.contains("write every one as [[experiment]]"),
        "{e}"
    );
    let none_fitted =
        format!("{text}\n[[experiment]]\nname = \"a\"\ndata = \"a.csv\"\nuse = \"validation\"\n");
    let e = parse_model(&none_fitted, &path).unwrap_err();
    assert!(e.message.contains("none is left to fit"), "{e}");
}

#[test]
fn per_experiment_needs_a_box() {
    let (text, path) = base();
    let t = text.replace(
        "name = \"P0\"\nvalue = \"100 daN\"",
        "name = \"P0\"\nvalue = \"100 daN\"\nper_experiment = true",
    );
    let e = parse_model(&t, &path).unwrap_err();
    assert_eq!(
        (e.entry.as_str(), e.field.as_str()),
        ("parameter \"P0\"", "per_experiment")
    );
}
