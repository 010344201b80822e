//! The model in tables: sampling, bodies, spring–damping elements,
//! excitations, sensors, fixed parameters.
use super::fmt::{short, sig, unit};
use super::html::table;
use super::svg::escape;
use crate::identification::result::IdentificationResult;
use crate::model::{Attachment, Model, SensorKind, Value, COMPONENT_NAMES};
use crate::simulation::free::free_directions;
use crate::simulation::steps::integrator;
use crate::simulation::Simulator;
use nalgebra::Vector3;
use std::fmt::Write;

/// A coefficient: a fixed number with its SI unit, or the parameter's name
/// (linked to its row of the parameter table when identified).
fn value(model: &Model, v: &Value, si_unit: &str) -> String {
    match *v {
        Value::Fixed(x) => {
            let s = short(x, 4);
            if si_unit.is_empty() {
                s
            } else {
                format!("{s} {}", unit(si_unit))
            }
        }
        Value::Param(i) => match model.parameters.get(i) {
            Some(p) if p.bounds.is_some() => {
                format!("<a href=\"#param-{0}\"><i>{0}</i></a>", escape(&p.name))
            }
            Some(p) => format!("<i>{}</i>", escape(&p.name)),
            None => "?".into(),
        },
    }
}

fn vector(v: &Vector3<f64>) -> String {
    format!("({}, {}, {})", short(v.x, 4), short(v.y, 4), short(v.z, 4))
}

fn body_name(model: &Model, b: usize) -> String {
    model
        .bodies
        .get(b)
        .map_or_else(|| "?".into(), |b| escape(&b.name))
}

/// The components of an element in words, e.g.
/// `ux: a·sign(δ)|δ|^m, a = a_n1, m = 2; c = h_n1`: each law's formula
/// and keys as it gives them.
fn components(model: &Model, e: &crate::model::Element) -> String {
    e.components
        .iter()
        .map(|c| {
            let rot = c.dof >= 3;
            let c_unit = if rot { "N*m*s/rad" } else { "N*s/m" };
            let name = COMPONENT_NAMES.get(c.dof).copied().unwrap_or("?");
            let law = c.law.joint();
            let mut text = law.formula();
            for key in law.keys() {
                let unit = key.unit.symbol(rot);
                let _ = write!(
                    text,
                    ", {} = {}",
                    key.symbol,
                    value(model, &key.value, unit)
                );
            }
            // A law that takes c itself (a contact) lists it among its keys.
            match law.owns_damping() {
                true => format!("<b>{name}</b>: {text}"),
                false => format!(
                    "<b>{name}</b>: {text}; c = {}",
                    value(model, &c.damping, c_unit)
                ),
            }
        })
        .collect::<Vec<_>>()
        .join("<br>")
}

fn kind(k: SensorKind) -> &'static str {
    match k {
        SensorKind::Displacement => "displacement",
        SensorKind::Velocity => "velocity",
        SensorKind::Acceleration => "acceleration",
    }
}

/// The model section's body.
pub(crate) fn model_summary(model: &Model, result: &IdentificationResult) -> String {
    let mut out = String::new();
    overview(&mut out, model);
    free_note(&mut out, model);
    bodies_table(&mut out, model);
    elements_table(&mut out, model);
    excitations_table(&mut out, model);
    sensors_table(&mut out, model, result);
    fixed_parameters_table(&mut out, model);
    out
}

/// One paragraph of counts, the record and gravity.
fn overview(out: &mut String, model: &Model) {
    let s = &model.sampling;
    let _ = writeln!(
        out,
        "<p>{} bodies ({} degrees of freedom), {} spring–damping elements, {} excitation(s), \
         {} sensor(s); {} parameters, {} identified. Record: {} s at {} Hz ({} samples, \
         {}){}.</p>",
        model.bodies.len(),
        model.n_dof(),
        model.elements.len(),
        model.excitations.len(),
        model.sensors.len(),
        model.parameters.len(),
        model.identified().len(),
        short(s.duration, 4),
        short(s.sample_rate, 6),
        s.n_samples(),
        s.steps_text(),
        model
            .gravity
            .map(|g| format!("; gravity {} m/s², from static equilibrium", vector(&g)))
            .unwrap_or_default()
    );
}

/// The directions no spring restrains at the nominal values
/// ([`crate::simulation::free`]), if any: rigid-body motions with no
/// restoring force, such as a feed axis driven through a damper.
fn free_note(out: &mut String, model: &Model) {
    let sim = Simulator::with_integrator(model, integrator(1));
    let Ok(sys) = sim.system(&model.nominal()) else {
        return;
    };
    let free = free_directions(&sys).descriptions(model);
    if !free.is_empty() {
        let list: Vec<String> = free.iter().map(|f| escape(f)).collect();
        let _ = writeln!(
            out,
            "<p>Free directions (no spring along them, so no restoring force; a \
             zero-frequency mode each): {}.</p>",
            list.join("; ")
        );
    }
}

/// The bodies: mass, moments of inertia and centre of mass.
fn bodies_table(out: &mut String, model: &Model) {
    out.push_str("<h3>Bodies</h3>\n");
    let rows: Vec<Vec<String>> = model
        .bodies
        .iter()
        .map(|b| {
            vec![
                escape(&b.name),
                value(model, &b.mass, "kg"),
                b.inertia
                    .iter()
                    .map(|j| value(model, j, ""))
                    .collect::<Vec<_>>()
                    .join(", "),
                vector(&b.com),
            ]
        })
        .collect();
    out.push_str(&table(
        &["body", "mass", "J1, J2, J3 (kg·m²)", "centre of mass (m)"],
        &rows,
        &[false, true, true, true],
        &[],
    ));
}

/// The spring–damping elements: what they join, where, and their components.
fn elements_table(out: &mut String, model: &Model) {
    out.push_str("<h3>Spring–damping elements</h3>\n");
    let rows: Vec<Vec<String>> = model
        .elements
        .iter()
        .map(|e| {
            vec![
                escape(&e.name),
                format!(
                    "{} – {}",
                    body_name(model, e.body),
                    match e.to {
                        Attachment::Body(b) => body_name(model, b),
                        Attachment::Ground => "ground".into(),
                    }
                ),
                vector(&e.at),
                components(model, e),
            ]
        })
        .collect();
    out.push_str(&table(
        &["element", "joins", "at (m)", "components (element axes)"],
        &rows,
        &[false, false, true, false],
        &[],
    ));
}

/// The excitations, if any: where they act and their signals.
fn excitations_table(out: &mut String, model: &Model) {
    if model.excitations.is_empty() {
        return;
    }
    out.push_str("<h3>Excitations</h3>\n");
    let rows: Vec<Vec<String>> = model
        .excitations
        .iter()
        .map(|x| {
            vec![
                escape(&x.name),
                match x.reaction {
                    Some(r) => format!(
                        "{} (reaction on {})",
                        body_name(model, x.body),
                        body_name(model, r)
                    ),
                    None => body_name(model, x.body),
                },
                vector(&x.at),
                vector(&x.direction),
                escape(x.signal.kind),
            ]
        })
        .collect();
    out.push_str(&table(
        &["excitation", "on", "at (m)", "direction", "signal"],
        &rows,
        &[false, false, true, true, false],
        &[],
    ));
}

/// The sensors: what they read, where, and their weights in the result.
fn sensors_table(out: &mut String, model: &Model, result: &IdentificationResult) {
    out.push_str("<h3>Sensors</h3>\n");
    let rows: Vec<Vec<String>> = model
        .sensors
        .iter()
        .map(|sn| {
            let w = result
                .sensors
                .iter()
                .position(|n| *n == sn.name)
                .and_then(|c| result.weights.get(c))
                .map_or_else(|| "—".into(), |w| sig(*w, 3));
            vec![
                escape(&sn.name),
                format!("{} ({})", kind(sn.kind), unit(sn.kind.unit())),
                body_name(model, sn.body),
                vector(&sn.at),
                vector(&sn.direction),
                w,
            ]
        })
        .collect();
    out.push_str(&table(
        &[
            "sensor",
            "reads",
            "body",
            "at (m)",
            "direction",
            "weight w_c",
        ],
        &rows,
        &[false, false, false, true, true, true],
        &[],
    ));
}

/// The parameters that are not identified, if any, with their values.
fn fixed_parameters_table(out: &mut String, model: &Model) {
    let fixed: Vec<Vec<String>> = model
        .parameters
        .iter()
        .filter(|p| p.bounds.is_none())
        .map(|p| {
            vec![
                escape(&p.name),
                format!(
                    "{} {}",
                    short(p.value / p.unit.scale, 4),
                    unit(&p.unit.symbol)
                ),
            ]
        })
        .collect();
    if !fixed.is_empty() {
        out.push_str("<h3>Fixed parameters</h3>\n");
        out.push_str(&table(&["parameter", "value"], &fixed, &[false, true], &[]));
    }
}
