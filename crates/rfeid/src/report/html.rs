//! The HTML page: inline CSS, no script, figures inline.
use super::fmt::{minus, seconds, sig, unit};
use super::svg::escape;
use super::{model_summary, Figure, ReportInput, SECTIONS};
use crate::identification::noise::StdErrorScope;
use crate::identification::result::{IdentificationResult, ParameterEstimate};
use crate::identification::search::Method;
use crate::identification::verdict::Outcome;
use std::fmt::Write;

pub(crate) const CSS: &str = "\
body{font-family:'DejaVu Sans',Helvetica,Arial,sans-serif;color:#222;max-width:900px;margin:0 auto;padding:16px 20px;line-height:1.4;font-size:14px}\
h1{font-size:22px;margin:0 0 6px}h2{font-size:18px;border-bottom:2px solid #0072B2;padding-bottom:2px;margin:28px 0 10px}\
h3{font-size:15px;margin:16px 0 6px}\
nav{font-size:12px;color:#555;margin-bottom:8px}nav a{color:#0072B2;margin-right:10px;text-decoration:none;white-space:nowrap}.nw{white-space:nowrap}\
.verdict{font-size:17px;font-weight:bold;padding:8px 12px;border-radius:4px;margin:8px 0}\
.verdict ul{font-size:14px;font-weight:normal;margin:6px 0 0}\
p.search{padding:4px 12px;margin:4px 0}\
.ok{background:#e3f4ec;border-left:6px solid #009E73}.bad{background:#fdeee4;border-left:6px solid #D55E00}\
.warn{background:#fff4d6;border:2px solid #E69F00;border-radius:4px;padding:8px 14px}\
.none{background:#e3f4ec;border:1px solid #009E73;border-radius:4px;padding:8px 14px}\
.warn ul,.none ul{margin:4px 0;padding-left:20px}\
table{border-collapse:collapse;font-size:12.5px;margin:6px 0 10px}\
th,td{border-bottom:1px solid #ddd;padding:3px 8px;text-align:left;vertical-align:top}\
th{background:#f0f0f0}td.n{text-align:right;font-variant-numeric:tabular-nums;white-space:nowrap}\
table.kv td:first-child{color:#555}\
tr.flag td{background:#fff4d6}\
figure{margin:10px 0 18px}figure svg{max-width:100%;height:auto}\
figcaption{font-size:12px;color:#555}\
.small{font-size:12px;color:#555}\
@media print{body{max-width:none;font-size:11px}h2{break-after:avoid}figure,table{break-inside:avoid}nav{display:none}}";

/// Whether the local search stopped on a convergence test.
pub(crate) fn converged(r: &IdentificationResult) -> bool {
    r.termination.is_converged()
}

/// A parameter value (SI) in the parameter's display unit, 4 digits.
fn shown(p: &ParameterEstimate, v: f64) -> String {
    sig(v / p.unit_scale, 4)
}

/// `<section>` start with the heading of `id`.
fn section(out: &mut String, id: &str) {
    let title = SECTIONS
        .iter()
        .find(|s| s.0 == id)
        .map(|s| s.1)
        .unwrap_or(id);
    let _ = write!(out, "<section id=\"{id}\">\n<h2>{}</h2>\n", escape(title));
}

/// The figures of section `id`.
fn figures_of(out: &mut String, figs: &[Figure], id: &str) {
    for f in figs.iter().filter(|f| f.section == id) {
        let _ = write!(
            out,
            "<figure>\n{}<figcaption>{} <span class=\"small\">({})</span></figcaption>\n</figure>\n",
            f.svg,
            escape(&f.caption),
            escape(&f.file)
        );
    }
}

/// A table; cells are HTML already, `numeric[i]` right-aligns column i.
pub(crate) fn table(
    header: &[&str],
    rows: &[Vec<String>],
    numeric: &[bool],
    flags: &[bool],
) -> String {
    let mut t = String::from("<table>\n<tr>");
    for h in header {
        let _ = write!(t, "<th>{}</th>", escape(h));
    }
    t.push_str("</tr>\n");
    for (i, row) in rows.iter().enumerate() {
        if flags.get(i).copied().unwrap_or(false) {
            t.push_str("<tr class=\"flag\">");
        } else {
            t.push_str("<tr>");
        }
        for (j, cell) in row.iter().enumerate() {
            if numeric.get(j).copied().unwrap_or(false) {
                let _ = write!(t, "<td class=\"n\">{cell}</td>");
            } else {
                let _ = write!(t, "<td>{cell}</td>");
            }
        }
        t.push_str("</tr>\n");
    }
    t.push_str("</table>\n");
    t
}

/// The worst relative error against the reference: (name, relative error,
/// error in standard errors).
fn worst_error(r: &IdentificationResult, reference: &[f64]) -> Option<(String, f64, Option<f64>)> {
    r.parameters
        .iter()
        .zip(reference)
        .map(|(p, x)| {
            let err = (p.estimate - x).abs();
            let rel = if *x != 0.0 { err / x.abs() } else { err };
            (p.name.clone(), rel, p.std_error.map(|s| err / s))
        })
        .max_by(|a, b| a.1.total_cmp(&b.1))
}

/// The verdict: trustworthy, or suspect with every reason.
fn verdict(out: &mut String, r: &IdentificationResult) {
    match &r.verdict {
        Some(v) if v.trustworthy => out.push_str(
            "<div class=\"verdict ok\">Trustworthy: no check of bounds, minima, convergence, \
             fit, residuals or identifiability found a reason to doubt this result.</div>\n",
        ),
        Some(v) => {
            let headline = match v.outcome() {
                Outcome::ModelError => "Model error: these estimates are the model's best fit, \
                                        with standard errors that cover the noise only; the \
                                        model lacks something the data show"
                    .to_string(),
                _ => format!(
                    "Suspect: do not use these estimates before resolving {} reason{}",
                    v.reasons.len(),
                    if v.reasons.len() == 1 { "" } else { "s" }
                ),
            };
            let _ = write!(out, "<div class=\"verdict bad\">{headline}:\n<ul>\n");
            for reason in &v.reasons {
                let _ = writeln!(out, "<li>{}</li>", escape(&reason.to_string()));
            }
            let _ = writeln!(
                out,
                "</ul>Decided by: {}.</div>",
                escape(&v.decided_by.join(", "))
            );
        }
        None => out.push_str(
            "<div class=\"verdict bad\">No verdict: this result was written by an rfeid \
             that did not check it.</div>\n",
        ),
    }
    if let Some(v) = r.verdict.as_ref().filter(|v| !v.sensors.is_empty()) {
        sensor_checks(out, v);
    }
}

/// Each sensor's residual checks: its fit, and the tests on what its noise
/// model leaves of its residuals (the model's order, Ljung–Box Q and p, the
/// noise-level ratio, the residual–input test's p).
fn sensor_checks(out: &mut String, v: &crate::identification::verdict::Verdict) {
    let num =
        |x: Option<f64>, digits: usize| x.map_or("-".to_string(), |x| format!("{x:.digits$}"));
    let p = |x: Option<f64>| x.map_or("-".to_string(), |x| format!("{x:.2e}"));
    out.push_str(
        "<table class=\"kv\">\n<tr><th>sensor</th><th>fit %</th><th>noise model order</th>\
         <th>Ljung–Box Q</th><th>p</th><th>noise ratio</th><th>input p</th></tr>\n",
    );
    for c in &v.sensors {
        let _ = writeln!(
            out,
            "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>",
            escape(&c.sensor),
            num(c.fit_percent, 2),
            c.noise_order.map_or("-".to_string(), |o| o.to_string()),
            num(c.ljung_box, 1),
            p(c.p_value),
            num(c.noise_ratio, 3),
            p(c.input_p_value),
        );
    }
    out.push_str("</table>\n");
}

/// The summary section: the verdict, how the local search ended, the worst
/// error against the reference, and a table of the result's numbers.
fn summary(out: &mut String, input: &ReportInput) {
    let r = input.result;
    section(out, "summary");
    verdict(out, r);
    search_outcome(out, r);
    if let Some(reference) = input.reference {
        worst_reference_error(out, r, reference);
    }
    let mut rows = summary_rows(input);
    rows.retain(|row| !row.1.is_empty());
    out.push_str("<table class=\"kv\">\n");
    for (k, v) in rows {
        let _ = writeln!(
            out,
            "<tr><td>{}</td><td>{}</td></tr>",
            escape(k),
            escape(&v)
        );
    }
    out.push_str("</table>\n</section>\n");
}

/// Whether the local search converged, and why it stopped.
fn search_outcome(out: &mut String, r: &IdentificationResult) {
    let (class, word) = if converged(r) {
        ("ok", "Converged")
    } else {
        ("bad", "Not converged")
    };
    // The message starts "converged: …" or "stopped: …"; the verdict says that.
    let why = r
        .termination_message
        .split_once(": ")
        .filter(|(head, _)| matches!(*head, "converged" | "stopped"))
        .map_or(r.termination_message.as_str(), |(_, tail)| tail);
    let _ = writeln!(
        out,
        "<p class=\"search {class}\">Local search: {word}: {}</p>",
        escape(why)
    );
}

/// The largest relative error of an estimate against the reference.
fn worst_reference_error(out: &mut String, r: &IdentificationResult, reference: &[f64]) {
    if let Some((name, rel, in_se)) = worst_error(r, reference) {
        let se = in_se
            .map(|s| format!(" = {} standard errors", sig(s, 2)))
            .unwrap_or_default();
        let _ = writeln!(
            out,
            "<p><b>Worst |estimate − reference|:</b> {} % of the reference ({}){}.</p>",
            sig(100.0 * rel, 3),
            escape(&name),
            se
        );
    }
}

/// The summary table's rows (name, value); an empty value is left out.
fn summary_rows(input: &ReportInput) -> Vec<(&'static str, String)> {
    let r = input.result;
    vec![
        ("criterion J (eq. 13)", sig(r.criterion, 4)),
        (
            "s² (eq. 29)",
            r.s2.map_or_else(|| "not available".into(), |v| sig(v, 4)),
        ),
        ("sum of squared residuals", sig(r.ssr, 4)),
        ("observations N", observations_text(r, input.time.len())),
        ("fitted from", format!("t = {} s", sig(r.from, 4))),
        ("experiments (fit per sensor, %)", experiments_text(r)),
        (
            "fit per sensor (100 (1 − ‖y − ŷ‖/‖y − ȳ‖))",
            sensor_fits_text(r),
        ),
        (
            "minima reached by the starts (J in the weighting of their searches)",
            minima_text(r),
        ),
        ("noise model per sensor", noise_text(r)),
        ("method", method_text(r)),
        ("integrator", integrator_text(r)),
        (
            "LP_τ plan",
            format!(
                "{} points, {} failed, {} abandoned, {} start(s)",
                r.plan.points,
                r.plan.failed,
                r.plan.abandoned.len(),
                r.plan.starts.len()
            ),
        ),
        (
            "condition number of the scaled Fisher matrix",
            r.condition_number
                .map_or_else(|| "not available".into(), |v| sig(v, 3)),
        ),
        (
            "sensor weights w_c",
            r.sensors
                .iter()
                .zip(&r.weights)
                .map(|(s, w)| format!("{s}: {}", sig(*w, 3)))
                .collect::<Vec<_>>()
                .join(", "),
        ),
        (
            "wall time",
            format!(
                "{} total: plan {}, local search {}, uncertainty {} ({} threads)",
                seconds(r.timings.total),
                seconds(r.timings.plan),
                seconds(r.timings.local_search),
                seconds(r.timings.uncertainty),
                r.threads
            ),
        ),
    ]
}

/// The number of observations as sensors × samples, of `samples` recorded.
fn observations_text(r: &IdentificationResult, samples: usize) -> String {
    if !r.experiments.is_empty() {
        let fitted: Vec<&str> = r
            .experiments
            .iter()
            .filter(|e| e.role == crate::model::Role::Fit)
            .map(|e| e.name.as_str())
            .collect();
        return format!(
            "{} over the fitted experiments ({})",
            r.observations,
            fitted.join(", ")
        );
    }
    format!(
        "{} = {} sensors × {} samples (of {} recorded)",
        r.observations,
        r.sensors.len(),
        r.observations / r.sensors.len().max(1),
        samples
    )
}

/// Each experiment with its role and its fit per sensor.
fn experiments_text(r: &IdentificationResult) -> String {
    r.experiments
        .iter()
        .map(|e| {
            let fits: Vec<String> = e
                .sensors
                .iter()
                .zip(&e.fits)
                .map(|(s, f)| match f {
                    Some(f) => format!("{s} {}", sig(*f, 4)),
                    None => format!("{s} undefined"),
                })
                .collect();
            let role = match e.role {
                crate::model::Role::Fit => "fitted",
                crate::model::Role::Validation => "validation",
            };
            format!("{} ({role}): {}", e.name, fits.join(", "))
        })
        .collect::<Vec<_>>()
        .join("; ")
}

/// Each sensor's noise model: white or AR(p), with the innovations'
/// standard deviation (empty with equal weights).
fn noise_text(r: &IdentificationResult) -> String {
    r.noise
        .iter()
        .map(|n| {
            let kind = match n.order {
                0 => "white".to_string(),
                p => format!("AR({p})"),
            };
            format!("{}: {kind}, σ {}", n.sensor, sig(n.innovation_std, 3))
        })
        .collect::<Vec<_>>()
        .join(", ")
}

/// The verdict's fit per sensor (empty without a verdict).
fn sensor_fits_text(r: &IdentificationResult) -> String {
    r.verdict.as_ref().map_or_else(String::new, |v| {
        v.sensors
            .iter()
            .map(|s| match s.fit_percent {
                Some(f) => format!("{}: {} %", s.sensor, sig(f, 4)),
                None => format!("{}: undefined (constant signal)", s.sensor),
            })
            .collect::<Vec<_>>()
            .join(", ")
    })
}

/// The verdict's distinct minima with how many starts reached each (empty
/// without a verdict).
fn minima_text(r: &IdentificationResult) -> String {
    r.verdict.as_ref().map_or_else(String::new, |v| {
        v.minima
            .iter()
            .map(|m| {
                format!(
                    "J = {} ({} start{})",
                    sig(m.cost, 4),
                    m.starts,
                    if m.starts == 1 { "" } else { "s" }
                )
            })
            .collect::<Vec<_>>()
            .join(", ")
    })
}

/// The local search's method, iterations and simulations.
fn method_text(r: &IdentificationResult) -> String {
    format!(
        "{} — {} iterations, {} simulations ({} with sensitivities, {} failed)",
        match r.method {
            Method::Lm => "Levenberg–Marquardt",
            Method::Bfgs => "BFGS",
        },
        r.iterations,
        r.simulations,
        r.simulations_with_sensitivities,
        r.failed_simulations
    )
}

/// The integrator's steps per sample, how they were chosen, and its error.
fn integrator_text(r: &IdentificationResult) -> String {
    match &r.simulation {
        Some(s) => format!(
            "{} step(s) per sample ({}); estimated relative error at the estimate {}",
            s.substeps,
            if s.automatic {
                format!("chosen for a tolerance of {:.0e}", s.tolerance)
            } else {
                "fixed".into()
            },
            s.estimated_error
                .map(|e| format!("{e:.1e}"))
                .unwrap_or_else(|| "not estimated".into())
        ),
        None => "not recorded".into(),
    }
}

/// Notes on the estimates that are not identifiability warnings as such.
fn notes(input: &ReportInput) -> Vec<String> {
    let r = input.result;
    let mut out = Vec::new();
    if !converged(r) {
        out.push(format!(
            "The local search did not converge: {}.",
            r.termination_message
        ));
    }
    for p in &r.parameters {
        let w = p.max - p.min;
        if w > 0.0 && (p.estimate - p.min) <= 1e-6 * w {
            out.push(format!("{} is at the lower end of its box.", p.name));
        } else if w > 0.0 && (p.max - p.estimate) <= 1e-6 * w {
            out.push(format!("{} is at the upper end of its box.", p.name));
        }
    }
    if r.plan.failed > 0 {
        let mut s = format!(
            "{} of {} plan points failed to simulate",
            r.plan.failed, r.plan.points
        );
        if let Some(f) = &r.plan.first_failure {
            s.push_str(&format!("; the first: {f}"));
        }
        s.push('.');
        out.push(s);
    }
    out
}

fn warnings(out: &mut String, input: &ReportInput) {
    let r = input.result;
    section(out, "warnings");
    let mut items: Vec<String> = r.warnings.iter().map(|w| w.to_string()).collect();
    if let Some(e) = &r.uncertainty_error {
        items.push(format!("Standard errors could not be computed: {e}"));
    }
    if items.is_empty() {
        out.push_str(
            "<div class=\"none\"><b>None.</b> The Cramér–Rao analysis found every parameter \
             constrained by the data and no strong correlation.</div>\n",
        );
    } else {
        out.push_str("<div class=\"warn\"><b>Warnings</b>\n<ul>\n");
        for w in &items {
            let _ = writeln!(out, "<li>{}</li>", escape(w));
        }
        out.push_str("</ul></div>\n");
    }
    let notes = notes(input);
    if !notes.is_empty() {
        out.push_str("<h3>Notes</h3>\n<ul>\n");
        for n in &notes {
            let _ = writeln!(out, "<li>{}</li>", escape(n));
        }
        out.push_str("</ul>\n");
    }
    out.push_str("</section>\n");
}

fn parameters(out: &mut String, input: &ReportInput, figs: &[Figure]) {
    let r = input.result;
    section(out, "parameters");
    let mut header = vec![
        "parameter",
        "unit",
        "min",
        "max",
        "scale",
        "nominal",
        "estimate",
        match r.std_errors_cover {
            StdErrorScope::Noise => "standard error",
            StdErrorScope::NoiseOnly => "standard error (noise only)",
        },
        "s.e. / estimate",
    ];
    if input.reference.is_some() {
        header.extend(["reference", "error", "error / s.e."]);
    }
    let mut numeric = vec![false, false, true, true, false];
    numeric.resize(header.len(), true);
    let mut flags = Vec::new();
    let rows: Vec<Vec<String>> = r
        .parameters
        .iter()
        .enumerate()
        .map(|(j, p)| {
            let se = p.std_error;
            let mut row = vec![
                format!("<span id=\"param-{0}\">{0}</span>", escape(&p.name)),
                format!("<span class=\"nw\">{}</span>", escape(&unit(&p.unit))),
                shown(p, p.min),
                shown(p, p.max),
                p.scale.as_str().to_string(),
                shown(p, p.nominal),
                format!("<b>{}</b>", shown(p, p.estimate)),
                se.map_or_else(|| "—".into(), |s| sig(s / p.unit_scale, 3)),
                se.map_or_else(
                    || "—".into(),
                    |s| format!("{} %", sig(100.0 * s / p.estimate.abs(), 3)),
                ),
            ];
            let w = p.max - p.min;
            flags.push(se.is_some_and(|s| s > w));
            if let Some(x) = input.reference.and_then(|rf| rf.get(j)) {
                let err = p.estimate - x;
                row.push(shown(p, *x));
                row.push(if *x != 0.0 {
                    minus(&format!("{:+.3} %", 100.0 * err / x.abs()))
                } else {
                    sig(err / p.unit_scale, 3)
                });
                row.push(se.map_or_else(|| "—".into(), |s| minus(&format!("{:+.2}", err / s))));
            }
            row
        })
        .collect();
    out.push_str(&table(&header, &rows, &numeric, &flags));
    out.push_str(
        "<p class=\"small\">Values in each parameter's unit from the model file (SI where none \
         is given). Standard errors are Cramér–Rao bounds (eq. 26) under each sensor's noise \
         model (white, or autoregressive: eq. 26–29 on the prewhitened criterion), valid for a \
         correct model; under model error they cover the noise only. Highlighted rows: standard error wider than the box. \
         Scale: how the plan and the local search spread over the box (log: equal steps are \
         equal ratios).</p>\n",
    );
    figures_of(out, figs, "parameters");
    out.push_str("</section>\n");
}

fn plan_text(out: &mut String, r: &IdentificationResult) {
    let finite: Vec<f64> = r.plan.costs.iter().flatten().copied().collect();
    let best = finite.iter().copied().fold(f64::INFINITY, f64::min);
    let _ = write!(
        out,
        "<p>{} plan points, {} failed to simulate{}. Best plan J = {}; the local search started \
         from plan point(s) {}.",
        r.plan.points,
        r.plan.failed,
        match r.plan.abandoned.len() {
            0 => String::new(),
            n => format!(
                ", {n} abandoned (their running J passed the best points', so their \
                 simulation stopped there)"
            ),
        },
        sig(best, 4),
        r.plan
            .starts
            .iter()
            .map(|s| (s + 1).to_string())
            .collect::<Vec<_>>()
            .join(", ")
    );
    if let Some(f) = &r.plan.first_failure {
        let _ = write!(out, " First failure: {}.", escape(f));
    }
    out.push_str("</p>\n");
}

/// The whole page.
pub(crate) fn page(input: &ReportInput, figs: &[Figure]) -> String {
    let r = input.result;
    let mut out = String::with_capacity(256 * 1024);
    let _ = write!(
        out,
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
         <meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n\
         <title>{t} — rfeid report</title>\n<style>{CSS}</style>\n</head>\n<body>\n\
         <h1>{t}</h1>\n<nav>",
        t = escape(&input.title)
    );
    for (id, title) in SECTIONS {
        let _ = writeln!(out, "<a href=\"#{id}\">{}</a>", escape(title));
    }
    out.push_str("</nav>\n");
    summary(&mut out, input);
    warnings(&mut out, input);
    parameters(&mut out, input, figs);

    section(&mut out, "response");
    figures_of(&mut out, figs, "response");
    out.push_str("</section>\n");

    section(&mut out, "residuals");
    figures_of(&mut out, figs, "residuals");
    out.push_str("</section>\n");

    section(&mut out, "frf");
    match figs.iter().any(|f| f.section == "frf") {
        true => figures_of(&mut out, figs, "frf"),
        false => out.push_str(&format!("<p>{}</p>\n", escape(super::frf::LEFT_OUT))),
    }
    out.push_str("</section>\n");

    section(&mut out, "plan");
    plan_text(&mut out, r);
    figures_of(&mut out, figs, "plan");
    out.push_str("</section>\n");

    section(&mut out, "history");
    if r.history.is_empty() {
        out.push_str("<p>No history was recorded.</p>\n");
    }
    figures_of(&mut out, figs, "history");
    out.push_str("</section>\n");

    section(&mut out, "correlation");
    match (&r.correlation, &r.uncertainty_error) {
        (Some(_), _) => {
            if let Some(c) = r.condition_number {
                let _ = writeln!(
                    out,
                    "<p>Condition number of the column-scaled Fisher matrix: {}.</p>",
                    sig(c, 3)
                );
            }
        }
        (None, Some(e)) => {
            let _ = writeln!(out, "<p>Not available: {}.</p>", escape(e));
        }
        (None, None) => out.push_str("<p>Not available.</p>\n"),
    }
    figures_of(&mut out, figs, "correlation");
    out.push_str("</section>\n");

    section(&mut out, "model");
    out.push_str(&model_summary::model_summary(input.model, r));
    out.push_str("</section>\n");

    let _ = write!(
        out,
        "<footer class=\"small\"><p>Written by rfeid {}. Self-contained: no script, no \
         external resources; each figure is also a separate SVG file beside this one.</p>\
         </footer>\n</body>\n</html>\n",
        env!("CARGO_PKG_VERSION")
    );
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tables_escape_headers_and_align_numbers() {
        let t = table(
            &["a<b", "x"],
            &[vec!["n".into(), "1".into()]],
            &[false, true],
            &[true],
        );
        assert!(t.contains("<th>a&lt;b</th>"));
        assert!(t.contains("<td class=\"n\">1</td>"));
        assert!(t.contains("<tr class=\"flag\">"));
    }
}
