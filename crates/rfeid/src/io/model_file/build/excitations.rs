//! The `[[excitation]]` entries: forces on a body, each with its signal.
use super::bodies::Bodies;
use super::ctx::*;
use super::signal::signal;
use crate::io::model_file::raw::*;
use crate::model::*;
use crate::units::Dimension;
use std::collections::HashMap;
use toml::Spanned;

/// Reads every `[[excitation]]`, in file order.
pub(super) fn excitations(
    ctx: &mut Ctx,
    raw: &RawFile,
    bodies: &Bodies,
) -> Result<Vec<Excitation>> {
    let mut excitations = Vec::new();
    let mut names = HashMap::new();
    for (i, x) in raw.excitation.iter().enumerate() {
        excitations.push(excitation(ctx, raw, x, i, &mut names, bodies)?);
    }
    Ok(excitations)
}

/// One `[[excitation]]`: name (or a number), body, reaction, point, direction, signal.
fn excitation(
    ctx: &mut Ctx,
    raw: &RawFile,
    x: &Spanned<RawExcitation>,
    i: usize,
    names: &mut HashMap<String, usize>,
    bodies: &Bodies,
) -> Result<Excitation> {
    let rx = x.get_ref();
    let (name, span) = match &rx.name {
        Some(n) => (n.get_ref().trim().to_string(), n.span()),
        None => (format!("excitation {}", i + 1), x.span()),
    };
    check_unique(ctx, names, &name, span, "excitation", i)?;
    let entry = format!("excitation \"{name}\"");
    let body = bodies.find(
        ctx,
        required(ctx, &rx.body, x.span(), &entry, "body")?,
        &entry,
        "body",
    )?;
    let reaction = reaction(ctx, rx, body, bodies, &entry)?;
    let at = ctx.vec3(
        required(ctx, &rx.at, x.span(), &entry, "at")?,
        Dimension::LENGTH,
        &entry,
        "at",
    )?;
    let direction = ctx.direction(
        required(ctx, &rx.direction, x.span(), &entry, "direction")?,
        &entry,
        "direction",
    )?;
    let sig = required(ctx, &rx.signal, x.span(), &entry, "signal")?;
    let signal = signal(ctx, sig, &entry, raw)?;
    Ok(Excitation {
        name,
        body,
        reaction,
        at,
        direction,
        signal,
    })
}

/// The body an excitation's reaction acts on, if any: not the excited body.
fn reaction(
    ctx: &Ctx,
    rx: &RawExcitation,
    body: usize,
    bodies: &Bodies,
    entry: &str,
) -> Result<Option<usize>> {
    let Some(r) = &rx.reaction else {
        return Ok(None);
    };
    let rb = bodies.find(ctx, r, entry, "reaction")?;
    if rb == body {
        return Err(ctx.err(
            Some(r.span()),
            entry,
            "reaction",
            "the reaction acts on the excited body itself",
        ));
    }
    Ok(Some(rb))
}
