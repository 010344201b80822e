//! One component (ux … rz) of an element: its law and damping. The laws
//! read their own keys ([`ReadLaw`]); this file gives them the component's
//! table ([`KeyReader`]) and refuses a key no law of the component takes.
use super::ctx::*;
use super::rules::ruled;
use crate::io::model_file::error::ModelFileError;
use crate::io::model_file::raw::*;
use crate::model::*;
use crate::simulation::laws::{readers, KeyReader, LawReader};
use crate::units::Dimension;
use std::ops::Range;
use toml::Spanned;

/// A component's table, its entry name and whether it is a rotation.
struct Comp<'a> {
    c: &'a Spanned<RawComponent>,
    entry: String,
    rotational: bool,
}

impl Comp<'_> {
    /// The value of `key`, if given.
    fn get(&self, key: &str) -> Option<&SNum> {
        self.c.get_ref().keys.get(key)
    }
}

/// One component of an element: its law and damping `c`.
pub(super) fn component(
    ctx: &mut Ctx,
    c: &Spanned<RawComponent>,
    dof: usize,
    element: &str,
) -> Result<Component> {
    let cname = COMPONENT_NAMES[dof];
    let comp = Comp {
        c,
        entry: format!("{element}, component {cname}"),
        rotational: dof >= 3,
    };
    let (law, own) = law(ctx, &comp)?;
    // A law that takes `c` itself (a contact's damper acts only while it
    // is closed) leaves the component none of its own.
    let damping = match own.contains(&"c") {
        true => Value::Fixed(0.0),
        false => damping(ctx, &comp)?,
    };
    Ok(Component { dof, law, damping })
}

/// The keys every component takes besides its law's.
const COMMON_KEYS: [&str; 2] = ["law", "c"];

/// The law a component names (trimmed, with the span of its text), or the
/// one its keys imply: the last law of [`readers`] that a given key
/// implies, `"none"` if none.
fn law_name(ctx: &Ctx, comp: &Comp, laws: &[LawReader<Box<ModelFileError>>]) -> Result<String> {
    match comp.get("law") {
        Some(l) => match l.get_ref() {
            RawNum::Text(t) => Ok(t.trim().to_string()),
            _ => Err(ctx.err(
                Some(l.span()),
                &comp.entry,
                "law",
                format!("the law is a name in quotes ({})", law_list(laws)),
            )),
        },
        None => Ok(laws
            .iter()
            .rev()
            .find(|l| l.implied_by.iter().any(|k| comp.get(k).is_some()))
            .map_or("none", |l| l.name)
            .to_string()),
    }
}

/// `linear, power, friction, bouc-wen or contact`.
fn law_list<E>(laws: &[LawReader<E>]) -> String {
    let names: Vec<&str> = laws.iter().map(|l| l.name).collect();
    match names.split_last() {
        Some((last, rest)) if !rest.is_empty() => format!("{} or {last}", rest.join(", ")),
        _ => names.join(""),
    }
}

/// A component's spring law, read by the law it names from its keys, and
/// the keys that law takes.
fn law(ctx: &mut Ctx, comp: &Comp) -> Result<(Law, &'static [&'static str])> {
    let laws = readers::<Box<ModelFileError>>();
    let name = law_name(ctx, comp, &laws)?;
    // Named first: a misspelt law is not a home for misplaced keys.
    let reader = laws.iter().find(|l| l.name == name);
    if reader.is_none() && name != "none" {
        let span = comp.get("law").map(|l| l.span());
        let message = format!(
            "unknown law '{name}' ({}){}",
            law_list(&laws),
            law_hint(&name, &laws)
        );
        return Err(ctx.err(span, &comp.entry, "law", message));
    }
    let own = reader.map_or(&[][..], |r| r.keys);
    for (key, v) in &comp.c.get_ref().keys {
        let key = key.get_ref().as_str();
        if own.contains(&key) || COMMON_KEYS.contains(&key) {
            continue;
        }
        return Err(stray_key(ctx, comp, key, v, &name, own, &laws));
    }
    match reader {
        Some(r) => Ok(((r.read)(&mut ComponentKeys { ctx, comp })?, r.keys)),
        None => Ok((damper_only(ctx, comp)?, &[])),
    }
}

/// The refusal of a `key` that the law `name` (whose keys are `own`) does
/// not take: another law's key, or one no law takes.
fn stray_key(
    ctx: &Ctx,
    comp: &Comp,
    key: &str,
    v: &SNum,
    name: &str,
    own: &[&str],
    laws: &[LawReader<Box<ModelFileError>>],
) -> Box<ModelFileError> {
    if laws.iter().any(|l| l.keys.contains(&key)) {
        let mut takes: Vec<&str> = own.to_vec();
        // `c`, unless the law takes it among its own (a contact).
        takes.extend(COMMON_KEYS[1..].iter().filter(|k| !own.contains(k)));
        let message = format!(
            "'{key}' does not belong to the {name} law (it takes {})",
            takes.join(", ")
        );
        return ctx.err(Some(v.span()), &comp.entry, key, message);
    }
    let mut all: Vec<&str> = COMMON_KEYS.to_vec();
    for k in laws.iter().flat_map(|l| l.keys) {
        if !all.contains(k) {
            all.push(k);
        }
    }
    let expected: Vec<String> = all.iter().map(|k| format!("`{k}`")).collect();
    let message = format!(
        "unknown field `{key}`, expected one of {}",
        expected.join(", ")
    );
    let span = comp
        .c
        .get_ref()
        .keys
        .get_key_value(key)
        .map(|(k, _)| k.span());
    ctx.err(span, &comp.entry, key, message)
}

/// A component's table as its law reads it.
struct ComponentKeys<'a, 'c> {
    ctx: &'a mut Ctx,
    comp: &'a Comp<'c>,
}

impl ComponentKeys<'_, '_> {
    /// The component's span: where a missing key is reported.
    fn span(&self) -> Range<usize> {
        self.comp.c.span()
    }
}

impl KeyReader for ComponentKeys<'_, '_> {
    type Error = Box<ModelFileError>;

    fn rotational(&self) -> bool {
        self.comp.rotational
    }

    fn given(&self, key: &str) -> bool {
        self.comp.get(key).is_some()
    }

    fn value(&mut self, key: &str, dim: Dimension) -> Result<Option<Value>> {
        let Some(raw) = self.comp.get(key) else {
            return Ok(None);
        };
        ruled(self.ctx, raw, dim, &self.comp.entry, key).map(Some)
    }

    fn required(&mut self, key: &str, dim: Dimension) -> Result<Value> {
        let (entry, given) = (&self.comp.entry, self.comp.get(key));
        let raw = required(self.ctx, &given, self.span(), entry, key)?;
        ruled(self.ctx, raw, dim, entry, key)
    }

    fn number(&mut self, key: &str, dim: Dimension) -> Result<Option<f64>> {
        let Some(raw) = self.comp.get(key) else {
            return Ok(None);
        };
        self.ctx.number(raw, dim, &self.comp.entry, key).map(Some)
    }

    fn nominal(&self, v: Value) -> f64 {
        nominal(self.ctx, v)
    }

    fn parameter_name(&self, index: usize) -> String {
        self.ctx.params[index].name.clone()
    }

    fn has_unit(&self, key: &str) -> bool {
        let Some(raw) = self.comp.get(key) else {
            return false;
        };
        match raw.get_ref() {
            RawNum::Num(_) | RawNum::Bool(_) => false,
            RawNum::Text(t) if looks_numeric(t) => !bare(t),
            RawNum::Text(t) => self.ctx.param_index.get(t.trim()).is_some_and(|&i| {
                let p = &self.ctx.params[i];
                let box_units = p
                    .bounds
                    .is_some_and(|(lo, hi)| lo.1.is_some() || hi.1.is_some());
                p.value.1.is_some() || box_units
            }),
        }
    }

    fn refuse(&self, key: &str, message: String) -> Self::Error {
        let span = self.comp.get(key).map_or_else(|| self.span(), |v| v.span());
        self.ctx.err(Some(span), &self.comp.entry, key, message)
    }
}

/// `"; did you mean 'friction'?"` for a law's name written with another
/// case, without its hyphen, or within two edits of it; empty otherwise.
fn law_hint<E>(written: &str, laws: &[LawReader<E>]) -> String {
    let plain = |s: &str| -> Vec<char> {
        s.to_lowercase()
            .chars()
            .filter(|c| c.is_alphanumeric())
            .collect()
    };
    let w = plain(written);
    laws.iter()
        .map(|law| (edit_distance(&w, &plain(law.name)), law.name))
        .filter(|(d, _)| *d <= 2)
        .min_by_key(|(d, _)| *d)
        .map(|(_, law)| format!("; did you mean '{law}'?"))
        .unwrap_or_default()
}

/// The Levenshtein distance between two words.
fn edit_distance(a: &[char], b: &[char]) -> usize {
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.iter().enumerate() {
        let mut diagonal = row[0];
        row[0] = i + 1;
        for (j, cb) in b.iter().enumerate() {
            let substituted = diagonal + usize::from(ca != cb);
            diagonal = row[j + 1];
            row[j + 1] = substituted.min(row[j] + 1).min(diagonal + 1);
        }
    }
    row[b.len()]
}

/// No spring: a damper `c` alone (a direction free of springs).
fn damper_only(ctx: &mut Ctx, comp: &Comp) -> Result<Law> {
    if comp.get("c").is_none() {
        return Err(ctx.err(
            Some(comp.c.span()),
            &comp.entry,
            "law",
            "the component has neither a spring (k, or a and m) nor damping (c)",
        ));
    }
    Ok(Law::None)
}

/// A value's nominal number: its own, or its parameter's.
fn nominal(ctx: &Ctx, v: Value) -> f64 {
    match v {
        Value::Fixed(x) => x,
        Value::Param(i) => ctx.params[i].value.0,
    }
}

/// A component's damping `c`: non-negative, 0 when absent.
fn damping(ctx: &mut Ctx, comp: &Comp) -> Result<Value> {
    let Some(v) = comp.get("c") else {
        return Ok(Value::Fixed(0.0));
    };
    let c_dim = if comp.rotational {
        Dimension::ROTATIONAL_DAMPING
    } else {
        Dimension::DAMPING
    };
    ruled(ctx, v, c_dim, &comp.entry, "c")
}

#[cfg(test)]
mod tests {
    use super::law_hint;
    use crate::simulation::laws::readers;

    #[test]
    fn a_law_written_nearly_right_gets_a_hint() {
        for (written, law) in [
            ("fricton", "friction"),
            ("Friction", "friction"),
            ("boucwen", "bouc-wen"),
            ("Bouc_Wen", "bouc-wen"),
            ("linaer", "linear"),
            ("POWER", "power"),
        ] {
            assert_eq!(
                law_hint(written, &readers::<()>()),
                format!("; did you mean '{law}'?")
            );
        }
        for far in ["quadratic", "coulomb", "nonsense", ""] {
            assert_eq!(law_hint(far, &readers::<()>()), "", "{far}");
        }
    }
}
