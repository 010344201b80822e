//! The report of hand-made results: failed plan points are marked, warnings
//! and their absence are shown, a result without standard errors still
//! renders, sizes that disagree are refused, user text is escaped, and a
//! large plan keeps the page small.
use crate::report_support;

use report_support::{
    assert_self_contained, check_svg, inline_svgs, knee_column, synthetic_result, synthetic_signals,
};
use rfeid::identification::result::IdentificationResult;
use rfeid::model::Model;
use rfeid::report::{render_html, write_report, ReportError, ReportInput};
use rfeid::simulation::Response;
use std::path::PathBuf;

struct Data {
    time: Vec<f64>,
    measured: Response,
    fitted: Response,
}

fn data(model: &Model, n: usize) -> Data {
    let (time, measured, fitted) = synthetic_signals(model.sensors.len(), n);
    Data {
        time,
        measured,
        fitted,
    }
}

fn input<'a>(
    model: &'a Model,
    result: &'a IdentificationResult,
    d: &'a Data,
    reference: Option<&'a [f64]>,
) -> ReportInput<'a> {
    ReportInput {
        title: "synthetic".into(),
        model,
        result,
        time: &d.time,
        measured: &d.measured,
        fitted: &d.fitted,
        reference,
    }
}

/// A fresh directory for a test's report (kept for inspection).
fn tmp(name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

/// The inline figure whose title starts with `prefix`.
fn figure<'h>(html: &'h str, prefix: &str) -> &'h str {
    inline_svgs(html)
        .into_iter()
        .find(|s| s.contains(&format!("<title>{prefix}")))
        .unwrap_or_else(|| panic!("no figure titled '{prefix}…'"))
}

#[test]
fn failed_plan_points_are_crossed_out_in_the_waterfall() {
    let model = knee_column();
    let result = synthetic_result(&model, 3);
    let d = data(&model, 500);
    let files = write_report(
        &tmp("report_failed_plan"),
        &input(&model, &result, &d, None),
    )
    .expect("writes");
    let html = std::fs::read_to_string(&files.html).expect("written");
    let plan = figure(&html, "LP_τ plan");
    check_svg(plan);
    // A cross is one vermillion path of two strokes; the legend has one more.
    let crosses = plan
        .lines()
        .filter(|l| l.starts_with("<path d=\"M") && l.contains("stroke=\"#D55E00\""))
        .count();
    assert_eq!(crosses, 3 + 1, "three failed points and the legend's cross");
    assert!(plan.contains("3 failed (J = +∞)"));
    assert!(
        plan.contains("start: plan point 4"),
        "the start is ringed and named"
    );
    assert!(
        html.contains("3 of 20 plan points failed to simulate; the first: the response diverged")
    );
}

#[test]
fn a_plan_without_failures_says_so() {
    let model = knee_column();
    let result = synthetic_result(&model, 0);
    let d = data(&model, 500);
    let html = render_html(&input(&model, &result, &d, None)).expect("renders");
    assert!(figure(&html, "LP_τ plan").contains("none failed"));
}

#[test]
fn warnings_are_listed_and_their_absence_is_said() {
    let model = knee_column();
    let mut result = synthetic_result(&model, 0);
    let d = data(&model, 500);
    let html = render_html(&input(&model, &result, &d, None)).expect("renders");
    assert!(html.contains("<div class=\"warn\">"));
    assert!(html.contains("<li>a_n1 and h_n1 are correlated (ρ = 0.97)</li>"));
    result.warnings.clear();
    let html = render_html(&input(&model, &result, &d, None)).expect("renders");
    assert!(html.contains("<div class=\"none\"><b>None.</b>"));
    assert!(!html.contains("<div class=\"warn\">"));
}

#[test]
fn a_result_without_standard_errors_still_renders() {
    let model = knee_column();
    let mut result = synthetic_result(&model, 0);
    for p in &mut result.parameters {
        p.std_error = None;
    }
    result.correlation = None;
    result.condition_number = None;
    result.s2 = None;
    result.uncertainty_error = Some("the Fisher matrix is singular".into());
    result.termination = rfeid::identification::termination::StopReason::MaxIterations;
    result.termination_message = "stopped: the iteration limit was reached".into();
    let d = data(&model, 500);
    let files = write_report(
        &tmp("report_no_uncertainty"),
        &input(&model, &result, &d, None),
    )
    .expect("writes");
    let html = std::fs::read_to_string(&files.html).expect("written");
    assert!(html.contains("Not converged: the iteration limit was reached"));
    assert!(html.contains("Standard errors could not be computed: the Fisher matrix is singular"));
    assert!(html.contains("<p>Not available: the Fisher matrix is singular.</p>"));
    assert!(!files.figures.iter().any(|f| f.ends_with("correlation.svg")));
    for f in &files.figures {
        check_svg(&std::fs::read_to_string(f).expect("figure"));
    }
    assert_self_contained(&html);
}

#[test]
fn the_unfitted_lead_in_and_the_reference_are_shown() {
    let model = knee_column();
    let mut result = synthetic_result(&model, 0);
    result.from = 0.01;
    let truth: Vec<f64> = result.parameters.iter().map(|p| p.nominal).collect();
    let d = data(&model, 500);
    let html = render_html(&input(&model, &result, &d, Some(&truth))).expect("renders");
    assert!(html.contains("not fitted (before `from`)"));
    assert!(html.contains("Worst |estimate − reference|:</b> 1.00 % of the reference"));
    let intervals = figure(&html, "Estimates within their boxes");
    assert!(intervals.contains(">reference</text>"));
}

#[test]
fn sizes_that_disagree_are_refused() {
    let model = knee_column();
    let result = synthetic_result(&model, 0);
    let mut d = data(&model, 500);
    d.time.pop();
    match render_html(&input(&model, &result, &d, None)) {
        Err(ReportError::Mismatch {
            expected: 499,
            found: 500,
            ..
        }) => {}
        other => panic!("expected a mismatch, got {:?}", other.map(|s| s.len())),
    }
    let d = data(&model, 500);
    let short = [1.0, 2.0];
    assert!(matches!(
        render_html(&input(&model, &result, &d, Some(&short))),
        Err(ReportError::Mismatch { .. })
    ));
}

#[test]
fn user_text_is_escaped() {
    let model = knee_column();
    let mut result = synthetic_result(&model, 0);
    result.warnings = vec![rfeid::identification::warning::Warning::recorded(
        "<script>alert(1)</script> & more",
    )];
    let d = data(&model, 500);
    let mut inp = input(&model, &result, &d, None);
    inp.title = "a <b>bold</b> & \"quoted\" title".into();
    let html = render_html(&inp).expect("renders");
    assert!(html.contains("a &lt;b&gt;bold&lt;/b&gt; &amp; &quot;quoted&quot; title"));
    assert!(html.contains("&lt;script&gt;alert(1)&lt;/script&gt; &amp; more"));
    assert_self_contained(&html);
}

#[test]
fn a_large_plan_and_long_record_keep_the_page_small() {
    let model = knee_column();
    let mut result = synthetic_result(&model, 0);
    let points = 5000;
    result.plan.points = points;
    result.plan.costs = (0..points)
        .map(|k| (k % 17 != 3).then(|| 1e-3 * (1.0 + (k * 7919 % points) as f64)))
        .collect();
    result.plan.failed = result.plan.costs.iter().filter(|c| c.is_none()).count();
    result.plan.starts = vec![0, 1, 2];
    result.history = (0..300)
        .map(|it| {
            let mut h = result.history[5].clone();
            h.iteration = it;
            h.cost = 1.0 / (1.0 + it as f64);
            h
        })
        .collect();
    let d = data(&model, 20_000);
    let files =
        write_report(&tmp("report_large_plan"), &input(&model, &result, &d, None)).expect("writes");
    let html = std::fs::read_to_string(&files.html).expect("written");
    eprintln!("large case: {} KB", html.len() / 1024);
    // 300 KB before the frequency-response section's three figures
    // (about 25 KB each, their curves thinned to the pixel columns).
    assert!(html.len() < 380 * 1024, "{} bytes", html.len());
    for s in inline_svgs(&html) {
        check_svg(s);
    }
    let plan = figure(&html, "LP_τ plan");
    assert!(plan.contains(&format!("{} failed (J = +∞)", result.plan.failed)));
}

/// The heat map outlines exactly the pairs the verdict names (in both
/// triangles), whatever other correlations are large: the text and the map
/// agree.
#[test]
fn the_heat_map_outlines_exactly_the_verdicts_pairs() {
    use rfeid::identification::verdict::{Reason, Verdict, VerdictSettings};
    let model = knee_column();
    let mut result = synthetic_result(&model, 0);
    let name = |i: usize| result.parameters[i].name.clone();
    let reasons = vec![Reason::StrongCorrelation {
        first: 0,
        second: 2,
        first_name: name(0),
        second_name: name(2),
        correlation: 0.95,
        slope: None,
        combination_std_error: None,
    }];
    result.verdict = Some(Verdict {
        trustworthy: false,
        decided_by: vec!["identifiability".into()],
        reasons,
        minima: Vec::new(),
        minima_threshold: 0.0,
        sensors: Vec::new(),
        correlation_threshold: 0.9,
        settings: VerdictSettings::default(),
    });
    let d = data(&model, 500);
    let html = render_html(&input(&model, &result, &d, None)).expect("renders");
    let map = figure(&html, "Correlation");
    let outlines = map
        .lines()
        .filter(|l| {
            l.starts_with("<rect")
                && l.contains("fill=\"none\" stroke=\"#000000\" stroke-width=\"2\"")
        })
        .count();
    assert_eq!(outlines, 2, "the pair (0, 2) in both triangles");
    assert!(map.contains("|correlation| &gt; 0.9: warned about"));
    assert!(html.contains("Suspect: do not use these estimates before resolving 1 reason:"));
    assert!(html.contains("are correlated (+0.9500)"));
}

/// A profiled parameter gets its figure: the profile (a failed refit
/// marked), the χ² threshold, the Wald parabola, the intervals in words.
#[test]
fn a_profile_is_drawn_with_its_threshold_and_wald_parabola() {
    use rfeid::identification::profile::{IntervalEnd, ParameterProfile, ProfilePoint};
    let model = knee_column();
    let mut result = synthetic_result(&model, 0);
    let d = data(&model, 500);
    let p = &result.parameters[0];
    let (x_hat, se) = (p.estimate, p.std_error.unwrap_or(p.estimate * 0.01));
    let point = |k: i32| {
        let value = x_hat + 0.6 * se * k as f64;
        ProfilePoint {
            value,
            criterion: (k != 2).then(|| 1.0 + 1e-3 * (k as f64 * 0.6).powi(2)),
            parameters: Vec::new(),
            termination: None,
            iterations: 1,
            failure: (k == 2).then(|| "diverged".to_string()),
        }
    };
    result.profiles = vec![ParameterProfile {
        name: p.name.clone(),
        estimate: x_hat,
        std_error: Some(se),
        criterion: 1.0,
        s2: 1e-3,
        variance_ratio: 1.0,
        threshold: 3.841458820694124,
        wald: Some([x_hat - 1.96 * se, x_hat + 1.96 * se]),
        lower: IntervalEnd::Crossed {
            value: x_hat - 1.96 * se,
        },
        upper: IntervalEnd::Open { bound: p.max },
        points: (-5..=5).map(point).collect(),
        warnings: Vec::new(),
    }];
    let html = render_html(&input(&model, &result, &d, None)).expect("renders");
    let svg = figure(&html, &format!("Profile likelihood of {}", p.name));
    check_svg(svg);
    for text in [
        "χ²₁(0.95) threshold",
        "Wald: ((x − x̂)/σ)²",
        "failed refit",
        "open at max",
    ] {
        assert!(svg.contains(text), "{text}");
    }
}
