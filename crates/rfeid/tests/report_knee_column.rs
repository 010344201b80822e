//! The report of a real identification: the knee–column benchmark with 2 %
//! noise (seed 1), a 10-point plan and one Levenberg–Marquardt search. The
//! page must hold every section, sensor and parameter, be self-contained,
//! inline well-formed SVG figures that are also written as files, and stay
//! under 300 KB.
use crate::report_support;

use report_support::{assert_self_contained, check_svg, inline_svgs, knee_column};
use rfeid::identification::output_error::OutputError;
use rfeid::identification::pipeline::{identify, Settings, Silent};
use rfeid::identification::result::IdentificationResult;
use rfeid::measurement::add_noise;
use rfeid::model::Model;
use rfeid::report::{render_html, write_report, ReportInput, SECTIONS};
use rfeid::simulation::{Response, Simulator, Workspace};
use std::path::PathBuf;
use std::sync::OnceLock;

/// Model, time, measured, fitted, result and truth of one identification.
struct Case {
    model: Model,
    time: Vec<f64>,
    measured: Response,
    fitted: Response,
    result: IdentificationResult,
    truth: Vec<f64>,
}

fn simulate(model: &Model, params: &[f64]) -> Response {
    let sim = Simulator::new(model);
    let mut out = sim.response_buffer();
    sim.run(params, &mut Workspace::default(), &mut out)
        .expect("simulates");
    out
}

fn case() -> &'static Case {
    static CASE: OnceLock<Case> = OnceLock::new();
    CASE.get_or_init(|| {
        let model = knee_column();
        let mut measured = simulate(&model, &model.nominal());
        add_noise(&mut measured, 0.02, 1);
        let settings = Settings {
            plan_points: 10,
            starts: 1,
            ..Settings::default()
        };
        let result = identify(
            OutputError::new(Simulator::new(&model), measured.clone(), 0),
            &settings,
            &Silent,
        )
        .expect("identifies");
        let ids = model.identified();
        let mut params = model.nominal();
        for (j, &i) in ids.iter().enumerate() {
            params[i] = result.parameters[j].estimate;
        }
        let fitted = simulate(&model, &params);
        let truth = ids.iter().map(|&i| model.parameters[i].value).collect();
        let time = (0..model.sampling.n_samples())
            .map(|k| model.sampling.time(k))
            .collect();
        Case {
            model,
            time,
            measured,
            fitted,
            result,
            truth,
        }
    })
}

fn input(c: &Case) -> ReportInput<'_> {
    ReportInput {
        title: "knee–column benchmark, 2 % noise, seed 1".into(),
        model: &c.model,
        result: &c.result,
        time: &c.time,
        measured: &c.measured,
        fitted: &c.fitted,
        reference: Some(&c.truth),
    }
}

fn out_dir(name: &str) -> PathBuf {
    let d = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&d);
    d
}

#[test]
fn page_has_every_section_in_order_and_every_sensor_and_parameter() {
    let c = case();
    let html = render_html(&input(c)).expect("renders");
    let mut at = 0;
    for (id, title) in SECTIONS {
        let heading = format!("<section id=\"{id}\">\n<h2>{title}</h2>");
        let pos = html[at..]
            .find(&heading)
            .unwrap_or_else(|| panic!("section '{title}' missing or out of order"));
        at += pos + heading.len();
    }
    for s in &c.model.sensors {
        assert!(html.contains(&s.name), "sensor {}", s.name);
    }
    for p in &c.result.parameters {
        assert!(
            html.contains(&format!("id=\"param-{}\"", p.name)),
            "parameter {}",
            p.name
        );
    }
    for b in &c.model.bodies {
        assert!(html.contains(&b.name), "body {}", b.name);
    }
    for e in &c.model.elements {
        assert!(html.contains(&e.name), "element {}", e.name);
    }
    assert!(html.contains("Worst |estimate − reference|"));
    assert!(html.contains("daN/µm²"), "display units");
    assert_self_contained(&html);
}

#[test]
fn report_files_are_written_well_formed_and_small() {
    let c = case();
    let dir = out_dir("report_knee_column");
    let files = write_report(&dir, &input(c)).expect("writes");
    assert_eq!(files.html, dir.join("report.html"));
    let html = std::fs::read_to_string(&files.html).expect("html written");
    let size = html.len();
    eprintln!(
        "report.html: {} KB at {}",
        size / 1024,
        files.html.display()
    );
    // 300 KB before the frequency-response section, whose three figures
    // (band, model, H1, phase, coherence) take about 22 KB each.
    assert!(size < 370 * 1024, "report.html is {size} bytes");

    // Three figures per sensor (response, residual spectrum, the FRF from
    // the one excitation), plus parameters, residuals, plan, 2 × history,
    // correlation.
    assert_eq!(files.figures.len(), 3 * c.model.sensors.len() + 6);
    let inline = inline_svgs(&html);
    assert_eq!(inline.len(), files.figures.len(), "every figure inline");
    for (path, inlined) in files.figures.iter().zip(&inline) {
        let text = std::fs::read_to_string(path).expect("figure written");
        assert!(text.starts_with("<?xml"), "{}", path.display());
        let elements = check_svg(&text);
        assert!(elements > 10, "{}: {elements} elements", path.display());
        assert!(
            text.ends_with(&format!("{inlined}\n")),
            "{} inlined as written",
            path.display()
        );
        check_svg(inlined);
        let kb = text.len() / 1024;
        eprintln!("  {}: {kb} KB", path.file_name().unwrap().to_string_lossy());
    }
    for s in &c.model.sensors {
        assert!(
            files
                .figures
                .iter()
                .any(|f| f.to_string_lossy().contains(&s.name)),
            "figure of {}",
            s.name
        );
    }
}

#[test]
fn long_signals_are_decimated_but_keep_their_peaks() {
    let c = case();
    let html = render_html(&input(c)).expect("renders");
    let first = inline_svgs(&html)
        .into_iter()
        .find(|s| s.contains(&c.model.sensors[0].name) && s.contains("zoom:"))
        .expect("response figure");
    // 2 signals × 3000 samples would be ≥ 6000 path vertices undecimated.
    let separators = first.matches(' ').count();
    assert!(separators < 6000, "{separators} separators: not decimated?");
    assert!(
        first.len() < 60 * 1024,
        "response figure {} bytes",
        first.len()
    );
}
