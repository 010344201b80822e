//! Every kind of bad model file is an error that names the entry and the
//! field, says what is wrong, and points (by its byte span) at the
//! offending text (SPEC §3: "a clear error naming the file, the entry and
//! the field"). Each case edits one thing in a valid file.
use rfeid::io::model_file::{parse_model, ModelFileError};
use std::path::Path;

const VALID: &str = r#"
[simulation]
duration = 0.1
sample_rate = 1000.0

[[body]]
name = "column"
mass = "900 kg"
inertia = [219.0, 210.75, 45.75]
com = [0.0, 0.0, 0.8]

[[body]]
name = "knee"
mass = 320.0
inertia = [18.47, 10.8, 18.47]
com = [0.0, 0.65, 0.75]
axes = [[1, 0, 0], [0, 1, 0], [0, 0, 1]]

[[element]]
name = "slide"
body = "knee"
to = "column"
at = [-0.2, 0.3, 0.95]
axes = [[0, 1, 0], [0, 0, 1], [1, 0, 0]]
ux = { law = "power", a = "a_n", m = 2.0, c = "h_n" }
uy = { k = "a_t", c = 100.0 }

[[element]]
name = "pad"
body = "column"
to = "ground"
at = [0, 0, 0]
uz = { k = "6e7 N/m" }

[[parameter]]
name = "a_n"
value = "380 daN/um^2"
min = "190 daN/um^2"
max = "570 daN/um^2"

[[parameter]]
name = "a_t"
value = "15 daN/um"

[[parameter]]
name = "h_n"
value = "3.6 daN*ms/um"
min = "1.8 daN*ms/um"
max = "5.4 daN*ms/um"

[[excitation]]
name = "exciter"
body = "knee"
reaction = "column"
at = [0.12, 0.45, 0.85]
direction = [1, 2, 1]
signal = { type = "sine", amplitude = "100 daN", frequency = "80 Hz" }

[[sensor]]
name = "knee_ax"
body = "knee"
at = [0.0, 0.65, 0.75]
direction = [1, 0, 0]
quantity = "acceleration"
"#;

/// `VALID` with the first `old` after `anchor` replaced by `new`.
fn edit(anchor: &str, old: &str, new: &str) -> String {
    let a = VALID
        .find(anchor)
        .unwrap_or_else(|| panic!("no anchor {anchor}"));
    let i = a + VALID[a..]
        .find(old)
        .unwrap_or_else(|| panic!("no {old} after {anchor}"));
    format!("{}{}{}", &VALID[..i], new, &VALID[i + old.len()..])
}

/// The error of reading `text` as `dir/model.toml`, if any.
fn error_of(text: &str) -> Option<ModelFileError> {
    parse_model(text, Path::new("dir/model.toml")).err()
}

/// One bad file and what its error must say.
struct Case {
    what: &'static str,
    text: String,
    entry: &'static str,
    field: &'static str,
    message: &'static str,
    /// The text the span must cover (None: no span).
    span: Option<&'static str>,
}

fn case(
    what: &'static str,
    text: String,
    entry: &'static str,
    field: &'static str,
    message: &'static str,
    span: Option<&'static str>,
) -> Case {
    Case {
        what,
        text,
        entry,
        field,
        message,
        span,
    }
}

fn append(extra: &str) -> String {
    format!("{VALID}{extra}")
}

/// `VALID` with the pad's `uz` given the law `keys` and a parameter
/// `f_pad` with the lines `value_lines` (its value and box).
fn pad_law(keys: &str, value_lines: &str) -> String {
    let text = edit(
        r#"name = "pad""#,
        r#"uz = { k = "6e7 N/m" }"#,
        &format!("uz = {{ {keys} }}"),
    );
    format!("{text}\n[[parameter]]\nname = \"f_pad\"\n{value_lines}\n")
}

const SLIDE: &str = "name = \"slide\"";
const KNEE: &str = "name = \"knee\"";
const EXC: &str = "name = \"exciter\"";
const SENSOR: &str = "name = \"knee_ax\"";

fn cases() -> Vec<Case> {
    let slide = r#"element "slide""#;
    let knee = r#"body "knee""#;
    let exc = r#"excitation "exciter""#;
    let pad = r#"element "pad", component uz"#;
    vec![
        // Names.
        case("unknown body", edit(SLIDE, r#"body = "knee""#, r#"body = "kne""#), slide, "body", "unknown body 'kne'", Some(r#""kne""#)),
        case("unknown 'to' body", edit(SLIDE, r#"to = "column""#, r#"to = "colum""#), slide, "to", "unknown body 'colum'", Some(r#""colum""#)),
        case("unknown reaction body", edit(EXC, r#"reaction = "column""#, r#"reaction = "colunm""#), exc, "reaction", "unknown body 'colunm'", Some(r#""colunm""#)),
        case("unknown sensor body", edit(SENSOR, r#"body = "knee""#, r#"body = "nee""#), r#"sensor "knee_ax""#, "body", "unknown body 'nee'", Some(r#""nee""#)),
        case("duplicate body", edit(KNEE, KNEE, r#"name = "column""#), r#"body "column""#, "name", "duplicate body name", Some(r#""column""#)),
        case("duplicate element", edit(r#"name = "pad""#, r#""pad""#, r#""slide""#), slide, "name", "duplicate element name", Some(r#""slide""#)),
        case("duplicate parameter", edit(r#"name = "a_t""#, r#""a_t""#, r#""a_n""#), r#"parameter "a_n""#, "name", "duplicate parameter name", Some(r#""a_n""#)),
        case("duplicate sensor", append("\n[[sensor]]\nname = \"knee_ax\"\nbody = \"knee\"\nat = [0, 0, 0]\ndirection = [0, 1, 0]\nquantity = \"velocity\"\n"), r#"sensor "knee_ax""#, "name", "duplicate sensor name", Some(r#""knee_ax""#)),
        case("'ground' as a body name", edit(KNEE, r#""knee""#, r#""ground""#), r#"body "ground""#, "name", "reserved", Some(r#""ground""#)),
        case("unknown parameter", edit(SLIDE, r#"k = "a_t""#, r#"k = "a_tx""#), r#"element "slide", component uy"#, "k", "unknown parameter 'a_tx'", Some(r#""a_tx""#)),
        case("unused parameter", append("\n[[parameter]]\nname = \"spare\"\nvalue = 1.0\n"), r#"parameter "spare""#, "name", "never used", Some(r#""spare""#)),
        // Bodies.
        case("zero mass", edit(KNEE, "mass = 320.0", "mass = 0.0"), knee, "mass", "must be positive", Some("0.0")),
        case("negative mass", edit(KNEE, "mass = 320.0", "mass = -320.0"), knee, "mass", "must be positive", Some("-320.0")),
        case("NaN mass", edit(KNEE, "mass = 320.0", "mass = nan"), knee, "mass", "not a finite number", Some("nan")),
        case("infinite mass", edit(KNEE, "mass = 320.0", "mass = inf"), knee, "mass", "not a finite number", Some("inf")),
        case("NaN mass with a unit", edit(KNEE, "mass = 320.0", r#"mass = "nan kg""#), knee, "mass", "", Some(r#""nan kg""#)),
        case("zero inertia", edit(KNEE, "[18.47, 10.8, 18.47]", "[18.47, 0, 18.47]"), knee, "inertia", "must be positive", Some("0")),
        case("negative inertia", edit(KNEE, "[18.47, 10.8, 18.47]", "[18.47, 10.8, -1.5]"), knee, "inertia", "must be positive", Some("-1.5")),
        case("skew body axes", edit(KNEE, "[[1, 0, 0], [0, 1, 0], [0, 0, 1]]", "[[1, 0, 0], [0.1, 1, 0], [0, 0, 1]]"), knee, "axes", "not orthonormal", Some("[[1, 0, 0], [0.1, 1, 0], [0, 0, 1]]")),
        case("left-handed body axes", edit(KNEE, "[[1, 0, 0], [0, 1, 0], [0, 0, 1]]", "[[1, 0, 0], [0, 1, 0], [0, 0, -1]]"), knee, "axes", "left-handed", Some("[[1, 0, 0], [0, 1, 0], [0, 0, -1]]")),
        case("missing com", edit(KNEE, "com = [0.0, 0.65, 0.75]\n", ""), knee, "com", "'com' is missing", None),
        // Elements.
        case("skew element axes", edit(SLIDE, "[1, 0, 0]]", "[1, 0, 0.01]]"), slide, "axes", "not orthonormal", Some("[[0, 1, 0], [0, 0, 1], [1, 0, 0.01]]")),
        case("left-handed element axes", edit(SLIDE, "[[0, 1, 0], [0, 0, 1]", "[[0, 0, 1], [0, 1, 0]"), slide, "axes", "left-handed", Some("[[0, 0, 1], [0, 1, 0], [1, 0, 0]]")),
        case("element joining a body to itself", edit(SLIDE, r#"to = "column""#, r#"to = "knee""#), slide, "to", "joins a body to itself", Some(r#""knee""#)),
        case("exponent below 1", edit(SLIDE, "m = 2.0", "m = 0.5"), r#"element "slide", component ux"#, "m", "at least 1", Some("0.5")),
        case("k in a power law", edit(SLIDE, "m = 2.0,", "m = 2.0, k = 5.0,"), r#"element "slide", component ux"#, "k", "does not belong to the power law", Some("5.0")),
        case("negative stiffness", edit(r#"name = "pad""#, r#""6e7 N/m""#, r#""-6e7 N/m""#), r#"element "pad", component uz"#, "k", "must not be negative", Some(r#""-6e7 N/m""#)),
        case("power key in a friction law", edit(SLIDE, r#"law = "power", a = "a_n", m = 2.0"#, r#"law = "friction", f = "30 N", m = 2.0"#), r#"element "slide", component ux"#, "m", "'m' does not belong to the friction law (it takes k, f, f_neg, fs, vs, smoothing, c)", Some("2.0")),
        case("contact key in a linear law", edit(SLIDE, r#"law = "power", a = "a_n", m = 2.0"#, r#"law = "linear", k = "1e8 N/m", gap = 0.0"#), r#"element "slide", component ux"#, "gap", "'gap' does not belong to the linear law (it takes k, c)", Some("0.0")),
        case("contact with k and a power law", edit(SLIDE, r#"law = "power", a = "a_n", m = 2.0"#, r#"law = "contact", k = "1e8 N/m", a = "a_n", m = 2.0"#), r#"element "slide", component ux"#, "a", "a contact's spring is k, or a and m, not both", Some("\"a_n\"")),
        case("contact with k and a reference", edit(SLIDE, r#"law = "power", a = "a_n", m = 2.0"#, r#"law = "contact", k = "1e8 N/m", reference = "1 um""#), r#"element "slide", component ux"#, "reference", "'reference' belongs to a power-law contact (a and m), not to k", Some("\"1 um\"")),
        case("friction key in a contact", edit(SLIDE, r#"law = "power", a = "a_n", m = 2.0"#, r#"law = "contact", k = "1e8 N/m", f = "30 N""#), r#"element "slide", component ux"#, "f", "'f' does not belong to the contact law (it takes k, a, m, reference, c, gap)", Some("\"30 N\"")),
        case("law not a name", edit(SLIDE, r#"law = "power""#, "law = 2"), r#"element "slide", component ux"#, "law", "the law is a name in quotes (linear, power, friction, bouc-wen or contact)", Some("2")),
        case("unknown law", edit(SLIDE, r#""power""#, r#""quadratic""#), r#"element "slide", component ux"#, "law", "unknown law 'quadratic'", Some(r#""quadratic""#)),
        case("unknown law with another law's keys", edit(SLIDE, r#"law = "power", a = "a_n", m = 2.0"#, r#"law = "coulomb", f = "30 N""#), r#"element "slide", component ux"#, "law", "unknown law 'coulomb'", Some(r#""coulomb""#)),
        case("misspelt law with its keys", edit(SLIDE, r#"law = "power", a = "a_n", m = 2.0"#, r#"law = "fricton", f = "30 N""#), r#"element "slide", component ux"#, "law", "unknown law 'fricton' (linear, power, friction, bouc-wen or contact); did you mean 'friction'?", Some(r#""fricton""#)),
        case("law in capitals", edit(SLIDE, r#"law = "power", a = "a_n", m = 2.0"#, r#"law = "Friction", f = "30 N""#), r#"element "slide", component ux"#, "law", "unknown law 'Friction' (linear, power, friction, bouc-wen or contact); did you mean 'friction'?", Some(r#""Friction""#)),
        case("law without its hyphen", edit(SLIDE, r#"law = "power", a = "a_n", m = 2.0"#, r#"law = "boucwen", alpha = 1.0, beta = 1.0, gamma = 0.5, d = 0.5"#), r#"element "slide", component ux"#, "law", "unknown law 'boucwen' (linear, power, friction, bouc-wen or contact); did you mean 'bouc-wen'?", Some(r#""boucwen""#)),
        // A law key naming a parameter: its nominal value, and its whole box, obey the law's rule.
        case("negative friction force as a parameter", pad_law(r#"law = "friction", f = "f_pad""#, r#"value = "-5 N""#), pad, "f", "parameter 'f_pad' is -5 N: a friction force must not be negative (f ≥ 0)", Some(r#""f_pad""#)),
        case("friction force's box below 0", pad_law(r#"law = "friction", f = "f_pad""#, "value = \"5 N\"\nmin = \"-10 N\"\nmax = \"50 N\""), pad, "f", "parameter 'f_pad' has the box [-10 N, 50 N], which reaches values the law refuses: a friction force must not be negative (f ≥ 0)", Some(r#""f_pad""#)),
        case("smoothing's box below 0", pad_law(r#"law = "friction", f = "30 N", smoothing = "f_pad""#, "value = \"1 mm/s\"\nmin = \"-1 mm/s\"\nmax = \"5 mm/s\""), pad, "smoothing", "[-1 mm/s, 5 mm/s], which reaches values the law refuses: a velocity scale must be positive (smoothing > 0)", Some(r#""f_pad""#)),
        case("Stribeck velocity's box below 0", pad_law(r#"law = "friction", f = "30 N", fs = "40 N", vs = "f_pad""#, "value = \"5 mm/s\"\nmin = \"-5 mm/s\"\nmax = \"10 mm/s\""), pad, "vs", "(vs > 0)", Some(r#""f_pad""#)),
        case("Bouc-Wen exponent's box below 1", pad_law(r#"law = "bouc-wen", alpha = "1e4 N/m", beta = 1e3, gamma = 0.8, d = -1.1, n = "f_pad""#, "value = 1.5\nmin = 0.5\nmax = 2"), pad, "n", "parameter 'f_pad' has the box [0.5, 2], which reaches values the law refuses: the Bouc–Wen exponent must be at least 1 (n ≥ 1)", Some(r#""f_pad""#)),
        case("fixed negative smoothing", pad_law(r#"law = "friction", f = "30 N", smoothing = "-1 mm/s", c = "f_pad""#, r#"value = "1 N*s/m""#), pad, "smoothing", "must be positive (found -0.001)", Some(r#""-1 mm/s""#)),
        case("Bouc-Wen beta with a unit while n is a parameter", pad_law(r#"law = "bouc-wen", alpha = "1e4 N/m", beta = "1e3 1/m", gamma = 0.8, d = -1.1, n = "f_pad""#, "value = 1.5"), pad, "beta", "n is the parameter 'f_pad', so beta's unit, N^(1−n)/m (1/N^0.5/m at n = 1.5), changes with n: write beta (or its parameter's value, min and max) as a bare number, taken in N and m at every n", Some(r#""1e3 1/m""#)),
        case("damping's box below 0", edit(r#"name = "h_n""#, r#"min = "1.8 daN*ms/um""#, r#"min = "-1.8 daN*ms/um""#), r#"element "slide", component ux"#, "c", "parameter 'h_n' has the box [-1.8 daN*ms/um, 5.4 daN*ms/um], which reaches values the law refuses: a damping must not be negative (c ≥ 0)", Some(r#""h_n""#)),
        // Excitations and sensors.
        case("zero excitation direction", edit(EXC, "direction = [1, 2, 1]", "direction = [0, 0, 0]"), exc, "direction", "zero", Some("[0, 0, 0]")),
        case("zero sensor direction", edit(SENSOR, "direction = [1, 0, 0]", "direction = [0, 0, 0.0]"), r#"sensor "knee_ax""#, "direction", "zero", Some("[0, 0, 0.0]")),
        case("reaction on the excited body", edit(EXC, r#"reaction = "column""#, r#"reaction = "knee""#), exc, "reaction", "itself", Some(r#""knee""#)),
        case("key of another signal type", edit(EXC, r#"frequency = "80 Hz""#, r#"frequency = "80 Hz", f0 = 3.0"#), exc, "signal.f0", "does not apply to a sine", Some("3.0")),
        case("unknown quantity", edit(SENSOR, r#""acceleration""#, r#""jerk""#), r#"sensor "knee_ax""#, "quantity", "unknown quantity 'jerk'", Some(r#""jerk""#)),
        case("noise as a boolean", edit(SENSOR, r#"quantity = "acceleration""#, "quantity = \"acceleration\"\nnoise = true"), r#"sensor "knee_ax""#, "noise", "a boolean (true) is not allowed here: expected a number or a string holding a quantity with a unit (\"15 daN/um\"); parameters are not allowed here", Some("true")),
        case("noise as a parameter", edit(SENSOR, r#"quantity = "acceleration""#, "quantity = \"acceleration\"\nnoise = \"a_t\""), r#"sensor "knee_ax""#, "noise", "parameters are not allowed here", Some(r#""a_t""#)),
        case("stiffness as a boolean", edit(SLIDE, r#"k = "a_t""#, "k = false"), r#"element "slide", component uy"#, "k", "a boolean (false) is not allowed here: expected a number, a string holding a quantity with a unit (\"15 daN/um\") or a parameter's name", Some("false")),
        case("parameter value as a boolean", edit(r#"name = "a_t""#, r#""15 daN/um""#, "true"), r#"parameter "a_t""#, "value", "a boolean (true) is not allowed here", Some("true")),
        // Parameters.
        case("value outside the box", edit(r#"name = "a_n""#, r#"value = "380 daN/um^2""#, r#"value = "600 daN/um^2""#), r#"parameter "a_n""#, "value", "outside [min, max]", Some(r#""600 daN/um^2""#)),
        case("min above max", edit(r#"name = "h_n""#, r#"min = "1.8 daN*ms/um""#, r#"min = "6 daN*ms/um""#), r#"parameter "h_n""#, "min", "must be below max", Some(r#""6 daN*ms/um""#)),
        case("min equal to max", edit(r#"name = "h_n""#, r#"min = "1.8 daN*ms/um""#, r#"min = "5.4 daN*ms/um""#), r#"parameter "h_n""#, "min", "must be below max", Some(r#""5.4 daN*ms/um""#)),
        case("NaN parameter value", edit(r#"name = "a_t""#, r#""15 daN/um""#, "nan"), r#"parameter "a_t""#, "value", "not a finite number", Some("nan")),
        case("parameter unit of the wrong dimension for its use", edit(r#"name = "a_t""#, r#""15 daN/um""#, r#""15 daN""#), r#"parameter "a_t""#, "value", "the dimension N, but the parameter is used as N/m", Some(r#""15 daN""#)),
        case("parameter box unit of the wrong dimension", edit(r#"name = "h_n""#, r#"max = "5.4 daN*ms/um""#, r#"max = "5.4 daN/um""#), r#"parameter "h_n""#, "max", "dimension", Some(r#""5.4 daN/um""#)),
        // Units.
        case("unit of the wrong dimension", edit(KNEE, "mass = 320.0", r#"mass = "3 N/m""#), knee, "mass", "has the dimension N/m, but mass needs kg", Some(r#""3 N/m""#)),
        case("unknown unit", edit(KNEE, "mass = 320.0", r#"mass = "3 kgg""#), knee, "mass", "", Some(r#""3 kgg""#)),
        case("duration in kilograms", VALID.replace("duration = 0.1", r#"duration = "0.1 kg""#), "[simulation]", "duration", "dimension", Some(r#""0.1 kg""#)),
        // Unknown keys (typos).
        case("unknown body key", edit(KNEE, "mass = 320.0", "masss = 320.0"), knee, "masss", "unknown field `masss`", Some("masss")),
        case("unknown component key", edit(SLIDE, "ux = { law", "ux = { lawz = 1, law"), r#"element "slide", component ux"#, "lawz", "unknown field `lawz`", Some("lawz")),
        case("unknown top-level key", format!("gravty = [0, 0, -9.81]\n{VALID}"), "", "gravty", "unknown field `gravty`", Some("gravty")),
        case("top-level key below a table's header", VALID.replace("sample_rate = 1000.0", "sample_rate = 1000.0\ngravity = [0, 0, -9.81]"), "[simulation]", "gravity", "'gravity' is a top-level key: write it above the first [table] header", Some("gravity")),
        // Simulation.
        case("missing [simulation]", VALID.replace("[simulation]\nduration = 0.1\nsample_rate = 1000.0\n", ""), "[simulation]", "", "no [simulation] table", None),
        case("zero sample rate", VALID.replace("sample_rate = 1000.0", "sample_rate = 0.0"), "[simulation]", "sample_rate", "must be positive", Some("0.0")),
        case("zero substeps", VALID.replace("sample_rate = 1000.0", "sample_rate = 1000.0\nsubsteps = 0"), "[simulation]", "substeps", "whole number from 1 to 1000", Some("0")),
    ]
}

#[test]
fn the_valid_file_parses() {
    let m = parse_model(VALID, Path::new("dir/model.toml")).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(m.bodies.len(), 2);
    assert_eq!(m.identified().len(), 2);
}

#[test]
fn every_bad_file_names_entry_field_and_problem_and_points_at_it() {
    let mut failures = Vec::new();
    let cases = cases();
    for c in &cases {
        let Some(e) = error_of(&c.text) else {
            failures.push(format!("{}: parsed without error", c.what));
            continue;
        };
        let span_text = e.span.clone().map(|s| &c.text[s]);
        let mut wrong = Vec::new();
        if e.entry != c.entry {
            wrong.push(format!("entry {:?} (want {:?})", e.entry, c.entry));
        }
        if e.field != c.field {
            wrong.push(format!("field {:?} (want {:?})", e.field, c.field));
        }
        if !e.message.contains(c.message) || e.message.is_empty() {
            wrong.push(format!(
                "message {:?} (want it to contain {:?})",
                e.message, c.message
            ));
        }
        if c.span.is_some() && span_text != c.span {
            wrong.push(format!("span {span_text:?} (want {:?})", c.span));
        }
        if e.path != Path::new("dir/model.toml") || !e.to_string().starts_with("dir/model.toml: ") {
            wrong.push(format!(
                "display {:?} does not name the file",
                e.to_string()
            ));
        }
        if !wrong.is_empty() {
            failures.push(format!("{}: {}\n    error: {e}", c.what, wrong.join("; ")));
        }
    }
    println!("{} cases", cases.len());
    assert!(
        failures.is_empty(),
        "{} of {} cases wrong:\n{}",
        failures.len(),
        cases.len(),
        failures.join("\n")
    );
}

/// A duplicate's span points at the second definition, not the first.
#[test]
fn a_duplicate_points_at_the_second_definition() {
    let text = edit(KNEE, KNEE, r#"name = "column""#);
    let e = error_of(&text).unwrap();
    let first = text.find(r#""column""#).unwrap();
    assert!(e.span.unwrap().start > first);
}

/// Bouc–Wen's β in a reciprocal unit parses (`"1e3 1/m"`), and the unit a
/// wrong β is told it needs is written as the reader accepts it.
#[test]
fn bouc_wen_beta_takes_the_unit_its_message_names() {
    let law = |beta: &str, n: &str| {
        pad_law(
            &format!(
                r#"law = "bouc-wen", alpha = "1e4 N/m", beta = "{beta}", gamma = 0.8, d = -1.1, n = {n}, c = "f_pad""#
            ),
            r#"value = "1 N*s/m""#,
        )
    };
    let m = parse_model(&law("1e3 1/m", "1"), Path::new("dir/model.toml"))
        .unwrap_or_else(|e| panic!("{e}"));
    let beta = match &m.elements[1].components[0].law {
        rfeid::model::Law::BoucWen(bw) => bw.beta,
        other => panic!("{other:?}"),
    };
    assert_eq!(beta, rfeid::model::Value::Fixed(1e3));
    for (n, needs) in [("1", "1/m"), ("2", "1/N/m"), ("1.5", "1/N^0.5/m")] {
        let e = error_of(&law("1e3 N", n)).expect("a force is no beta");
        let said = format!("but beta needs {needs}");
        assert!(e.message.ends_with(&said), "n = {n}: {}", e.message);
        assert!(
            error_of(&law(&format!("1e3 {needs}"), n)).is_none(),
            "n = {n}: 1e3 {needs}"
        );
    }
}
