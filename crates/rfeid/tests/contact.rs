//! The contact law (SPEC §1, `law = "contact"`) in whole simulations: a
//! slide bolted to a base through a contact that lifts off in every
//! tension peak (`examples/contact`). Sensitivities to every key against
//! finite differences at a fixed step sequence on both kernels, through
//! the located openings and closings, touching at rest and preloaded; the
//! convergence of the response with the steps per sample; a contact that
//! never opens is its linear spring.
use crate::common;

use common::*;
use rfeid::model::Model;
use rfeid::simulation::steps::integrator;
use rfeid::simulation::{Kernel, Simulator, Workspace};

/// The text of `examples/contact/model.toml` and its contact's law line.
fn example() -> (String, &'static str) {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../examples/contact/model.toml"
    );
    let text = std::fs::read_to_string(path).unwrap();
    let law = r#"uz = { law = "contact", k = "k_contact", c = "c_contact", gap = 0.0 }"#;
    assert!(text.contains(law), "the example's contact");
    (text, law)
}

/// The example's model with the contact's gap a parameter, and `{GAP}` its
/// value.
fn contact_model(gap: &str) -> Model {
    let (text, law) = example();
    let text = text.replace(
        law,
        r#"uz = { law = "contact", k = "k_contact", c = "c_contact", gap = "gap" }"#,
    ) + &format!("\n[[parameter]]\nname = \"gap\"\nvalue = \"{gap}\"\n");
    // Displacements and velocities: an acceleration jumps where the contact
    // closes at a speed (its damper's c ṡ), so a sample at that instant is
    // not differentiable in the parameters.
    let text = text.replace("quantity = \"acceleration\"", "quantity = \"displacement\"")
        + "\n[[sensor]]\nname = \"slide_v\"\nbody = \"slide\"\nat = [0.0, 0.0, 0.2]\ndirection = [0, 0, 1]\nquantity = \"velocity\"\n";
    model(&text)
}

/// The sensitivities of the slide's and the base's displacements and the
/// slide's velocity to the contact's k, c and gap at 32 steps per sample,
/// against the five-point stencil of runs at the same steps
/// ([`stencil_errors`]), each column's error in units of its RMS, to 1e-6;
/// the kernels agree to rounding. Touching at rest (gap 0), preloaded (−5 µm) and open at rest
/// (+2 µm). At gap 0 exactly the static equilibrium has a kink in the gap
/// (a preload for gap < 0, none for gap > 0), so no derivative in it
/// exists there: only k and c are compared. The stencil's steps: 1e-6 of
/// k, 1e-5 of c, 1e-10 m of the gap (measured: at 1e-9 m the stencil's own
/// error is 2.5e-5 of the column).
///
/// At coarser steps: [`sensitivities_at_coarse_steps_are_the_computed_responses_derivative`].
#[test]
fn sensitivities_through_openings_and_closings_match_finite_differences() {
    let (errors, columns) = stencil_errors(32);
    for (what, err) in errors {
        assert!(err < 1e-6, "{what}: {err:.2e}");
    }
    for (gap, columns) in columns {
        assert_kernels_agree(gap, &columns);
    }
}

/// The response converges with the steps per sample through the openings
/// and closings: the slide's acceleration at 1, 2, 4, 8 and 16 steps per
/// sample against 64, each error in units of the signal's RMS, falls
/// below 1e-6 at 16 and at least fourfold with each doubling from 1 to 8.
#[test]
fn the_response_converges_through_openings_and_closings() {
    let model = contact_model("-5e-6 m");
    let run = |k: usize| simulate(&model, &model.nominal(), Some(integrator(k))).values;
    let reference = run(64);
    let scale = rms(&reference);
    let errors: Vec<f64> = [1, 2, 4, 8, 16]
        .into_iter()
        .map(|k| {
            let y = run(k);
            let diff: Vec<f64> = y.iter().zip(&reference).map(|(a, b)| a - b).collect();
            rms(&diff) / scale
        })
        .collect();
    let shown: Vec<String> = errors.iter().map(|e| format!("{e:.2e}")).collect();
    eprintln!(
        "errors at 1, 2, 4, 8, 16 steps per sample: {}",
        shown.join(", ")
    );
    assert!(errors[4] < 1e-6, "{errors:?}");
    for w in errors[..4].windows(2) {
        assert!(w[1] < 0.25 * w[0], "{errors:?}");
    }
}

/// A contact preloaded so that it never opens under a small force is its
/// spring and damper: the same response as the linear component with the
/// same k and c, about the same equilibrium (accelerations to 1e-9 of
/// their RMS).
#[test]
fn a_contact_that_never_opens_is_its_linear_spring() {
    let small = |text: String| text.replace(" N\", frequency", " mN\", frequency");
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../examples/contact/model.toml"
    );
    let text = small(std::fs::read_to_string(path).unwrap());
    let contact = r#"uz = { law = "contact", k = "k_contact", c = "c_contact", gap = 0.0 }"#;
    assert!(text.contains(contact));
    let preloaded = text.replace(contact, &contact.replace("gap = 0.0", "gap = -5e-6"));
    let linear = text.replace(contact, r#"uz = { k = "k_contact", c = "c_contact" }"#);
    let (a, b) = (model(&preloaded), model(&linear));
    let run = |m: &Model| simulate(m, &m.nominal(), Some(integrator(4))).values;
    let (ya, yb) = (run(&a), run(&b));
    let diff: Vec<f64> = ya.iter().zip(&yb).map(|(x, y)| x - y).collect();
    let err = max_abs(&diff) / rms(&yb);
    eprintln!("preloaded contact against its linear spring: {err:.2e} of the RMS");
    assert!(err < 1e-9, "{err:.2e}");
}

/// Two preloaded contacts pressing a slide from above and below (a gib),
/// balanced at q = 0, each with its own k and gap: the static deformation
/// is zero while each carries its preload, and the sensitivities (which
/// take each force as its change from the static one) agree with the
/// five-point stencil to 1e-6 of each column's RMS at 32 steps per sample.
#[test]
fn opposed_preloaded_contacts_balanced_at_rest_have_exact_sensitivities() {
    let text = r#"
[simulation]
duration = "0.5 s"
sample_rate = "2 kHz"

[[body]]
name = "slide"
mass = "20 kg"
inertia = [0.5, 0.5, 0.5]
com = [0.0, 0.0, 0.0]

[[element]]
name = "top"
body = "slide"
to = "ground"
at = [0.0, 0.0, 0.0]
uz = { law = "contact", k = "k_top", c = "300 N*s/m", gap = "gap_top" }

[[element]]
name = "bottom"
body = "slide"
to = "ground"
at = [0.0, 0.0, 0.0]
axes = [[1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, -1.0]]
uz = { law = "contact", k = "k_bottom", c = "300 N*s/m", gap = "gap_bottom" }

[[excitation]]
body = "slide"
at = [0.0, 0.0, 0.0]
direction = [0, 0, 1]
signal = { type = "multisine", components = [{ amplitude = "150 N", frequency = "31 Hz" }, { amplitude = "90 N", frequency = "83 Hz", phase = 1.0 }] }

[[sensor]]
name = "z"
body = "slide"
at = [0.0, 0.0, 0.0]
direction = [0, 0, 1]
quantity = "displacement"

[[sensor]]
name = "v"
body = "slide"
at = [0.0, 0.0, 0.0]
direction = [0, 0, 1]
quantity = "velocity"

[[parameter]]
name = "k_top"
value = "2e7 N/m"

[[parameter]]
name = "k_bottom"
value = "2e7 N/m"

[[parameter]]
name = "gap_top"
value = "-5e-6 m"

[[parameter]]
name = "gap_bottom"
value = "-5e-6 m"
"#;
    let model = model(text);
    let wrt: Vec<usize> = (0..model.parameters.len()).collect();
    let x = model.nominal();
    let sim = Simulator::with_integrator(&model, integrator(32));
    let mut ws = Workspace::default();
    let (out, cols) = sensitivity_columns(&sim, &mut ws, &x, &wrt);
    // Both contacts open in turn: the slide moves past ±5 µm.
    assert!(
        max_abs(out.sensor(0)) > 1e-5,
        "{:e}",
        max_abs(out.sensor(0))
    );
    for (&p, col) in wrt.iter().zip(cols) {
        let name = &model.parameters[p].name;
        let h = match name.starts_with("gap") {
            true => 1e-10,
            false => 1e-6 * x[p],
        };
        let err = column_error(&col, &five_point(&sim, &mut ws, &x, p, h));
        eprintln!("{name}: {err:.2e} of the column's RMS");
        assert!(err < 1e-6, "{name}: {err:.2e}");
    }
}

/// Each gap's sensitivity columns, the dense kernel's then the sparse one's.
type GapColumns = Vec<(&'static str, Vec<Vec<f64>>)>;

/// The sensitivities' errors against the five-point stencil at a fixed
/// `steps` per sample, for each gap and key on both kernels (each column's
/// error in units of its RMS, named), and each gap's columns, the dense
/// kernel's then the sparse one's.
fn stencil_errors(steps: usize) -> (Vec<(String, f64)>, GapColumns) {
    let (mut errors, mut by_gap) = (Vec::new(), Vec::new());
    for gap in ["0 m", "-5e-6 m", "2e-6 m"] {
        let model = contact_model(gap);
        let wrt: Vec<usize> = (0..model.parameters.len())
            .filter(|&p| gap != "0 m" || model.parameters[p].name != "gap")
            .collect();
        let stencil = |name: &str, value: f64| match name {
            "gap" => 1e-10,
            "k_contact" => 1e-6 * value,
            _ => 1e-5 * value,
        };
        let mut columns = Vec::new();
        for (what, err, col) in kernel_errors(&model, &wrt, steps, stencil) {
            let what = format!("{steps} steps, gap {gap}, {what}");
            eprintln!("{what}: {err:.2e} of the column's RMS");
            errors.push((what, err));
            columns.push(col);
        }
        by_gap.push((gap, columns));
    }
    (errors, by_gap)
}

/// Each of `wrt`'s sensitivity columns at a fixed `steps` per sample on
/// both kernels (the dense kernel's first), with its error against the
/// five-point stencil of step `stencil(name, value)`, in units of the
/// column's RMS: (kernel and parameter, error, column).
fn kernel_errors(
    model: &Model,
    wrt: &[usize],
    steps: usize,
    stencil: impl Fn(&str, f64) -> f64,
) -> Vec<(String, f64, Vec<f64>)> {
    let x = model.nominal();
    let mut out = Vec::new();
    for kernel in [Kernel::Dense, Kernel::Sparse] {
        let mut sim = Simulator::with_integrator(model, integrator(steps));
        sim.set_kernel(kernel);
        let mut ws = Workspace::default();
        let (_, cols) = sensitivity_columns(&sim, &mut ws, &x, wrt);
        for (&p, col) in wrt.iter().zip(cols) {
            let name = &model.parameters[p].name;
            let h = stencil(name, x[p]);
            let err = column_error(&col, &five_point(&sim, &mut ws, &x, p, h));
            out.push((format!("{kernel:?}, {name}"), err, col));
        }
    }
    out
}

/// At the coarse steps the identification takes (1 per sample in the
/// search, a few at its end), the sensitivities are still the derivative
/// of the computed response: every located instant moves with the
/// parameters by its own derivative, taken from the trial step's
/// sensitivities (`contact_events::contact_instant_rates`), and the step
/// split there takes its pieces' own derivative in that instant (the split
/// column, `split_shifts`), not the flow's jump condition.
///
/// Measured: at 4 steps per sample 3.0e-9 to 1.1e-7, at 1 step 4.2e-8 to
/// 2.8e-7 (with the jump condition: 1.9e-7 to 1.5e-6, the 5 µm preload's k
/// and c missing 1e-6; before the instants' own derivatives, 7.1e-4 to
/// 6.3e-3).
#[test]
fn sensitivities_at_coarse_steps_are_the_computed_responses_derivative() {
    for (what, err) in stencil_errors(4).0 {
        assert!(err < 1e-6, "{what}: {err:.2e}");
    }
    for (what, err) in stencil_errors(1).0 {
        assert!(err < 1e-6, "{what}: {err:.2e}");
    }
}

/// A power-law contact (`a`, `m` = 1.5, a 5 µm preload) has exact
/// sensitivities to every key at 1, 4 and 32 steps per sample on both
/// kernels: against the five-point stencil to 1e-6 of each column's RMS.
///
/// Its spring grows as s^1.5 from a closing, not twice differentiable
/// there, so the jump condition at a located switch, exact for the flow,
/// was off for the computed pieces by O(h^1.5): 0.16 to 0.44 of a column
/// at 1 step, 2.2e-2 to 5.2e-2 at 4, 7.7e-4 to 1.9e-3 at 32. The split
/// column (`split_shifts`) now carries the pieces' own derivative in the
/// located instant. Measured: 1.0e-7 to 2.4e-7 at 1 step, 2.1e-8 to
/// 6.9e-8 at 4, 8.3e-9 to 2.9e-8 at 32.
///
/// Its stencil steps: 1e-6 of a and m (at 1e-5 the stencil's own error
/// reaches 2.5e-6 for a at 4 steps and 3.7e-6 for m at 32), 1e-5 of c (at
/// 1e-6 its rounding reaches 1.5e-6 at 1 step).
///
/// Without a damper the force is continuous where the contact closes, so
/// the jump condition added nothing there: 3.99e-3 at 32 steps before, 6.0e-9
/// to 3.0e-7 now at 1 to 32.
///
/// Also finite: a located zero of the force often shares its step with the
/// opening, so the law is evaluated held acting at an open end (s ≤ 0),
/// where its spring is zero with all its derivatives: the exponent's term
/// once took the logarithm of s ≤ 0 there, and its column was NaN in 3 946
/// of 4 000 rows.
#[test]
fn a_power_law_contacts_sensitivities_are_exact_at_every_step_count() {
    for damper in [true, false] {
        let model = power_law_contact(damper);
        let wrt: Vec<usize> = (0..model.parameters.len())
            .filter(|&p| model.parameters[p].name.ends_with("_contact"))
            .collect();
        assert_eq!(wrt.len(), 2 + usize::from(damper), "a, m (and c)");
        let stencil = |name: &str, value: f64| match name {
            "c_contact" => 1e-5 * value,
            _ => 1e-6 * value,
        };
        for steps in [1, 4, 32] {
            let mut columns = Vec::new();
            for (what, err, col) in kernel_errors(&model, &wrt, steps, stencil) {
                let what = format!("damper {damper}, {steps} steps, {what}");
                let bad = col.iter().filter(|v| !v.is_finite()).count();
                assert_eq!(bad, 0, "{what}");
                eprintln!("{what}: {err:.2e} of the column's RMS");
                assert!(err < 1e-6, "{what}: {err:.2e}");
                columns.push(col);
            }
            assert_kernels_agree(&format!("{steps} steps"), &columns);
        }
    }
}

/// The example with its contact a power law (`a` = 200 N at 10 µm, `m` =
/// 1.5, a 5 µm preload), with its damper `c` or none (then its force is
/// continuous where it closes), and displacement sensors: an acceleration
/// jumps where the contact closes at a speed, so a sample at that instant
/// is not differentiable.
fn power_law_contact(damper: bool) -> Model {
    let (text, law) = example();
    let c = if damper { r#"c = "c_contact", "# } else { "" };
    let power = format!(
        r#"uz = {{ law = "contact", a = "a_contact", m = "m_contact", reference = "10 um", {c}gap = "-5 um" }}"#
    );
    let k = "name = \"k_contact\"\nvalue = \"2e7 N/m\"\nmin = \"5e6 N/m\"\nmax = \"1e8 N/m\"";
    assert!(text.contains(k), "the example's k");
    let a = "name = \"a_contact\"\nvalue = \"200 N\"\nmin = \"50 N\"\nmax = \"1000 N\"";
    let c_parameter = "[[parameter]]\nname = \"c_contact\"\nvalue = \"400 N*s/m\"\nmin = \"50 N*s/m\"\nmax = \"3000 N*s/m\"\n";
    assert!(text.contains(c_parameter), "the example's c");
    let text = text
        .replace(law, &power)
        .replace(k, a)
        .replace(c_parameter, if damper { c_parameter } else { "" })
        .replace("quantity = \"acceleration\"", "quantity = \"displacement\"")
        + "\n[[parameter]]\nname = \"m_contact\"\nvalue = 1.5\n";
    model(&text)
}

/// Two contacts side by side, each half of the example's (k and c halved,
/// their own parameters), switch at one instant at the nominal values: the
/// step's split column moves both with the first one's dt*/dx, and the
/// second's jump condition adds the rest of its own. Against the
/// five-point stencil at 1, 4 and 32 steps per sample, both kernels, to
/// 1e-6 of each column's RMS (a perturbed k or c separates the two
/// instants, so the stencil sees each move with its own).
///
/// Measured: at most 3.9e-7 (1 step), 8.6e-8 (4), 2.0e-8 (32). With the
/// second contact left to the split column alone, 5.3e-6 at 1 step.
#[test]
fn two_contacts_switching_at_one_instant_have_exact_sensitivities() {
    let (text, law) = example();
    let half = |k: &str, c: &str| {
        format!(r#"uz = {{ law = "contact", k = "{k}", c = "{c}", gap = 0.0 }}"#)
    };
    let second = format!(
        "\n[[element]]\nname = \"slideway_2\"\nbody = \"base\"\nto = \"slide\"\nat = [0.0, 0.0, 0.1]\n{}\n",
        half("k_2", "c_2")
    );
    let text = text
        .replace(law, &half("k_contact", "c_contact"))
        .replace("value = \"2e7 N/m\"", "value = \"1e7 N/m\"")
        .replace("value = \"400 N*s/m\"", "value = \"200 N*s/m\"")
        .replace("quantity = \"acceleration\"", "quantity = \"displacement\"")
        + &second
        + "\n[[parameter]]\nname = \"k_2\"\nvalue = \"1e7 N/m\"\n"
        + "\n[[parameter]]\nname = \"c_2\"\nvalue = \"200 N*s/m\"\n";
    let model = model(&text);
    let wrt: Vec<usize> = (0..model.parameters.len()).collect();
    assert_eq!(wrt.len(), 4, "two k, two c");
    let stencil = |name: &str, value: f64| match name.starts_with('k') {
        true => 1e-6 * value,
        false => 1e-5 * value,
    };
    for steps in [1, 4, 32] {
        let mut columns = Vec::new();
        for (what, err, col) in kernel_errors(&model, &wrt, steps, stencil) {
            let what = format!("{steps} steps, {what}");
            eprintln!("{what}: {err:.2e} of the column's RMS");
            assert!(err < 1e-6, "{what}: {err:.2e}");
            columns.push(col);
        }
        assert_kernels_agree(&format!("{steps} steps"), &columns);
    }
}
