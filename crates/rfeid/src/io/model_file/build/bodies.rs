//! The `[[body]]` entries, and looking bodies up by name.
use super::ctx::*;
use super::rules::ruled;
use crate::io::model_file::raw::*;
use crate::model::*;
use crate::units::Dimension;
use std::collections::HashMap;
use toml::Spanned;

/// The bodies read, in file order, with their indices by name.
pub(super) struct Bodies {
    pub(super) list: Vec<Body>,
    index: HashMap<String, usize>,
}

impl Bodies {
    /// The index of the body a field names, or an error that lists the bodies.
    pub(super) fn find(
        &self,
        ctx: &Ctx,
        v: &Spanned<String>,
        entry: &str,
        field: &str,
    ) -> Result<usize> {
        self.index.get(v.get_ref().trim()).copied().ok_or_else(|| {
            let known: Vec<&str> = self.list.iter().map(|b| b.name.as_str()).collect();
            ctx.err(
                Some(v.span()),
                entry,
                field,
                format!("unknown body '{}' (bodies: {})", v.get_ref(), list(&known)),
            )
        })
    }
}

/// Reads every `[[body]]`; a model needs at least one.
pub(super) fn bodies(ctx: &mut Ctx, raw: &RawFile) -> Result<Bodies> {
    let mut index = HashMap::new();
    let mut list = Vec::new();
    for (i, b) in raw.body.iter().enumerate() {
        list.push(body(ctx, b, i, &mut index)?);
    }
    if list.is_empty() {
        return Err(ctx.err(None, "", "body", "the model has no [[body]]"));
    }
    Ok(Bodies { list, index })
}

/// One `[[body]]`: unique name (not `ground`), mass, inertia, centre of mass, axes.
fn body(
    ctx: &mut Ctx,
    b: &Spanned<RawBody>,
    i: usize,
    index: &mut HashMap<String, usize>,
) -> Result<Body> {
    let (name, span) = name_of(ctx, &b.get_ref().name, b.span(), "body", i)?;
    let entry = format!("body \"{name}\"");
    if name == "ground" {
        return Err(ctx.err(
            Some(span),
            &entry,
            "name",
            "'ground' is reserved for the fixed frame",
        ));
    }
    check_unique(ctx, index, &name, span, "body", i)?;
    let rb = b.get_ref();
    let mass = ruled(
        ctx,
        required(ctx, &rb.mass, b.span(), &entry, "mass")?,
        Dimension::MASS,
        &entry,
        "mass",
    )?;
    let inertia_raw = required(ctx, &rb.inertia, b.span(), &entry, "inertia")?;
    let inertia = inertia(ctx, inertia_raw, &entry)?;
    let com = ctx.vec3(
        required(ctx, &rb.com, b.span(), &entry, "com")?,
        Dimension::LENGTH,
        &entry,
        "com",
    )?;
    let axes = ctx.axes(&rb.axes, &entry)?;
    Ok(Body {
        name,
        mass,
        inertia,
        com,
        axes,
    })
}

/// A body's three principal moments of inertia.
fn inertia(ctx: &mut Ctx, inertia_raw: &SVec, entry: &str) -> Result<[Value; 3]> {
    if inertia_raw.get_ref().len() != 3 {
        return Err(ctx.err(
            Some(inertia_raw.span()),
            entry,
            "inertia",
            "needs three principal moments [J1, J2, J3]",
        ));
    }
    let mut inertia = [Value::Fixed(0.0); 3];
    for (j, x) in inertia_raw.get_ref().iter().enumerate() {
        inertia[j] = ruled(ctx, x, Dimension::INERTIA, entry, "inertia")?;
    }
    Ok(inertia)
}
