//! Experiment design (SPEC §6) against exact references: the prediction
//! equals the Cramér–Rao bound of the whole weighted Jacobian, the
//! greedy-plus-exchange choice is within 1 % D-efficiency of a brute-force
//! search over every subset, and the relaxation's bound lies above every
//! subset; with no sensor placed too.
use nalgebra::DMatrix;
use rfeid::design::choose::{choose, criterion, log_det};
use rfeid::design::fisher::fisher_parts;
use rfeid::design::{bound, design, DesignError, DesignSettings};
use rfeid::identification::options::Spelling;
use rfeid::identification::output_error::OutputError;
use rfeid::identification::problem::LeastSquares;
use rfeid::identification::uncertainty::{cramer_rao_mapped, UncertaintySettings};
use rfeid::io::model_file::{load_model, parse_model, parse_model_for, Purpose};
use rfeid::model::Model;
use rfeid::simulation::Simulator;
use std::path::Path;

/// The knee–column with its 3 placed sensors and 21 candidates.
fn knee_column() -> Model {
    load_model(&Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/knee-column/model.toml"))
        .expect("the example loads")
}

/// The Cramér–Rao standard errors of the model's placed sensors from the
/// whole Jacobian, rows weighted by 1/σ_c (the identification's own
/// path: QR of the stacked Jacobian, eq. 26–29 with s² = 1).
fn exact_std_errors(model: &Model) -> Vec<f64> {
    let sim = Simulator::choose(model, &model.nominal()).unwrap();
    let measured = sim.response_buffer();
    bound_of(
        OutputError::new(sim, measured, 0),
        &[model],
        &model.nominal(),
    )
}

/// The Cramér–Rao standard errors of `problem` (zero data, one weight
/// 1/σ² per sensor of `models` in turn) at the parameter values `x`.
fn bound_of(mut problem: OutputError, models: &[&Model], x: &[f64]) -> Vec<f64> {
    let w: Vec<f64> = models
        .iter()
        .flat_map(|m| m.sensors.iter().map(|s| s.noise.unwrap().powi(-2)))
        .collect();
    problem.set_weights(&w);
    let cols: Vec<f64> = problem.columns().iter().map(|c| x[c.parameter]).collect();
    let u = problem.to_normalised(&cols);
    let n = problem.n_residuals();
    let mut jac = DMatrix::zeros(n, cols.len());
    let mut r = vec![0.0; n];
    problem
        .residuals_jacobian(&mut problem.workspace(), &u, &mut r, &mut jac)
        .unwrap();
    let ssr = (n - cols.len() - 1) as f64; // s² = 1: σ is in the weights.
    cramer_rao_mapped(
        &jac,
        ssr,
        &problem.dx_du(&u),
        problem.widths(),
        &UncertaintySettings::default(),
    )
    .unwrap()
    .std_errors
}

#[test]
fn prediction_equals_the_exact_cramer_rao_bound() {
    let model = knee_column();
    let exact = exact_std_errors(&model);
    let d = design(&model, &DesignSettings::default(), &|| {}).unwrap();
    let placed = d.placed.as_ref().unwrap();
    assert_eq!(placed.std_errors.len(), exact.len());
    for (j, (p, e)) in placed.std_errors.iter().zip(&exact).enumerate() {
        let rel = (p / e - 1.0).abs();
        assert!(
            rel < 1e-6,
            "{}: predicted {p:e}, exact {e:e}",
            d.parts.columns[j]
        );
    }
    assert_eq!(placed.observations, 9000);
}

#[test]
fn a_candidate_at_a_placed_sensor_carries_its_information() {
    // The candidates' shares come from the same simulation as the placed
    // sensors': a candidate equal to a placed sensor gives its share.
    let mut model = knee_column();
    let mut twin = model.sensors[1].clone();
    twin.name = "twin".into();
    model.candidates = vec![twin];
    let parts = fisher_parts(&model, &model.nominal()).unwrap();
    let mut alone = model.clone();
    alone.sensors = vec![model.sensors[1].clone()];
    alone.candidates.clear();
    let single = fisher_parts(&alone, &alone.nominal()).unwrap();
    // Each in units of its own σ₀²: the information itself is F·σ₀² / σ₀².
    let twin = parts.candidate(0) / parts.noise_scale.powi(2);
    let own = single.placed() / single.noise_scale.powi(2);
    let diff = (&twin - &own).abs().max();
    assert!(diff <= 1e-9 * own.abs().max(), "{diff:e}");
}

/// Every sensor's noise 10¹⁵⁰ times larger (or smaller) scales every
/// predicted standard error by exactly that and shifts log det F by
/// −2r·ln 10¹⁵⁰, leaving the correlations, the condition number and the
/// choice (only the box warnings follow the standard errors): the
/// shares are held in units of the common noise, so nothing underflows
/// (1/σ² alone would be 10⁻³⁰⁰).
#[test]
fn scaling_every_noise_scales_every_standard_error() {
    let model = knee_column();
    let settings = DesignSettings {
        choose: Some(2),
        ..Default::default()
    };
    let base = design(&model, &settings, &|| {}).unwrap();
    for factor in [1e150, 1e-150] {
        let mut scaled = model.clone();
        for s in scaled.sensors.iter_mut().chain(&mut scaled.candidates) {
            s.noise = s.noise.map(|n| n * factor);
        }
        let d = design(&scaled, &settings, &|| {}).unwrap();
        let (c0, c) = (base.chosen.as_ref().unwrap(), d.chosen.as_ref().unwrap());
        assert_eq!(c.chosen, c0.chosen);
        let r = base.parts.columns.len() as f64;
        for (p0, p) in [(base.placed.as_ref().unwrap(), d.placed.as_ref().unwrap())]
            .into_iter()
            .chain([(&c0.prediction, &c.prediction)])
        {
            assert_eq!(p.std_errors.len(), r as usize);
            for (se0, se) in p0.std_errors.iter().zip(&p.std_errors) {
                assert!(
                    (se / (se0 * factor) - 1.0).abs() < 1e-9,
                    "{se:e} vs {se0:e}"
                );
            }
            let shift = -2.0 * r * factor.ln();
            assert!((p.log_det - p0.log_det - shift).abs() < 1e-9 * shift.abs());
            let cond = (p.condition_number.unwrap(), p0.condition_number.unwrap());
            assert!((cond.0 / cond.1 - 1.0).abs() < 1e-9);
            for (row0, row) in p0.correlation.iter().zip(&p.correlation) {
                for (r0, r) in row0.iter().zip(row) {
                    assert!((r - r0).abs() < 1e-9, "{r} vs {r0}");
                }
            }
        }
        // The relaxation's bound stops within 1e-9·|bound| of its optimum
        // (`bound.rs`), so the certificate agrees to that over r.
        let eff = (c.efficiency_at_least, c0.efficiency_at_least);
        assert!((eff.0 / eff.1 - 1.0).abs() < 1e-7, "{eff:?}");
    }
}

#[test]
fn greedy_exchange_is_within_one_percent_of_brute_force() {
    let model = knee_column();
    let parts = fisher_parts(&model, &model.nominal()).unwrap();
    let base = [parts.placed()];
    let cand = [parts.candidates()];
    let r = parts.columns.len() as f64;
    assert_eq!(cand[0].len(), 21);
    for k in [1, 2, 3, 4] {
        let brute = choose(&base, &cand, k, false);
        let greedy = choose(&base, &cand, k, true);
        let efficiency = ((greedy.log_det - brute.log_det) / r).exp();
        assert!(efficiency >= 0.99, "K = {k}: D-efficiency {efficiency}");
        // The brute force is the maximum over every subset ...
        let mut all = 0;
        let mut best = f64::NEG_INFINITY;
        subsets(21, k, &mut Vec::new(), &mut |s| {
            all += 1;
            best = best.max(criterion(&base, &cand, s));
        });
        assert_eq!(brute.log_det, best, "K = {k}");
        // ... and the relaxation bounds it from above.
        let upper = bound::upper_bound(&base, &cand, k);
        assert!(upper >= best - 1e-9, "K = {k}: bound {upper} below {best}");
        eprintln!(
            "K = {k}: {all} subsets, best log det {best:.4}, greedy+exchange {:.4} (efficiency {efficiency:.5}), bound {upper:.4}",
            greedy.log_det
        );
    }
}

/// Calls `f` with every k-subset of 0..n.
fn subsets(n: usize, k: usize, s: &mut Vec<usize>, f: &mut dyn FnMut(&[usize])) {
    if s.len() == k {
        f(s);
        return;
    }
    let from = s.last().map_or(0, |&i| i + 1);
    for i in from..n {
        s.push(i);
        subsets(n, k, s, f);
        s.pop();
    }
}

#[test]
fn log_det_is_invariant_to_the_order_of_the_sum() {
    let model = knee_column();
    let parts = fisher_parts(&model, &model.nominal()).unwrap();
    let c = parts.candidates();
    let a = log_det(&(parts.placed() + &c[3] + &c[7]));
    let b = log_det(&(&c[7] + &c[3] + parts.placed()));
    assert!((a - b).abs() < 1e-9 * a.abs());
}

/// A campaign's prediction is the Cramér–Rao bound of its stacked
/// Jacobian (every fitted experiment, each sensor weighted by 1/σ²), and
/// each experiment's gain is what dropping it costs.
#[test]
fn a_campaign_prediction_is_the_bound_of_its_stacked_jacobian() {
    use rfeid::identification::output_error::ExperimentData;
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples/knee-column-campaign/model.toml");
    let mut model = load_model(&path).expect("the campaign loads");
    for (c, s) in model.sensors.iter_mut().enumerate() {
        s.noise = Some(1e-3 * (c + 1) as f64);
    }
    let x = model.nominal();
    let models: Vec<Model> = model
        .fitted_experiments()
        .iter()
        .map(|&e| model.for_experiment(e))
        .collect();
    let parts: Vec<ExperimentData> = models
        .iter()
        .zip(model.fitted_experiments())
        .map(|(m, e)| {
            let sim = Simulator::choose(m, &m.nominal()).unwrap();
            ExperimentData {
                name: model.experiments[e].name.clone(),
                measured: sim.response_buffer(),
                sim,
                first: 0,
                weight: 1.0,
            }
        })
        .collect();
    let refs: Vec<&Model> = models.iter().collect();
    let exact = bound_of(OutputError::campaign(parts), &refs, &x);
    let d = design(&model, &DesignSettings::default(), &|| {}).unwrap();
    for (p, e) in d.placed.as_ref().unwrap().std_errors.iter().zip(&exact) {
        assert!((p / e - 1.0).abs() < 1e-6, "predicted {p:e}, exact {e:e}");
    }
    // Dropping an experiment costs exactly its gain.
    assert_eq!(d.experiments.len(), 3);
    let total = log_det(&d.parts.placed());
    for (e, g) in d.parts.experiments.iter().zip(&d.experiments) {
        let without = log_det(&(d.parts.placed() - &e.placed));
        assert!((total - without - g.log_det_gain).abs() < 1e-9 * total.abs());
        assert!(g.log_det_gain > 0.0);
    }
}

/// Candidates read through their body's six-reading basis carry the same
/// information as each one simulated as a sensor of its own: the knee's
/// and column's accelerometers, and eight velocity pick-ups at seeded
/// points and directions on the column.
#[test]
fn candidates_read_through_a_body_basis_equal_their_own_simulation() {
    use rfeid::design::fisher::fisher_parts_with;
    use rfeid::model::SensorKind;
    let mut model = knee_column();
    let mut seed: u64 = 0x5eed_0026;
    let mut next = || {
        seed = seed
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    let template = model.candidates.last().unwrap().clone();
    for k in 0..8 {
        let mut s = template.clone();
        s.name = format!("v{k}");
        s.kind = SensorKind::Velocity;
        s.at = nalgebra::Vector3::new(next(), next(), 0.8 + next());
        s.direction = nalgebra::Vector3::new(next(), next(), next()).normalize();
        s.noise = Some(1e-5);
        model.candidates.push(s);
    }
    let x = model.nominal();
    let via_basis = fisher_parts_with(&model, &x, true).unwrap();
    let direct = fisher_parts_with(&model, &x, false).unwrap();
    for i in 0..model.candidates.len() {
        let (a, b) = (via_basis.candidate(i), direct.candidate(i));
        let err = (&a - &b).abs().max() / b.abs().max();
        assert!(
            err < 1e-9,
            "{}: relative difference {err:e}",
            model.candidates[i].name
        );
    }
    assert_eq!(via_basis.placed(), direct.placed());
}

/// Two parameters the test cannot tell apart (two equal springs at one
/// point) make a singular Fisher matrix: no standard errors, and the
/// reason names both, as `identify` would.
#[test]
fn a_singular_design_names_the_parameters_it_cannot_tell_apart() {
    use rfeid::design::fisher_bound::cramer_rao_fisher;
    use rfeid::identification::uncertainty::UncertaintyError;
    let j = DMatrix::from_row_slice(
        4,
        3,
        &[
            1.0, 2.0, 2.0, //
            0.5, 1.0, 1.0, //
            3.0, 0.1, 0.1, //
            1.0, 4.0, 4.0,
        ],
    );
    let f = j.transpose() * &j;
    let e = cramer_rao_fisher(
        &f,
        4,
        &[1.0; 3],
        &[1.0; 3],
        1.0,
        &UncertaintySettings::default(),
    )
    .unwrap_err();
    match e {
        UncertaintyError::Singular { parameters, .. } => assert_eq!(parameters, vec![1, 2]),
        other => panic!("{other}"),
    }
    // Nearly equal columns stay regular, with their large standard errors.
    let mut k = j.clone();
    k[(0, 2)] += 0.05;
    let ok = cramer_rao_fisher(
        &(k.transpose() * &k),
        4,
        &[1.0; 3],
        &[1.0; 3],
        1.0,
        &UncertaintySettings::default(),
    )
    .unwrap();
    assert!(ok.std_errors[1] > 10.0 && ok.std_errors[1].is_finite());
}

/// The knee–column before its first test: the example's 21 candidates and
/// its 3 measured sensors make 24 places, so its three measured sensors
/// (the knee's centre) become candidates and the k4 point's three are left
/// out: 21 candidates, seven points by three directions (four on the knee,
/// three on the column, as the example's grid), none placed.
fn knee_column_unplaced() -> (Model, String) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/knee-column/model.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    let mut blocks = text.split("[[sensor]]");
    let mut out = blocks.next().unwrap().to_string();
    for block in blocks {
        let name = block
            .lines()
            .find_map(|l| l.strip_prefix("name = \""))
            .unwrap();
        if name.starts_with("k4") {
            // Keep what follows the entry (a section's heading).
            out += &block[block.find("\n# ----").unwrap_or(block.len())..];
            continue;
        }
        out += "[[sensor]]";
        match block.contains("candidate = true") {
            true => out += block,
            false => out += &block.replacen("\nnoise = ", "\ncandidate = true\nnoise = ", 1),
        }
    }
    let model = parse_model_for(&out, &path, Purpose::Design).expect("design reads it");
    (model, out)
}

/// With no sensor placed, `--choose 3` picks all three of the 21 from a
/// base information of 0: its D-efficiency against every one of the
/// C(21, 3) = 1330 subsets (their log det from the same Fisher matrices) is
/// at least 0.99, greedy plus exchange from the empty base is within 1 % of
/// brute force for K = 1 to 4, the certificate holds, and the prediction is
/// the one of the three placed.
#[test]
fn choosing_with_no_placed_sensor_is_checked_against_every_subset() {
    let (model, _) = knee_column_unplaced();
    assert!(model.sensors.is_empty());
    assert_eq!(model.candidates.len(), 21);
    let settings = DesignSettings {
        choose: Some(3),
        ..Default::default()
    };
    let d = design(&model, &settings, &|| {}).unwrap();
    assert!(d.placed.is_none());
    let c = d.chosen.as_ref().unwrap();
    let cand = [d.parts.candidates()];
    let r = d.parts.columns.len();
    let base = [DMatrix::zeros(r, r)];
    let mut all = 0;
    let mut worst = f64::INFINITY;
    let mut best = f64::NEG_INFINITY;
    subsets(21, 3, &mut Vec::new(), &mut |s| {
        all += 1;
        let other = log_det(&s.iter().fold(base[0].clone(), |m, &i| m + &cand[0][i]));
        best = best.max(other);
        worst = worst.min(((c.prediction.log_det - other) / r as f64).exp());
    });
    assert_eq!(all, 1330);
    eprintln!(
        "no placed sensor, K = 3: chosen {:?}, log det {:.4}, best of {all} {best:.4}, D-efficiency against every subset at least {worst:.6}, certified {:.4} (bound {:.4})",
        c.names, c.prediction.log_det, c.efficiency_at_least, c.upper_bound
    );
    assert!(worst >= 0.99, "D-efficiency {worst}");
    assert!(
        c.upper_bound >= best - 1e-9,
        "bound {} below {best}",
        c.upper_bound
    );
    assert!((0.0..=worst.min(1.0) + 1e-12).contains(&c.efficiency_at_least));
    for k in 1..=4 {
        let brute = choose(&base, &cand, k, false);
        let greedy = choose(&base, &cand, k, true);
        let efficiency = ((greedy.log_det - brute.log_det) / r as f64).exp();
        eprintln!(
            "no placed sensor, K = {k}: brute force {:?} {:.4}, greedy+exchange {:?} {:.4} (D-efficiency {efficiency:.5})",
            brute.chosen, brute.log_det, greedy.chosen, greedy.log_det
        );
        assert!(
            efficiency >= 0.99,
            "K = {k}: greedy's D-efficiency {efficiency}"
        );
        assert!(greedy.log_det.is_finite(), "K = {k}");
    }
    // The chosen three placed: the same prediction, from no hidden base.
    let mut placed = model.clone();
    placed.sensors = c
        .chosen
        .iter()
        .map(|&i| model.candidates[i].clone())
        .collect();
    placed.candidates.clear();
    let p = design(&placed, &DesignSettings::default(), &|| {}).unwrap();
    for (a, b) in c
        .prediction
        .std_errors
        .iter()
        .zip(&p.placed.unwrap().std_errors)
    {
        assert!((a / b - 1.0).abs() < 1e-9, "{a:e} vs {b:e}");
    }
}

/// A model whose sensors are all candidates is refused for a test's data
/// (naming the file), and by `design` without `--choose`.
#[test]
fn a_model_with_candidates_alone_needs_design_and_choose() {
    let (model, text) = knee_column_unplaced();
    let e = parse_model(&text, Path::new("unplaced.toml")).unwrap_err();
    let msg = e.to_string();
    assert!(
        msg.contains("unplaced.toml") && msg.contains("every [[sensor]] is a candidate"),
        "{msg}"
    );
    let e = design(&model, &DesignSettings::default(), &|| {}).unwrap_err();
    let DesignError::Option(o) = e else {
        panic!("{e:?}")
    };
    assert!(
        o.option == "choose" && o.detail.starts_with("is needed"),
        "{o}"
    );
    let e = rfeid::design::json::check_request(&model, "unplaced.toml", None, None).unwrap_err();
    let cli = e.option_error().spelt(Spelling::CommandLine);
    assert!(
        e.of_model() && cli.starts_with("--choose is needed"),
        "{cli}"
    );
    assert!(
        cli.contains("(--choose K)") && !e.to_string().contains("--"),
        "{e}"
    );
}

/// A chosen candidate on a body no force reaches (held to the ground on
/// its own) carries no information: the choice says so rather than
/// reporting it as a full gain.
#[test]
fn a_chosen_candidate_that_carries_nothing_is_named() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/knee-column/model.toml");
    let text = std::fs::read_to_string(&path).unwrap()
        + r#"
[[body]]
name = "still"
mass = "10 kg"
inertia = [1.0, 1.0, 1.0]
com = [2.0, 0.0, 0.5]

[[element]]
name = "still_pad"
body = "still"
to = "ground"
at = [2.0, 0.0, 0.5]
ux = { k = "1e7 N/m", c = "1e3 N*s/m" }
uy = { k = "1e7 N/m", c = "1e3 N*s/m" }
uz = { k = "1e7 N/m", c = "1e3 N*s/m" }
rx = { k = "1e6 N*m/rad", c = "10 N*m*s/rad" }
ry = { k = "1e6 N*m/rad", c = "10 N*m*s/rad" }
rz = { k = "1e6 N*m/rad", c = "10 N*m*s/rad" }

[[sensor]]
name = "still"
body = "still"
at = [2.0, 0.0, 0.5]
direction = [1, 0, 0]
quantity = "acceleration"
noise = "1.0e-3 m/s^2"
candidate = true
"#;
    let mut model = parse_model(&text, &path).unwrap();
    let keep = ["k1x", "still"];
    model.candidates.retain(|c| keep.contains(&c.name.as_str()));
    let settings = DesignSettings {
        choose: Some(2),
        ..Default::default()
    };
    let d = design(&model, &settings, &|| {}).unwrap();
    let c = d.chosen.as_ref().unwrap();
    let still = model.candidates.iter().position(|c| c.name == "still");
    assert_eq!(c.uninformative, vec![still.unwrap()]);
    let texts = c.warning_texts(&d.parts.columns);
    assert!(texts
        .iter()
        .any(|t| t.contains("candidate still carries no information")));
    // One informative candidate alone names nothing.
    model.candidates.retain(|c| c.name == "k1x");
    let settings = DesignSettings {
        choose: Some(1),
        ..Default::default()
    };
    let d = design(&model, &settings, &|| {}).unwrap();
    assert!(d.chosen.unwrap().uninformative.is_empty());
}
