//! `rfeid check`: validate and summarise a model.
use crate::cli::CheckArgs;
use crate::diagnostics::Failure;
use crate::format::{sig, table};
use crate::run::experiments::campaign_data;
use crate::run::failures::simulation_failure;
use crate::run::inputs::load;
use crate::ui::Ui;
use rfeid::model::{Attachment, Law, Model, Value, COMPONENT_NAMES};
use rfeid::simulation::equilibrium::contacts_at_rest;
use rfeid::simulation::{free::free_directions, steps::integrator, Simulator};

/// Runs the command.
pub fn run(args: CheckArgs, ui: &Ui) -> Result<(), Failure> {
    let model = load(&args.model, ui)?;
    // A campaign names its data: read them as identify would, so that a
    // missing, short or mismatched file shows here and not after a plan.
    if !model.experiments.is_empty() {
        campaign_data(&model, &args.model, ui)?;
    }
    let free = free_text(&model, &args.model)?;
    if ui.json {
        let mut json = json_summary(&model);
        json["free_directions"] = serde_json::json!(free);
        return ui.print_json(&json);
    }
    print!("{}", summary(&model));
    if !free.is_empty() {
        println!("\nFree directions (no spring along them)");
        for f in &free {
            println!("  {f} (no restoring force)");
        }
    }
    let contacts = contacts_text(&model)?;
    if !contacts.is_empty() {
        println!("\nContacts at rest (the static equilibrium at the nominal values)");
        for c in &contacts {
            println!("  {c}");
        }
    }
    if !model.experiments.is_empty() {
        println!("\ndata: every experiment's file read and matched to its sensors and sampling");
    }
    println!("\n{}: OK", args.model.display());
    Ok(())
}

/// The directions no spring restrains at the nominal values, in words
/// (`carriage: free along x`); bad input (exit 2) if gravity pulls along
/// one, since then no static equilibrium exists.
fn free_text(model: &Model, path: &std::path::Path) -> Result<Vec<String>, Failure> {
    let sim = Simulator::with_integrator(model, integrator(1));
    let sys = sim
        .system(&model.nominal())
        .map_err(|e| simulation_failure("the model at its nominal values", e))?;
    let free = free_directions(&sys);
    if model.gravity.is_some() {
        free.check_gravity(&sys)
            .map_err(|e| Failure::input_msg(format!("{}: {e}", path.display())))?;
    }
    Ok(free.descriptions(model))
}

/// Each contact at the static equilibrium at the nominal values, in words
/// (`slideway uz: closed by 4.00e-6 m, carrying 16.0 N`).
fn contacts_text(model: &Model) -> Result<Vec<String>, Failure> {
    let sim = Simulator::with_integrator(model, integrator(1));
    let at_rest = |what| move |e| simulation_failure(what, e);
    let sys = (sim.system(&model.nominal())).map_err(at_rest("the model at its nominal values"))?;
    let contacts = contacts_at_rest(&sys).map_err(at_rest("the static equilibrium"))?;
    let comps = &sim.structure().components;
    Ok(contacts
        .iter()
        .map(|c| {
            let comp = &comps[c.component];
            let name = format!(
                "{} {}",
                model.elements[comp.element].name, COMPONENT_NAMES[comp.dof]
            );
            let (length, force) = match comp.dof < 3 {
                true => ("m", "N"),
                false => ("rad", "N*m"),
            };
            match c.closure {
                s if s > 0.0 => format!(
                    "{name}: closed by {s:.3e} {length}, carrying {:.4e} {force}",
                    c.force
                ),
                0.0 => format!("{name}: touching (closes under the first push)"),
                s => format!("{name}: open by {:.3e} {length}", -s),
            }
        })
        .collect())
}

/// The model's summary for `--json`.
fn json_summary(model: &Model) -> serde_json::Value {
    let s = model.sampling;
    serde_json::json!({
        "bodies": model.bodies.iter().map(|b| &b.name).collect::<Vec<_>>(),
        "degrees_of_freedom": model.n_dof(),
        "elements": model.elements.iter().map(|e| &e.name).collect::<Vec<_>>(),
        "sensors": model.sensors.iter().map(|s| serde_json::json!({"name": s.name, "unit": s.kind.unit(), "noise": s.noise})).collect::<Vec<_>>(),
        "candidates": model.candidates.iter().map(|s| serde_json::json!({"name": s.name, "unit": s.kind.unit(), "noise": s.noise})).collect::<Vec<_>>(),
        "samples": s.n_samples(),
        "sample_rate": s.sample_rate,
        "parameters": model.parameters.iter().map(|p| serde_json::json!({
            "name": p.name,
            "nominal": p.value,
            "min": p.bounds.map(|b| b.0),
            "max": p.bounds.map(|b| b.1),
            "identified": p.bounds.is_some(),
            "scale": p.bounds.map(|_| p.scale.as_str()),
            "si_unit": p.dimension.to_string(),
        })).collect::<Vec<_>>(),
    })
}

/// A readable summary of a model.
pub fn summary(model: &Model) -> String {
    let mut out = String::new();
    let s = model.sampling;
    out.push_str(&format!(
        "{} bodies, {} degrees of freedom, {} elements, {} excitations, {} sensors\n",
        model.bodies.len(),
        model.n_dof(),
        model.elements.len(),
        model.excitations.len(),
        model.sensors.len()
    ));
    out.push_str(&format!(
        "sampling: {} s at {} Hz = {} samples; {}\n",
        sig(s.duration, 6),
        sig(s.sample_rate, 6),
        s.n_samples(),
        s.steps_text()
    ));
    if let Some(g) = model.gravity {
        out.push_str(&format!(
            "gravity: [{}, {}, {}] m/s^2 (runs start from static equilibrium)\n",
            g.x, g.y, g.z
        ));
    }
    out.push_str("\nBodies\n");
    out.push_str(&bodies_table(model));
    out.push_str("\nElements\n");
    out.push_str(&elements_table(model));
    out.push_str("\nSensors\n");
    out.push_str(&sensors_table(model, &model.sensors));
    if !model.candidates.is_empty() {
        out.push_str(&format!(
            "\nCandidate sensors ({}, for `rfeid design --choose K`; not measured)\n",
            model.candidates.len()
        ));
        out.push_str(&sensors_table(model, &model.candidates));
    }
    let identified = model.identified();
    out.push_str(&format!(
        "\nParameters ({} identified, {} fixed)\n",
        identified.len(),
        model.parameters.len() - identified.len()
    ));
    out.push_str(&parameters_table(model));
    out
}

/// A coefficient as the summary shows it: a number, or its parameter's name.
fn value_text(model: &Model, v: &Value) -> String {
    match v {
        Value::Fixed(x) => sig(*x, 5),
        Value::Param(i) => model.parameters[*i].name.clone(),
    }
}

/// The bodies: mass, inertia and centre of mass.
fn bodies_table(model: &Model) -> String {
    let value = |v: &Value| value_text(model, v);
    let rows: Vec<Vec<String>> = model
        .bodies
        .iter()
        .map(|b| {
            vec![
                b.name.clone(),
                value(&b.mass),
                b.inertia.iter().map(value).collect::<Vec<_>>().join(", "),
                format!("({}, {}, {})", b.com.x, b.com.y, b.com.z),
            ]
        })
        .collect();
    table(
        &["body", "mass kg", "J1, J2, J3 kg·m²", "centre of mass m"],
        &rows,
    )
}

/// The elements: what they join and their components' laws.
fn elements_table(model: &Model) -> String {
    let value = |v: &Value| value_text(model, v);
    let rows: Vec<Vec<String>> = model
        .elements
        .iter()
        .map(|e| {
            let to = match e.to {
                Attachment::Body(p) => model.bodies[p].name.clone(),
                Attachment::Ground => "ground".into(),
            };
            let comps = e
                .components
                .iter()
                .map(|c| {
                    let law = c.law.joint();
                    let owns_damping = law.owns_damping();
                    let keys = law
                        .keys()
                        .into_iter()
                        .map(|k| format!(" {}={}", k.name, value(&k.value)));
                    let law = match c.law {
                        Law::None => "c only".to_string(),
                        _ => std::iter::once(law.name().to_string())
                            .chain(keys)
                            .collect(),
                    };
                    // A law that takes c itself (a contact) shows it among its keys.
                    match owns_damping {
                        true => format!("{}[{law}]", COMPONENT_NAMES[c.dof]),
                        false => {
                            format!("{}[{law} c={}]", COMPONENT_NAMES[c.dof], value(&c.damping))
                        }
                    }
                })
                .collect::<Vec<_>>()
                .join(" ");
            vec![
                e.name.clone(),
                format!("{} → {to}", model.bodies[e.body].name),
                comps,
            ]
        })
        .collect();
    table(&["element", "joins", "components"], &rows)
}

/// Sensors of the model: what they read, where, along what, and the
/// noise `rfeid design` assumes.
fn sensors_table(model: &Model, sensors: &[rfeid::model::Sensor]) -> String {
    let rows: Vec<Vec<String>> = sensors
        .iter()
        .map(|s| {
            vec![
                s.name.clone(),
                format!("{:?}", s.kind).to_lowercase(),
                model.bodies[s.body].name.clone(),
                format!("({}, {}, {})", s.at.x, s.at.y, s.at.z),
                format!(
                    "({}, {}, {})",
                    sig(s.direction.x, 4),
                    sig(s.direction.y, 4),
                    sig(s.direction.z, 4)
                ),
                s.noise
                    .map_or("-".into(), |n| format!("{} {}", sig(n, 3), s.kind.unit())),
            ]
        })
        .collect();
    table(
        &["sensor", "reads", "body", "at m", "direction", "noise σ"],
        &rows,
    )
}

/// The parameters: unit, nominal value, box and scale.
fn parameters_table(model: &Model) -> String {
    let rows: Vec<Vec<String>> = model
        .parameters
        .iter()
        .map(|p| {
            let u = &p.unit;
            let show = |v: f64| sig(v / u.scale, 5);
            let (lo, hi, scale) = p
                .bounds
                .map(|(l, h)| (show(l), show(h), p.scale.as_str().to_string()))
                .unwrap_or(("-".into(), "-".into(), "-".into()));
            let unit = if u.symbol.is_empty() {
                p.dimension.to_string()
            } else {
                u.symbol.clone()
            };
            vec![p.name.clone(), unit, show(p.value), lo, hi, scale]
        })
        .collect();
    table(
        &["parameter", "unit", "nominal", "min", "max", "scale"],
        &rows,
    )
}
