//! The `[[element]]` entries: joints between two bodies or a body and ground.
use super::bodies::Bodies;
use super::component::component;
use super::ctx::*;
use crate::io::model_file::raw::*;
use crate::model::*;
use crate::units::Dimension;
use std::collections::HashMap;
use toml::Spanned;

/// Reads every `[[element]]`, in file order.
pub(super) fn elements(ctx: &mut Ctx, raw: &RawFile, bodies: &Bodies) -> Result<Vec<Element>> {
    let mut names = HashMap::new();
    let mut elements = Vec::new();
    for (i, e) in raw.element.iter().enumerate() {
        elements.push(element(ctx, e, i, &mut names, bodies)?);
    }
    Ok(elements)
}

/// One `[[element]]`: unique name, body, what it joins to, position, axes, components.
fn element(
    ctx: &mut Ctx,
    e: &Spanned<RawElement>,
    i: usize,
    names: &mut HashMap<String, usize>,
    bodies: &Bodies,
) -> Result<Element> {
    let (name, span) = name_of(ctx, &e.get_ref().name, e.span(), "element", i)?;
    let entry = format!("element \"{name}\"");
    check_unique(ctx, names, &name, span, "element", i)?;
    let re = e.get_ref();
    let body_raw = required(ctx, &re.body, e.span(), &entry, "body")?;
    let body = bodies.find(ctx, body_raw, &entry, "body")?;
    let to_raw = required(ctx, &re.to, e.span(), &entry, "to")?;
    let to = attachment(ctx, to_raw, body, bodies, &entry)?;
    let at = ctx.vec3(
        required(ctx, &re.at, e.span(), &entry, "at")?,
        Dimension::LENGTH,
        &entry,
        "at",
    )?;
    let axes = ctx.axes(&re.axes, &entry)?;
    let components = components(ctx, e, &entry)?;
    Ok(Element {
        name,
        body,
        to,
        at,
        axes,
        components,
    })
}

/// What an element's `to` names: `ground`, or a body other than its own.
fn attachment(
    ctx: &Ctx,
    to_raw: &Spanned<String>,
    body: usize,
    bodies: &Bodies,
    entry: &str,
) -> Result<Attachment> {
    if to_raw.get_ref().trim() == "ground" {
        return Ok(Attachment::Ground);
    }
    let p = bodies.find(ctx, to_raw, entry, "to")?;
    if p == body {
        return Err(ctx.err(
            Some(to_raw.span()),
            entry,
            "to",
            "the element joins a body to itself",
        ));
    }
    Ok(Attachment::Body(p))
}

/// An element's components (`ux … rz`, those given); at least one.
fn components(ctx: &mut Ctx, e: &Spanned<RawElement>, entry: &str) -> Result<Vec<Component>> {
    let mut components = Vec::new();
    for (dof, slot) in e.get_ref().components().iter().enumerate() {
        let Some(c) = slot else { continue };
        components.push(component(ctx, c, dof, entry)?);
    }
    if components.is_empty() {
        return Err(ctx.err(
            Some(e.span()),
            entry,
            "ux",
            "the element has no components (ux, uy, uz, rx, ry, rz)",
        ));
    }
    Ok(components)
}
