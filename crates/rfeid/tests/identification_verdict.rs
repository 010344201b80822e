//! The verdict: each reason a result can be suspect, triggered on purpose,
//! and a correct model at its best fit to white noise found trustworthy.
//!
//! The model is a two-body chain along x (a 10 kg base on a spring–damper to
//! the ground, a 5 kg slide on a second one), driven on the slide by a chirp
//! and observed by two accelerometers: fast to simulate (500 samples), with
//! known true values, and wrong in controlled ways.
use crate::common;

use common::model;
use rfeid::identification::lm::LmSettings;
use rfeid::identification::output_error::OutputError;
use rfeid::identification::pipeline::{identify, NoiseModel, Settings, Silent};
use rfeid::identification::result::IdentificationResult;
use rfeid::identification::termination::StopReason;
use rfeid::identification::uncertainty::UncertaintySettings;
use rfeid::identification::verdict::{
    cluster_minima, ljung_box, noise_ratio, Reason, Side, StartEnd, Verdict,
};
use rfeid::measurement::add_noise;
use rfeid::model::Model;
use rfeid::simulation::{Response, Simulator, Workspace};

const K1: f64 = 4.0e5;
const C1: f64 = 120.0;
const K2: f64 = 2.5e5;
const C2: f64 = 60.0;

/// The chain with `k1` in `k1_box`, `c1` and `c2` identified, and the fixed
/// slide stiffness `k2`; the signal is `signal` (TOML inline table).
fn chain(k1_box: (f64, f64), k1: f64, k2: f64, signal: &str) -> String {
    format!(
        r#"
[simulation]
duration = 0.5
sample_rate = 1000.0

[[body]]
name = "base"
mass = 10.0
inertia = [0.1, 0.1, 0.1]
com = [0.0, 0.0, 0.0]

[[body]]
name = "slide"
mass = 5.0
inertia = [0.05, 0.05, 0.05]
com = [0.0, 0.0, 0.0]

[[element]]
name = "foot"
body = "base"
to = "ground"
at = [0.0, 0.0, 0.0]
ux = {{ k = "k1", c = "c1" }}

[[element]]
name = "guide"
body = "slide"
to = "base"
at = [0.0, 0.0, 0.0]
ux = {{ k = {k2:e}, c = "c2" }}

[[excitation]]
body = "slide"
reaction = "base"
at = [0.0, 0.0, 0.0]
direction = [1, 0, 0]
signal = {signal}

[[sensor]]
name = "base_a"
body = "base"
at = [0.0, 0.0, 0.0]
direction = [1, 0, 0]
quantity = "acceleration"

[[sensor]]
name = "slide_a"
body = "slide"
at = [0.0, 0.0, 0.0]
direction = [1, 0, 0]
quantity = "acceleration"

[[parameter]]
name = "k1"
value = {k1:e}
min = {:e}
max = {:e}

[[parameter]]
name = "c1"
value = {C1:e}
min = 40.0
max = 400.0

[[parameter]]
name = "c2"
value = {C2:e}
min = 20.0
max = 200.0
"#,
        k1_box.0, k1_box.1
    )
}

const CHIRP: &str = r#"{ type = "chirp", amplitude = 50.0, f0 = 5.0, f1 = 150.0 }"#;

/// The truth's model: k1 in a box around K1.
fn truth() -> Model {
    model(&chain((1.0e5, 1.0e6), K1, K2, CHIRP))
}

/// The truth's response with `noise` × RMS white noise (seeded).
fn data(noise: f64, seed: u64) -> Response {
    let m = truth();
    let sim = Simulator::new(&m);
    let mut out = sim.response_buffer();
    sim.run(&m.nominal(), &mut Workspace::default(), &mut out)
        .expect("the truth simulates");
    add_noise(&mut out, noise, seed);
    out
}

fn settings(plan: usize, starts: usize) -> Settings {
    Settings {
        plan_points: plan,
        starts,
        ..Settings::default()
    }
}

fn run(m: &Model, measured: Response, s: &Settings) -> IdentificationResult {
    identify(OutputError::new(Simulator::new(m), measured, 0), s, &Silent).expect("identifies")
}

fn verdict(r: &IdentificationResult) -> &Verdict {
    let v = r
        .verdict
        .as_ref()
        .expect("every identification has a verdict");
    for reason in &v.reasons {
        eprintln!("  reason: {reason}");
    }
    v
}

/// The reasons of `v` of the kind `pred` picks.
fn count(v: &Verdict, pred: impl Fn(&Reason) -> bool) -> usize {
    v.reasons.iter().filter(|r| pred(r)).count()
}

#[test]
fn a_correct_model_with_white_noise_is_trustworthy() {
    for seed in 1..=5 {
        let r = run(&truth(), data(0.02, seed), &settings(32, 2));
        let v = verdict(&r);
        assert!(v.trustworthy, "seed {seed}: {:?}", v.reasons);
        assert_eq!(v.sensors.len(), 2);
        for s in &v.sensors {
            // 2 % noise of the RMS leaves a fit of about 98 %.
            let fit = s.fit_percent.expect("a varying signal");
            assert!(
                (fit - 98.0).abs() < 1.0,
                "seed {seed}: {} fit {fit}",
                s.sensor
            );
            assert!(s.p_value.expect("tested") > 1e-6);
        }
        // Both starts reach the one minimum.
        assert_eq!(v.minima.len(), 1, "seed {seed}");
        assert_eq!(v.minima[0].starts, 2);
    }
}

#[test]
fn noise_free_data_are_trustworthy_and_skip_the_noise_tests() {
    let r = run(&truth(), data(0.0, 1), &settings(32, 1));
    let v = verdict(&r);
    assert!(v.trustworthy, "{:?}", v.reasons);
    for s in &v.sensors {
        assert!(s.fit_percent.expect("varying") > 99.9999);
        assert_eq!(s.ljung_box, None, "no noise to test");
        assert_eq!(s.noise_ratio, None);
    }
}

#[test]
fn a_box_that_excludes_the_truth_puts_the_estimate_on_its_bound() {
    // k1's box lies entirely above the true 4e5 N/m.
    let m = model(&chain((6.0e5, 2.0e6), 1.0e6, K2, CHIRP));
    let r = run(&m, data(0.01, 1), &settings(32, 1));
    let v = verdict(&r);
    assert!(!v.trustworthy);
    let at_lower = count(v, |r| {
        matches!(r, Reason::AtBound { parameter, side: Side::Lower, distance, .. }
            if parameter == "k1" && *distance <= 1e-3)
    });
    assert_eq!(at_lower, 1, "k1 is on its lower bound");
    // The misfit shows in the residuals too: what the noise model fitted
    // to them leaves still follows the input.
    assert!(count(v, |r| matches!(r, Reason::InputCorrelated { .. })) >= 1);
}

#[test]
fn a_wrong_fixed_parameter_leaves_residuals_that_are_not_white() {
    // The fixed guide stiffness is 30 % too high; k1, c1 and c2 cannot
    // make up for it.
    let m = model(&chain((1.0e5, 1.0e6), K1, 1.3 * K2, CHIRP));
    // With the default noise model, what it leaves follows the input.
    let r = run(&m, data(0.01, 2), &settings(32, 1));
    let v = verdict(&r);
    assert!(!v.trustworthy);
    assert!(count(v, |r| matches!(r, Reason::InputCorrelated { .. })) >= 1);
    // With white noise models the residuals are judged as they are.
    let white = Settings {
        noise_model: NoiseModel::White,
        ..settings(32, 1)
    };
    let r = run(&m, data(0.01, 2), &white);
    let v = verdict(&r);
    assert!(!v.trustworthy);
    assert!(
        count(v, |r| matches!(r, Reason::NotWhite { .. })) >= 1,
        "Ljung–Box sees the misfit"
    );
    assert!(
        count(v, |r| matches!(r, Reason::NoiseMismatch { .. })) >= 1,
        "s² is far above the noise the first differences show"
    );
}

#[test]
fn the_iteration_limit_is_a_reason() {
    let s = Settings {
        lm: LmSettings::default().with_max_iterations(1).expect("valid"),
        ..settings(8, 1)
    };
    let r = run(&truth(), data(0.01, 3), &s);
    assert_eq!(r.termination, StopReason::MaxIterations);
    let v = verdict(&r);
    assert_eq!(
        count(v, |r| matches!(r, Reason::IterationLimit { iterations: 1 })),
        1
    );
    assert!(!v.trustworthy);
}

#[test]
fn heavy_noise_is_a_poor_fit() {
    // Noise of 30 % of the RMS caps the fit near 70 %.
    let r = run(&truth(), data(0.3, 4), &settings(32, 1));
    let v = verdict(&r);
    assert_eq!(count(v, |r| matches!(r, Reason::PoorFit { .. })), 2);
    for s in &v.sensors {
        let fit = s.fit_percent.expect("varying");
        assert!(fit < 90.0 && fit > 60.0, "{}: {fit}", s.sensor);
    }
}

#[test]
fn correlations_at_the_threshold_are_reasons() {
    let s = Settings {
        uncertainty: UncertaintySettings::default()
            .with_correlation_threshold(0.05)
            .expect("valid"),
        ..settings(32, 1)
    };
    let r = run(&truth(), data(0.02, 5), &s);
    let v = verdict(&r);
    let corr = r.correlation.as_ref().expect("standard errors");
    // Exactly the pairs beyond the threshold, each once.
    let mut expected = Vec::new();
    for (i, row) in corr.iter().enumerate() {
        for (j, c) in row.iter().enumerate().skip(i + 1) {
            if c.abs() > 0.05 {
                expected.push((i, j));
            }
        }
    }
    assert!(!expected.is_empty());
    assert_eq!(v.correlated_pairs(), expected);
    assert_eq!(v.correlation_threshold, 0.05);
}

/// A lightly damped oscillator (ζ = 5e-4) rung by a short impulse and
/// recorded for 32 periods, its stiffness in a box two decades wide: the
/// criterion in k has a narrow valley at the truth and many side minima
/// (the record's window makes J(k) ripple like a sinc).
fn ringing(k: f64) -> String {
    format!(
        r#"
[simulation]
duration = 1.0
sample_rate = 1000.0

[[body]]
name = "mass"
mass = 10.0
inertia = [0.1, 0.1, 0.1]
com = [0.0, 0.0, 0.0]

[[element]]
name = "spring"
body = "mass"
to = "ground"
at = [0.0, 0.0, 0.0]
ux = {{ k = "k", c = 2.0 }}

[[excitation]]
body = "mass"
at = [0.0, 0.0, 0.0]
direction = [1, 0, 0]
signal = {{ type = "impulse", amplitude = 100.0, t0 = 0.01, width = 0.002 }}

[[sensor]]
name = "v"
body = "mass"
at = [0.0, 0.0, 0.0]
direction = [1, 0, 0]
quantity = "velocity"

[[parameter]]
name = "k"
value = {k:e}
min = 1.0e4
max = 1.0e6
"#
    )
}

#[test]
fn starts_in_different_basins_are_listed_as_distinct_minima() {
    let m = model(&ringing(K1));
    let sim = Simulator::new(&m);
    let mut measured = sim.response_buffer();
    sim.run(&m.nominal(), &mut Workspace::default(), &mut measured)
        .expect("simulates");
    add_noise(&mut measured, 0.01, 6);
    let r = run(&m, measured, &settings(16, 4));
    let v = verdict(&r);
    let reasons = count(v, |r| matches!(r, Reason::DistinctMinima { .. }));
    assert_eq!(reasons, 1);
    assert!(v.minima.len() >= 2);
    assert_eq!(v.minima.iter().map(|m| m.starts).sum::<usize>(), 4);
    // Lowest J first, and each further minimum beyond the noise threshold.
    for w in v.minima.windows(2) {
        assert!(w[1].cost - w[0].cost > v.minima_threshold);
    }
    // The estimate is the lowest minimum.
    assert_eq!(v.minima[0].cost, r.criterion);
    assert_eq!(v.minima[0].parameters[0], r.parameters[0].estimate);
}

#[test]
fn minima_are_clustered_by_the_noise_threshold() {
    let end = |cost: f64| StartEnd {
        cost,
        parameters: vec![cost],
    };
    // r = 2, N − r − 1 = 997: s² = 997 / 997 = 1 and χ²_2(0.999) = 13.8155.
    let ends = [end(1010.0), end(997.0), end(1030.0), end(997.5)];
    let (minima, threshold) = cluster_minima(&ends, 2, 1000, 0.999);
    assert!((threshold - (-2.0 * 1e-3_f64.ln())).abs() < 1e-9);
    let summary: Vec<(f64, usize)> = minima.iter().map(|m| (m.cost, m.starts)).collect();
    assert_eq!(summary, vec![(997.0, 3), (1030.0, 1)]);
    assert_eq!(minima[0].parameters, vec![997.0]);
}

#[test]
fn ljung_box_and_the_noise_ratio_on_known_sequences() {
    // An alternating sequence: ρ_k = (−1)^k (n − k)/n exactly (zero mean),
    // so Q = n (n + 2) Σ (n − k) / n².
    let n = 100;
    let e: Vec<f64> = (0..n)
        .map(|k| if k % 2 == 0 { 1.0 } else { -1.0 })
        .collect();
    let expected: f64 = (1..=5)
        .map(|k| (n - k) as f64 / (n * n) as f64)
        .sum::<f64>()
        * (n * (n + 2)) as f64;
    let q = ljung_box(&e, 5).expect("long enough");
    assert!((q - expected).abs() < 1e-9 * expected);
    // Differences of ±2: variance 1 over 4/2 = 0.5.
    assert!((noise_ratio(&e).expect("varies") - 0.5).abs() < 1e-12);
    // A straight line is all smooth: the ratio is huge.
    let line: Vec<f64> = (0..n).map(|k| k as f64).collect();
    assert!(noise_ratio(&line).expect("varies") > 1000.0);
    assert_eq!(ljung_box(&e[..11], 5), None, "too short");
}
