//! The `[[sensor]]` entries: what is measured, where, and in which file.
use super::bodies::Bodies;
use super::ctx::*;
use crate::io::model_file::raw::*;
use crate::io::model_file::Purpose;
use crate::model::*;
use crate::units::Dimension;
use std::collections::HashMap;
use toml::Spanned;

/// Reads every `[[sensor]]`: the placed ones and the candidates
/// (`candidate = true`, SPEC §6). Names are unique over both. A model
/// needs a sensor; read for a test's data ([`Purpose::Measure`]) it needs a
/// placed one, while a design before the first test
/// ([`Purpose::Design`]) may have candidates only.
pub(super) fn sensors(
    ctx: &mut Ctx,
    raw: &RawFile,
    bodies: &Bodies,
    purpose: Purpose,
) -> Result<(Vec<Sensor>, Vec<Sensor>)> {
    let (mut sensors, mut candidates) = (Vec::new(), Vec::new());
    let mut names = HashMap::new();
    for (i, s) in raw.sensor.iter().enumerate() {
        let read = sensor(ctx, s, i, &mut names, bodies)?;
        if s.get_ref().candidate.as_ref().is_some_and(|c| *c.get_ref()) {
            // Nothing measures a candidate, so nothing could identify a
            // parameter in its gain or offset.
            let raw = s.get_ref();
            for (field, v, at) in [
                ("gain", &read.gain, &raw.gain),
                ("offset", &read.offset, &raw.offset),
            ] {
                if matches!(v, Value::Param(_)) {
                    return Err(ctx.err(
                        at.as_ref().map(|r| r.span()),
                        &format!("sensor \"{}\"", read.name),
                        field,
                        "a candidate's gain and offset must be numbers: a candidate is not measured, so nothing identifies a parameter there",
                    ));
                }
            }
            candidates.push(read);
        } else {
            sensors.push(read);
        }
    }
    let what = match (sensors.is_empty(), candidates.is_empty(), purpose) {
        (false, _, _) | (true, false, Purpose::Design) => return Ok((sensors, candidates)),
        (true, true, _) => "the model has no [[sensor]]: nothing to simulate or identify",
        (true, false, Purpose::Measure) => {
            "every [[sensor]] is a candidate: place at least one (a sensor without \
             `candidate = true`), as the test has one at least (only a design that \
             chooses sensors reads a model with candidates alone)"
        }
    };
    Err(ctx.err(None, "", "sensor", what))
}

/// One `[[sensor]]`: name, body, point, direction, quantity, data, gain, offset.
fn sensor(
    ctx: &mut Ctx,
    s: &Spanned<RawSensor>,
    i: usize,
    names: &mut HashMap<String, usize>,
    bodies: &Bodies,
) -> Result<Sensor> {
    let name = sensor_name(ctx, s, i, names)?;
    let entry = format!("sensor \"{name}\"");
    let rs = s.get_ref();
    let body = bodies.find(
        ctx,
        required(ctx, &rs.body, s.span(), &entry, "body")?,
        &entry,
        "body",
    )?;
    let at = ctx.vec3(
        required(ctx, &rs.at, s.span(), &entry, "at")?,
        Dimension::LENGTH,
        &entry,
        "at",
    )?;
    let direction = ctx.direction(
        required(ctx, &rs.direction, s.span(), &entry, "direction")?,
        &entry,
        "direction",
    )?;
    let kind = sensor_kind(
        ctx,
        required(ctx, &rs.quantity, s.span(), &entry, "quantity")?,
        &entry,
    )?;
    let data = sensor_data(ctx, rs, &name, &entry)?;
    let gain = match &rs.gain {
        Some(g) => ctx.value(g, Dimension::DIMENSIONLESS, &entry, "gain")?,
        None => Value::Fixed(1.0),
    };
    let offset = match &rs.offset {
        Some(o) => ctx.value(o, reading_dimension(kind), &entry, "offset")?,
        None => Value::Fixed(0.0),
    };
    let noise = match &rs.noise {
        Some(n) => {
            let v = ctx.number(n, reading_dimension(kind), &entry, "noise")?;
            // σ² and 1/σ² are normal numbers: σ from about 1e-154 to 1e154.
            if !(v > 0.0 && v.powi(2).is_normal() && v.powi(-2).is_normal()) {
                return Err(ctx.err(
                    Some(n.span()),
                    &entry,
                    "noise",
                    "the noise's standard deviation must be positive, with σ² and 1/σ² finite and not below 1e-308 (σ from about 1e-154 to 1e154)",
                ));
            }
            Some(v)
        }
        None => None,
    };
    Ok(Sensor {
        name,
        body,
        at,
        direction,
        kind,
        data,
        gain,
        offset,
        noise,
    })
}

/// A sensor's name: unique, not `time`, without commas or quotes (it heads a column).
fn sensor_name(
    ctx: &Ctx,
    s: &Spanned<RawSensor>,
    i: usize,
    names: &mut HashMap<String, usize>,
) -> Result<String> {
    let (name, span) = name_of(ctx, &s.get_ref().name, s.span(), "sensor", i)?;
    let entry = format!("sensor \"{name}\"");
    check_unique(ctx, names, &name, span.clone(), "sensor", i)?;
    if name == "time" || name.contains(',') || name.contains('"') {
        return Err(ctx.err(
            Some(span),
            &entry,
            "name",
            "a sensor name cannot be 'time' or contain commas or quotes",
        ));
    }
    Ok(name)
}

/// A sensor's `quantity`: displacement, velocity or acceleration.
fn sensor_kind(ctx: &Ctx, q: &Spanned<String>, entry: &str) -> Result<SensorKind> {
    match q.get_ref().trim() {
        "displacement" => Ok(SensorKind::Displacement),
        "velocity" => Ok(SensorKind::Velocity),
        "acceleration" => Ok(SensorKind::Acceleration),
        other => Err(ctx.err(
            Some(q.span()),
            entry,
            "quantity",
            format!("unknown quantity '{other}' (displacement, velocity or acceleration)"),
        )),
    }
}

/// Where a sensor's measurements are: its `data`, checked, or its own column.
fn sensor_data(ctx: &Ctx, rs: &RawSensor, name: &str, entry: &str) -> Result<DataSource> {
    match &rs.data {
        Some(d) => {
            d.get_ref()
                .check()
                .map_err(|m| ctx.err(Some(d.span()), entry, "data", m))?;
            Ok(d.get_ref().clone())
        }
        None => Ok(DataSource::for_sensor(name)),
    }
}

/// The dimension of what a sensor of this kind reads (and of its offset).
fn reading_dimension(kind: SensorKind) -> Dimension {
    match kind {
        SensorKind::Displacement => Dimension::LENGTH,
        SensorKind::Velocity => Dimension::LENGTH.div(Dimension::TIME),
        SensorKind::Acceleration => Dimension::LENGTH.div(Dimension::TIME.powf(2.0)),
    }
}
