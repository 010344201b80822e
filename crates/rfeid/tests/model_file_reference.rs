//! `docs/reference/model-file.md` against the model-file reader, so the two
//! cannot drift: every key the reader accepts in each table is in the
//! page's table for it (after its `<!-- keys: NAME -->` marker), and every
//! key there is accepted; likewise the names of the laws, signal types and
//! quantities (`<!-- values: NAME -->`).
//!
//! The reader is asked, not read: a table holding an unknown key is
//! refused with the list of the keys it takes, and an unknown law, type or
//! quantity with the list of the known ones.
use rfeid::io::model_file::parse_model;
use std::collections::BTreeSet;
use std::path::Path;

/// A key no table accepts.
const PROBE: &str = "zzz_probe";

/// One body and one element: enough around a probe for the reader to get
/// to it.
const BASE: &str = r#"
[simulation]
duration = 0.1
sample_rate = 1000.0

[[body]]
name = "b"
mass = 1.0
inertia = [1.0, 1.0, 1.0]
com = [0.0, 0.0, 0.0]
"#;

/// Each documented table and a model text that puts the probe key into it.
fn key_probes() -> Vec<(&'static str, String)> {
    let p = PROBE;
    vec![
        ("file", format!("{p} = 1\n")),
        ("simulation", format!("[simulation]\n{p} = 1\n")),
        ("body", format!("[[body]]\n{p} = 1\n")),
        ("element", format!("[[element]]\n{p} = 1\n")),
        // A component's keys are its law's to judge, once the builder
        // reaches it: the probe needs a body for the element to join.
        (
            "component",
            format!(
                "{BASE}[[element]]\nname = \"e\"\nbody = \"b\"\nto = \"ground\"\nat = [0, 0, 0]\nux = {{ {p} = 1 }}\n"
            ),
        ),
        ("parameter", format!("[[parameter]]\n{p} = 1\n")),
        ("excitation", format!("[[excitation]]\n{p} = 1\n")),
        ("signal", format!("[[excitation]]\nsignal = {{ {p} = 1 }}\n")),
        (
            "tone",
            format!(
                "[[excitation]]\nsignal = {{ type = \"multisine\", components = [{{ {p} = 1 }}] }}\n"
            ),
        ),
        ("sensor", format!("[[sensor]]\n{p} = 1\n")),
        ("sensor.data", format!("[[sensor]]\ndata = {{ {p} = 1 }}\n")),
        ("experiment", format!("[[experiment]]\n{p} = 1\n")),
    ]
}

/// Each documented list of names and a model that names an unknown one.
fn value_probes() -> Vec<(&'static str, String)> {
    let p = PROBE;
    vec![
        (
            "law",
            format!(
                "{BASE}[[element]]\nname = \"e\"\nbody = \"b\"\nto = \"ground\"\nat = [0, 0, 0]\nux = {{ law = \"{p}\", k = 1 }}\n"
            ),
        ),
        (
            "signal.type",
            format!(
                "{BASE}[[excitation]]\nbody = \"b\"\nat = [0, 0, 0]\ndirection = [1, 0, 0]\nsignal = {{ type = \"{p}\" }}\n"
            ),
        ),
        (
            "quantity",
            format!(
                "{BASE}[[sensor]]\nname = \"s\"\nbody = \"b\"\nat = [0, 0, 0]\ndirection = [1, 0, 0]\nquantity = \"{p}\"\n"
            ),
        ),
    ]
}

/// The reader's message on `text`, which it must refuse.
fn refusal(text: &str) -> String {
    match parse_model(text, Path::new("probe.toml")) {
        Ok(_) => panic!("the reader accepted\n{text}"),
        Err(e) => e.message,
    }
}

/// The keys a serde refusal lists: "unknown field `zzz_probe`, expected one
/// of `a`, `b`" (or "expected `a`").
fn accepted_keys(message: &str) -> BTreeSet<String> {
    let (_, list) = message
        .split_once("expected")
        .unwrap_or_else(|| panic!("not an unknown-key refusal: {message}"));
    list.split('`')
        .skip(1)
        .step_by(2)
        .map(str::to_string)
        .collect()
}

/// The names an unknown-name refusal lists: "unknown law 'x' (a, b or c)".
fn known_names(message: &str) -> BTreeSet<String> {
    let list = message
        .rsplit_once('(')
        .and_then(|(_, l)| l.strip_suffix(')'))
        .unwrap_or_else(|| panic!("not an unknown-name refusal: {message}"));
    list.replace(" or ", ", ")
        .split(", ")
        .map(|s| s.trim().to_string())
        .collect()
}

/// The first-column entries of the table after each `<!-- kind: NAME -->`
/// marker of the page: the backticked words, quotes removed.
fn documented(page: &str, kind: &str, name: &str) -> BTreeSet<String> {
    let marker = format!("<!-- {kind}: {name} -->");
    let (_, after) = page
        .split_once(&marker)
        .unwrap_or_else(|| panic!("docs/reference/model-file.md has no {marker}"));
    after
        .lines()
        .skip_while(|l| l.trim().is_empty())
        .take_while(|l| l.starts_with('|'))
        .skip(2) // the header and its rule
        .flat_map(|row| {
            let first = row.split('|').nth(1).unwrap_or_default();
            first
                .split('`')
                .skip(1)
                .step_by(2)
                .map(|w| w.trim_matches('"').to_string())
                .collect::<Vec<_>>()
        })
        .collect()
}

fn page() -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs/reference/model-file.md");
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// Each probe's list, read from the reader's refusal by `list`, against
/// the page's table after `<!-- kind: NAME -->`.
fn compare(kind: &str, probes: Vec<(&str, String)>, list: fn(&str) -> BTreeSet<String>) {
    let page = page();
    for (name, text) in probes {
        let reader = list(&refusal(&text));
        assert!(reader.len() >= 3, "{name}: {reader:?}");
        let listed = documented(&page, kind, name);
        assert_eq!(
            listed, reader,
            "docs/reference/model-file.md, {kind} of {name}: documented (left) against the reader's (right)"
        );
    }
}

#[test]
fn every_key_the_reader_accepts_is_documented_and_no_other() {
    compare("keys", key_probes(), accepted_keys);
}

#[test]
fn every_law_signal_type_and_quantity_is_documented_and_no_other() {
    compare("values", value_probes(), known_names);
}
