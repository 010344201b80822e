//! Shared fixtures and checks of the report tests: the knee–column model, a
//! hand-made identification result, synthetic signals, and checks that a
//! page is self-contained and its figures well-formed.
#![allow(dead_code)]

use rfeid::identification::result::{
    IdentificationResult, Iterate, ParameterEstimate, PlanSummary, Timings,
};
use rfeid::identification::search::Method;
use rfeid::identification::termination::StopReason;
use rfeid::identification::warning::Warning;
use rfeid::io::model_file::load_model;
use rfeid::model::Model;
use rfeid::simulation::Response;
use std::path::Path;

/// The knee–column example model.
pub fn knee_column() -> Model {
    load_model(&Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/knee-column/model.toml"))
        .expect("example loads")
}

/// A plausible result for `model`'s identified parameters, made by hand:
/// estimates 1 % off nominal, 20 plan points of which `failed` fail,
/// a 6-iterate history, a full correlation matrix and one warning.
pub fn synthetic_result(model: &Model, failed: usize) -> IdentificationResult {
    let ids = model.identified();
    let r = ids.len();
    let parameters: Vec<ParameterEstimate> = ids
        .iter()
        .enumerate()
        .map(|(j, &i)| {
            let p = &model.parameters[i];
            let (min, max) = p.bounds.expect("identified");
            ParameterEstimate {
                name: p.name.clone(),
                unit: p.unit.symbol.clone(),
                unit_scale: p.unit.scale,
                estimate: p.value * (1.0 + 0.01 * if j % 2 == 0 { 1.0 } else { -1.0 }),
                std_error: Some(p.value * 0.004 * (1.0 + j as f64)),
                min,
                max,
                scale: p.scale,
                nominal: p.value,
            }
        })
        .collect();
    let points = 20;
    let costs: Vec<Option<f64>> = (0..points)
        .map(|k| (k >= failed).then(|| 1e-2 * (1.0 + ((k * 7) % points) as f64)))
        .collect();
    let history = (0..6)
        .map(|it| Iterate {
            iteration: it,
            cost: 0.3 * 10f64.powi(-(it as i32)),
            parameters: parameters
                .iter()
                .map(|p| p.min + (p.estimate - p.min) * (it as f64 / 5.0).sqrt())
                .collect(),
        })
        .collect();
    let correlation = (0..r)
        .map(|a| {
            (0..r)
                .map(|b| {
                    if a == b {
                        1.0
                    } else {
                        0.95 * ((a + 2 * b) as f64).cos()
                    }
                })
                .collect()
        })
        .collect();
    IdentificationResult {
        parameters,
        criterion: 3e-6,
        ssr: 6e-6,
        s2: Some(7e-10),
        observations: 9000,
        correlation: Some(correlation),
        condition_number: Some(4.2e5),
        warnings: vec![Warning::recorded("a_n1 and h_n1 are correlated (ρ = 0.97)")],
        uncertainty_error: None,
        method: Method::Lm,
        termination: StopReason::ConvergedCost,
        termination_message: "converged: the criterion stopped decreasing".into(),
        iterations: 5,
        simulations: 40,
        simulations_with_sensitivities: 6,
        failed_simulations: failed,
        weights: vec![1.0; model.sensors.len()],
        sensors: model.sensors.iter().map(|s| s.name.clone()).collect(),
        from: 0.0,
        plan: PlanSummary {
            points,
            failed,
            costs,
            starts: vec![failed],
            first_failure: (failed > 0).then(|| {
                "the response diverged at t = 0.1 s (state not finite or beyond 1e6)".into()
            }),
            abandoned: Vec::new(),
        },
        failed_starts: Vec::new(),
        history,
        timings: Timings {
            plan: 1.5,
            local_search: 2.5,
            uncertainty: 0.2,
            profiles: 0.0,
            total: 4.3,
            ..Timings::default()
        },
        threads: 2,
        source: Default::default(),
        verdict: None,
        simulation: None,
        experiments: Vec::new(),
        profiles: Vec::new(),
        noise: Vec::new(),
        std_errors_cover: Default::default(),
    }
}

/// Sample instants and measured/fitted signals of `n_sensors` sensors:
/// decaying sines, the measured ones with a deterministic wiggle.
pub fn synthetic_signals(n_sensors: usize, n: usize) -> (Vec<f64>, Response, Response) {
    let time: Vec<f64> = (0..n).map(|k| k as f64 * 1e-4).collect();
    let mut fitted = Response::zeros(n_sensors, n);
    let mut measured = Response::zeros(n_sensors, n);
    for c in 0..n_sensors {
        for (k, t) in time.iter().enumerate() {
            let y = (1.0 + c as f64) * (2.0 * std::f64::consts::PI * 80.0 * t).sin();
            fitted.values[c * n + k] = y;
            measured.values[c * n + k] = y + 0.02 * ((k * 7919 + c * 104729) % 97) as f64 / 97.0;
        }
    }
    (time, measured, fitted)
}

/// Parses `text` as XML and checks that the root is an `<svg>` in the SVG
/// namespace with a size; returns the number of elements.
pub fn check_svg(text: &str) -> usize {
    let doc = roxmltree::Document::parse(text).unwrap_or_else(|e| panic!("not well-formed: {e}"));
    let root = doc.root_element();
    assert_eq!(root.tag_name().name(), "svg");
    assert_eq!(
        root.tag_name().namespace(),
        Some("http://www.w3.org/2000/svg")
    );
    assert!(root.attribute("viewBox").is_some(), "viewBox");
    assert!(root.attribute("width").is_some(), "width");
    doc.descendants().filter(|n| n.is_element()).count()
}

/// The `<svg …>…</svg>` fragments inlined in a page.
pub fn inline_svgs(html: &str) -> Vec<&str> {
    let mut out = Vec::new();
    let mut rest = html;
    while let Some(a) = rest.find("<svg") {
        let b = rest[a..].find("</svg>").expect("closed svg") + a + "</svg>".len();
        out.push(&rest[a..b]);
        rest = &rest[b..];
    }
    out
}

/// Every `http://` or `https://` reference other than the SVG namespace.
pub fn external_references(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    for scheme in ["http://", "https://"] {
        for (i, _) in text.match_indices(scheme) {
            let tail: String = text[i..].chars().take(40).collect();
            if !tail.starts_with("http://www.w3.org/2000/svg\"") {
                out.push(tail);
            }
        }
    }
    out
}

/// Checks that `html` is self-contained: no script, no external reference,
/// no `src=`/`href=` outside the page.
pub fn assert_self_contained(html: &str) {
    let lower = html.to_lowercase();
    assert!(!lower.contains("<script"), "a script element");
    assert!(!lower.contains("javascript:"), "a javascript: URL");
    assert!(!lower.contains(" src="), "an external source");
    assert!(!lower.contains("<link"), "a link element");
    assert!(!lower.contains("@import"), "a CSS import");
    assert!(!lower.contains("url("), "a CSS url()");
    for (i, _) in html.match_indices("href=\"") {
        let target = &html[i + 6..];
        assert!(
            target.starts_with('#'),
            "non-local link: {}",
            &target[..40.min(target.len())]
        );
    }
    let ext = external_references(html);
    assert!(ext.is_empty(), "external references: {ext:?}");
}
