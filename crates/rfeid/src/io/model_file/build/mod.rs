//! From the raw file to a validated [`Model`].
mod component;
mod ctx;
mod experiments;
mod parameters;
mod signal;

use crate::io::model_file::raw::*;
use crate::model::*;
use crate::units::{parse_quantity, Dimension};
use component::component;
use ctx::*;
use parameters::finish_parameters;
use signal::{sampling, signal};
use std::collections::HashMap;
use std::path::Path;
use std::sync::Arc;
use toml::Spanned;

pub(super) fn build(text: &str, path: &Path) -> Result<Model> {
    let mut ctx = Ctx {
        path: path.into(),
        dir: path.parent().map(Path::to_path_buf).unwrap_or_default(),
        text: Arc::from(text),
        params: Vec::new(),
        param_index: HashMap::new(),
        files: Default::default(),
    };
    let raw: RawFile = toml::from_str(text).map_err(|e| toml_error(&ctx, text, &e))?;

    // Parameters first, so that fields can name them.
    for (i, p) in raw.parameter.iter().enumerate() {
        let (name, span) = name_of(&ctx, &p.get_ref().name, p.span(), "parameter", i)?;
        if ctx.param_index.contains_key(&name) {
            return Err(ctx.err(
                Some(span),
                &format!("parameter \"{name}\""),
                "name",
                "duplicate parameter name",
            ));
        }
        let entry = format!("parameter \"{name}\"");
        let read = |v: &SNum, field: &str| -> Result<(f64, Option<Dimension>, String)> {
            match v.get_ref() {
                RawNum::Num(x) => Ok((
                    ctx.finite(*x, v.span(), &entry, field)?,
                    None,
                    String::new(),
                )),
                RawNum::Text(t) => {
                    let q = parse_quantity(t)
                        .map_err(|e| ctx.err(Some(v.span()), &entry, field, e.to_string()))?;
                    let sym = unit_symbol(t).to_string();
                    let dim = (!sym.is_empty()).then_some(q.dim);
                    Ok((ctx.finite(q.value, v.span(), &entry, field)?, dim, sym))
                }
            }
        };
        let rp = p.get_ref();
        let value_raw = required(&ctx, &rp.value, p.span(), &entry, "value")?;
        let (value, vdim, sym) = read(value_raw, "value")?;
        let bounds = match (&rp.min, &rp.max) {
            (None, None) => None,
            (Some(_), None) => {
                return Err(ctx.err(
                    Some(p.span()),
                    &entry,
                    "max",
                    "'min' is given but 'max' is missing",
                ))
            }
            (None, Some(_)) => {
                return Err(ctx.err(
                    Some(p.span()),
                    &entry,
                    "min",
                    "'max' is given but 'min' is missing",
                ))
            }
            (Some(lo), Some(hi)) => {
                let (l, ld, _) = read(lo, "min")?;
                let (h, hd, _) = read(hi, "max")?;
                if l >= h {
                    return Err(ctx.err(
                        Some(lo.span()),
                        &entry,
                        "min",
                        format!("min ({l:e}) must be below max ({h:e})"),
                    ));
                }
                if value < l || value > h {
                    return Err(ctx.err(
                        Some(value_raw.span()),
                        &entry,
                        "value",
                        format!(
                            "the value {value:e} lies outside [min, max] = [{l:e}, {h:e}] (SI)"
                        ),
                    ));
                }
                Some(((l, ld), (h, hd)))
            }
        };
        let value_spans = [
            value_raw.span(),
            rp.min.as_ref().map_or(value_raw.span(), |v| v.span()),
            rp.max.as_ref().map_or(value_raw.span(), |v| v.span()),
        ];
        let unit = match (&sym, value_raw.get_ref()) {
            (s, RawNum::Text(t)) if !s.is_empty() => {
                let one = parse_quantity(&format!("1 {s}"))
                    .map(|q| q.value)
                    .unwrap_or(1.0);
                let _ = t;
                DisplayUnit {
                    symbol: s.clone(),
                    scale: one,
                }
            }
            _ => DisplayUnit::default(),
        };
        let scale = parameter_scale(&ctx, rp, p.span(), &entry, bounds.map(|b| (b.0 .0, b.1 .0)))?;
        let per_experiment = match &rp.per_experiment {
            Some(f) if *f.get_ref() && bounds.is_none() => {
                return Err(ctx.err(
                    Some(f.span()),
                    &entry,
                    "per_experiment",
                    "only an identified parameter can differ between experiments: give 'min' and 'max' too",
                ))
            }
            Some(f) => *f.get_ref(),
            None => false,
        };
        ctx.param_index.insert(name.clone(), i);
        ctx.params.push(ParamDraft {
            per_experiment,
            name,
            span,
            value: (value, vdim),
            bounds,
            value_spans,
            unit,
            scale,
            uses: Vec::new(),
        });
    }

    // Bodies.
    let mut body_index: HashMap<String, usize> = HashMap::new();
    let mut bodies = Vec::new();
    for (i, b) in raw.body.iter().enumerate() {
        let (name, span) = name_of(&ctx, &b.get_ref().name, b.span(), "body", i)?;
        let entry = format!("body \"{name}\"");
        if name == "ground" {
            return Err(ctx.err(
                Some(span),
                &entry,
                "name",
                "'ground' is reserved for the fixed frame",
            ));
        }
        check_unique(&ctx, &mut body_index, &name, span, "body", i)?;
        let rb = b.get_ref();
        let mass = ctx.value(
            required(&ctx, &rb.mass, b.span(), &entry, "mass")?,
            Dimension::MASS,
            &entry,
            "mass",
        )?;
        let inertia_raw = required(&ctx, &rb.inertia, b.span(), &entry, "inertia")?;
        if inertia_raw.get_ref().len() != 3 {
            return Err(ctx.err(
                Some(inertia_raw.span()),
                &entry,
                "inertia",
                "needs three principal moments [J1, J2, J3]",
            ));
        }
        let mut inertia = [Value::Fixed(0.0); 3];
        for (j, x) in inertia_raw.get_ref().iter().enumerate() {
            inertia[j] = ctx.value(x, Dimension::INERTIA, &entry, "inertia")?;
        }
        for (v, field, span) in std::iter::once((mass, "mass", rb.mass.as_ref().map(|m| m.span())))
            .chain(
                inertia
                    .iter()
                    .zip(inertia_raw.get_ref())
                    .map(|(v, raw)| (*v, "inertia", Some(raw.span()))),
            )
        {
            if let Value::Fixed(x) = v {
                if !(x > 0.0) {
                    return Err(ctx.err(
                        span,
                        &entry,
                        field,
                        format!("must be positive (found {x})"),
                    ));
                }
            }
        }
        let com = ctx.vec3(
            required(&ctx, &rb.com, b.span(), &entry, "com")?,
            Dimension::LENGTH,
            &entry,
            "com",
        )?;
        let axes = ctx.axes(&rb.axes, &entry)?;
        bodies.push(Body {
            name,
            mass,
            inertia,
            com,
            axes,
        });
    }
    if bodies.is_empty() {
        return Err(ctx.err(None, "", "body", "the model has no [[body]]"));
    }
    let body_ref = |ctx: &Ctx, v: &Spanned<String>, entry: &str, field: &str| -> Result<usize> {
        body_index.get(v.get_ref().trim()).copied().ok_or_else(|| {
            let known: Vec<&str> = bodies.iter().map(|b: &Body| b.name.as_str()).collect();
            ctx.err(
                Some(v.span()),
                entry,
                field,
                format!("unknown body '{}' (bodies: {})", v.get_ref(), list(&known)),
            )
        })
    };

    // Elements.
    let mut element_names = HashMap::new();
    let mut elements = Vec::new();
    for (i, e) in raw.element.iter().enumerate() {
        let (name, span) = name_of(&ctx, &e.get_ref().name, e.span(), "element", i)?;
        let entry = format!("element \"{name}\"");
        check_unique(&ctx, &mut element_names, &name, span, "element", i)?;
        let re = e.get_ref();
        let body_raw = required(&ctx, &re.body, e.span(), &entry, "body")?;
        let body = body_ref(&ctx, body_raw, &entry, "body")?;
        let to_raw = required(&ctx, &re.to, e.span(), &entry, "to")?;
        let to = if to_raw.get_ref().trim() == "ground" {
            Attachment::Ground
        } else {
            let p = body_ref(&ctx, to_raw, &entry, "to")?;
            if p == body {
                return Err(ctx.err(
                    Some(to_raw.span()),
                    &entry,
                    "to",
                    "the element joins a body to itself",
                ));
            }
            Attachment::Body(p)
        };
        let at = ctx.vec3(
            required(&ctx, &re.at, e.span(), &entry, "at")?,
            Dimension::LENGTH,
            &entry,
            "at",
        )?;
        let axes = ctx.axes(&re.axes, &entry)?;
        let mut components = Vec::new();
        for (dof, slot) in re.components().iter().enumerate() {
            let Some(c) = slot else { continue };
            components.push(component(&mut ctx, c, dof, &entry)?);
        }
        if components.is_empty() {
            return Err(ctx.err(
                Some(e.span()),
                &entry,
                "ux",
                "the element has no components (ux, uy, uz, rx, ry, rz)",
            ));
        }
        elements.push(Element {
            name,
            body,
            to,
            at,
            axes,
            components,
        });
    }

    // Excitations.
    let mut excitations = Vec::new();
    let mut excitation_names = HashMap::new();
    for (i, x) in raw.excitation.iter().enumerate() {
        let rx = x.get_ref();
        let (name, span) = match &rx.name {
            Some(n) => (n.get_ref().trim().to_string(), n.span()),
            None => (format!("excitation {}", i + 1), x.span()),
        };
        check_unique(&ctx, &mut excitation_names, &name, span, "excitation", i)?;
        let entry = format!("excitation \"{name}\"");
        let body = body_ref(
            &ctx,
            required(&ctx, &rx.body, x.span(), &entry, "body")?,
            &entry,
            "body",
        )?;
        let reaction = match &rx.reaction {
            None => None,
            Some(r) => {
                let rb = body_ref(&ctx, r, &entry, "reaction")?;
                if rb == body {
                    return Err(ctx.err(
                        Some(r.span()),
                        &entry,
                        "reaction",
                        "the reaction acts on the excited body itself",
                    ));
                }
                Some(rb)
            }
        };
        let at = ctx.vec3(
            required(&ctx, &rx.at, x.span(), &entry, "at")?,
            Dimension::LENGTH,
            &entry,
            "at",
        )?;
        let direction = ctx.direction(
            required(&ctx, &rx.direction, x.span(), &entry, "direction")?,
            &entry,
            "direction",
        )?;
        let sig = required(&ctx, &rx.signal, x.span(), &entry, "signal")?;
        let signal = signal(&mut ctx, sig, &entry, &raw)?;
        excitations.push(Excitation {
            name,
            body,
            reaction,
            at,
            direction,
            signal,
        });
    }

    // Sensors.
    let mut sensors = Vec::new();
    let mut sensor_names = HashMap::new();
    for (i, s) in raw.sensor.iter().enumerate() {
        let (name, span) = name_of(&ctx, &s.get_ref().name, s.span(), "sensor", i)?;
        let entry = format!("sensor \"{name}\"");
        check_unique(&ctx, &mut sensor_names, &name, span.clone(), "sensor", i)?;
        if name == "time" || name.contains(',') || name.contains('"') {
            return Err(ctx.err(
                Some(span),
                &entry,
                "name",
                "a sensor name cannot be 'time' or contain commas or quotes",
            ));
        }
        let rs = s.get_ref();
        let body = body_ref(
            &ctx,
            required(&ctx, &rs.body, s.span(), &entry, "body")?,
            &entry,
            "body",
        )?;
        let at = ctx.vec3(
            required(&ctx, &rs.at, s.span(), &entry, "at")?,
            Dimension::LENGTH,
            &entry,
            "at",
        )?;
        let direction = ctx.direction(
            required(&ctx, &rs.direction, s.span(), &entry, "direction")?,
            &entry,
            "direction",
        )?;
        let q = required(&ctx, &rs.quantity, s.span(), &entry, "quantity")?;
        let kind = match q.get_ref().trim() {
            "displacement" => SensorKind::Displacement,
            "velocity" => SensorKind::Velocity,
            "acceleration" => SensorKind::Acceleration,
            other => {
                return Err(ctx.err(
                    Some(q.span()),
                    &entry,
                    "quantity",
                    format!("unknown quantity '{other}' (displacement, velocity or acceleration)"),
                ))
            }
        };
        let data = match &rs.data {
            Some(d) => {
                d.get_ref()
                    .check()
                    .map_err(|m| ctx.err(Some(d.span()), &entry, "data", m))?;
                d.get_ref().clone()
            }
            None => crate::model::DataSource::for_sensor(&name),
        };
        let reading = match kind {
            SensorKind::Displacement => Dimension::LENGTH,
            SensorKind::Velocity => Dimension::LENGTH.div(Dimension::TIME),
            SensorKind::Acceleration => Dimension::LENGTH.div(Dimension::TIME.powf(2.0)),
        };
        let gain = match &rs.gain {
            Some(g) => ctx.value(g, Dimension::DIMENSIONLESS, &entry, "gain")?,
            None => Value::Fixed(1.0),
        };
        let offset = match &rs.offset {
            Some(o) => ctx.value(o, reading, &entry, "offset")?,
            None => Value::Fixed(0.0),
        };
        sensors.push(Sensor {
            name,
            body,
            at,
            direction,
            kind,
            data,
            gain,
            offset,
        });
    }
    if sensors.is_empty() {
        return Err(ctx.err(
            None,
            "",
            "sensor",
            "the model has no [[sensor]]: nothing to simulate or identify",
        ));
    }

    let sampling = sampling(&ctx, &raw)?;
    let gravity = match &raw.gravity {
        None => None,
        Some(g) => Some(ctx.vec3(
            g,
            Dimension::LENGTH.div(Dimension::TIME.powf(2.0)),
            "gravity",
            "gravity",
        )?),
    };

    let parameters = finish_parameters(&ctx)?;
    let experiments =
        experiments::experiments(&ctx, &raw, &parameters, &excitations, &sensors, &sampling)?;
    Ok(Model {
        experiments,
        bodies,
        elements,
        parameters,
        excitations,
        sensors,
        sampling,
        gravity,
        files: ctx.files.take(),
    })
}

/// A parameter's `scale`: `"log"` or `"linear"`, only with a box; log needs
/// `min > 0`. Without it, [`Scale::default_for`] the box.
fn parameter_scale(
    ctx: &Ctx,
    rp: &crate::io::model_file::raw::RawParameter,
    span: std::ops::Range<usize>,
    entry: &str,
    bounds: Option<(f64, f64)>,
) -> Result<Scale> {
    let Some(raw) = &rp.scale else {
        return Ok(bounds.map_or(Scale::Linear, |(lo, hi)| Scale::default_for(lo, hi)));
    };
    let scale = match raw.get_ref().as_str() {
        "log" => Scale::Log,
        "linear" => Scale::Linear,
        other => {
            return Err(ctx.err(
                Some(raw.span()),
                entry,
                "scale",
                format!("unknown scale '{other}' (log or linear)"),
            ))
        }
    };
    match bounds {
        None => Err(ctx.err(
            Some(span),
            entry,
            "scale",
            "'scale' applies to identified parameters only: give 'min' and 'max' too",
        )),
        Some((lo, _)) if scale == Scale::Log && !(lo > 0.0) => Err(ctx.err(
            Some(raw.span()),
            entry,
            "scale",
            format!("a log scale needs min > 0 (min is {lo:e})"),
        )),
        _ => Ok(scale),
    }
}
