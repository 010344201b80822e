//! Excitation signals: sine, multisine, chirp, impulse, constant (tables in
//! [`super::table`]).
use super::ctx::*;
use super::simulation::simulation_duration;
use super::table::table;
use crate::io::model_file::raw::*;
use crate::model::*;
use crate::units::Dimension;
use std::ops::Range;
use toml::Spanned;

/// A signal's table and the entry it belongs to, for reading its fields.
pub(super) struct Sig<'a> {
    pub(super) sig: &'a Spanned<RawSignal>,
    pub(super) entry: &'a str,
}

impl Sig<'_> {
    /// The signal's fields.
    pub(super) fn raw(&self) -> &RawSignal {
        self.sig.get_ref()
    }

    /// The number in `signal.{field}`, which must be given, of dimension `dim`.
    fn required_number(
        &self,
        ctx: &Ctx,
        v: &Option<SNum>,
        field: &str,
        dim: Dimension,
    ) -> Result<f64> {
        let (sig, entry) = (self.sig, self.entry);
        ctx.number(
            required(ctx, v, sig.span(), entry, &format!("signal.{field}"))?,
            dim,
            entry,
            &format!("signal.{field}"),
        )
    }

    /// The signal's `amplitude` (a force or a parameter), or `default` when absent.
    pub(super) fn amplitude(&self, ctx: &mut Ctx, default: Option<f64>) -> Result<Value> {
        match (&self.raw().amplitude, default) {
            (Some(v), _) => ctx.value(v, Dimension::FORCE, self.entry, "signal.amplitude"),
            (None, Some(d)) => Ok(Value::Fixed(d)),
            (None, None) => Err(ctx.err(
                Some(self.sig.span()),
                self.entry,
                "signal.amplitude",
                "'amplitude' is missing",
            )),
        }
    }

    /// `x` if it is positive; otherwise an error on `signal.{field}`.
    fn positive(&self, ctx: &Ctx, x: f64, field: &str) -> Result<f64> {
        if x > 0.0 {
            Ok(x)
        } else {
            Err(ctx.err(
                Some(self.sig.span()),
                self.entry,
                &format!("signal.{field}"),
                format!("must be positive (found {x})"),
            ))
        }
    }
}

/// An excitation's `signal`: its type, only that type's keys, and its terms.
pub(super) fn signal(
    ctx: &mut Ctx,
    sig: &Spanned<RawSignal>,
    entry: &str,
    raw: &RawFile,
) -> Result<Signal> {
    let kind = signal_kind(ctx, sig, entry)?;
    check_keys(ctx, sig.get_ref(), kind, entry)?;
    let s = Sig { sig, entry };
    let terms = match kind {
        "sine" => vec![sine(ctx, &s)?],
        "multisine" => multisine(ctx, &s)?,
        "chirp" => vec![chirp(ctx, &s, raw)?],
        "impulse" => vec![impulse(ctx, &s)?],
        "constant" => vec![Term {
            amplitude: s.amplitude(ctx, None)?,
            shape: Shape::Constant,
        }],
        _ => vec![table(ctx, &s, raw)?],
    };
    Ok(Signal { kind, terms })
}

/// The signal's `type`: sine, multisine, chirp, impulse, constant or table.
fn signal_kind(ctx: &Ctx, sig: &Spanned<RawSignal>, entry: &str) -> Result<&'static str> {
    let kind_raw = required(ctx, &sig.get_ref().kind, sig.span(), entry, "signal.type")?;
    match kind_raw.get_ref().trim() {
        "sine" => Ok("sine"),
        "multisine" => Ok("multisine"),
        "chirp" => Ok("chirp"),
        "impulse" => Ok("impulse"),
        "constant" => Ok("constant"),
        "table" => Ok("table"),
        other => Err(ctx.err(
            Some(kind_raw.span()),
            entry,
            "signal.type",
            format!(
                "unknown signal type '{other}' (sine, multisine, chirp, impulse, constant or table)"
            ),
        )),
    }
}

/// Keys that do not belong to this type are errors, like unknown keys.
fn check_keys(ctx: &Ctx, rs: &RawSignal, kind: &str, entry: &str) -> Result<()> {
    let allowed = allowed_keys(kind);
    for (key, span) in present_keys(rs) {
        if let Some(span) = span {
            if !allowed.contains(&key) {
                return Err(ctx.err(
                    Some(span),
                    entry,
                    &format!("signal.{key}"),
                    format!(
                        "'{key}' does not apply to a {kind} signal (it takes {})",
                        allowed.join(", ")
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// The keys a signal of this type takes.
fn allowed_keys(kind: &str) -> &'static [&'static str] {
    match kind {
        "sine" => &["amplitude", "frequency", "phase"],
        "multisine" => &["components"],
        "chirp" => &["amplitude", "f0", "f1", "duration"],
        "impulse" => &["amplitude", "t0", "width"],
        "constant" => &["amplitude"],
        _ => &["amplitude", "file", "column", "variable", "interpolation"],
    }
}

/// Every key a signal can have, with its span when it is given.
fn present_keys(rs: &RawSignal) -> [(&'static str, Option<Range<usize>>); 13] {
    [
        ("amplitude", rs.amplitude.as_ref().map(|v| v.span())),
        ("frequency", rs.frequency.as_ref().map(|v| v.span())),
        ("phase", rs.phase.as_ref().map(|v| v.span())),
        ("components", rs.components.as_ref().map(|v| v.span())),
        ("f0", rs.f0.as_ref().map(|v| v.span())),
        ("f1", rs.f1.as_ref().map(|v| v.span())),
        ("duration", rs.duration.as_ref().map(|v| v.span())),
        ("t0", rs.t0.as_ref().map(|v| v.span())),
        ("width", rs.width.as_ref().map(|v| v.span())),
        ("file", rs.file.as_ref().map(|v| v.span())),
        ("column", rs.column.as_ref().map(|v| v.span())),
        ("variable", rs.variable.as_ref().map(|v| v.span())),
        ("interpolation", rs.interpolation.as_ref().map(|v| v.span())),
    ]
}

/// A sine: frequency, optional phase (0), amplitude.
fn sine(ctx: &mut Ctx, s: &Sig) -> Result<Term> {
    let rs = s.raw();
    let frequency = s.required_number(ctx, &rs.frequency, "frequency", Dimension::FREQUENCY)?;
    let phase = rs
        .phase
        .as_ref()
        .map(|p| ctx.number(p, Dimension::DIMENSIONLESS, s.entry, "signal.phase"))
        .transpose()?
        .unwrap_or(0.0);
    Ok(Term {
        amplitude: s.amplitude(ctx, None)?,
        shape: Shape::Sine { frequency, phase },
    })
}

/// A multisine: one sine term per component; at least one.
fn multisine(ctx: &mut Ctx, s: &Sig) -> Result<Vec<Term>> {
    let comps = required(
        ctx,
        &s.raw().components,
        s.sig.span(),
        s.entry,
        "signal.components",
    )?;
    if comps.get_ref().is_empty() {
        return Err(ctx.err(
            Some(comps.span()),
            s.entry,
            "signal.components",
            "a multisine needs at least one component",
        ));
    }
    let mut terms = Vec::new();
    for tone in comps.get_ref() {
        terms.push(multisine_tone(ctx, tone, s.entry)?);
    }
    Ok(terms)
}

/// One component of a multisine: frequency, optional phase (0), amplitude.
fn multisine_tone(ctx: &mut Ctx, tone: &Spanned<RawTone>, entry: &str) -> Result<Term> {
    let t = tone.get_ref();
    let frequency = ctx.number(
        required(
            ctx,
            &t.frequency,
            tone.span(),
            entry,
            "signal.components.frequency",
        )?,
        Dimension::FREQUENCY,
        entry,
        "signal.components.frequency",
    )?;
    let phase = t
        .phase
        .as_ref()
        .map(|p| {
            ctx.number(
                p,
                Dimension::DIMENSIONLESS,
                entry,
                "signal.components.phase",
            )
        })
        .transpose()?
        .unwrap_or(0.0);
    let amplitude = ctx.value(
        required(
            ctx,
            &t.amplitude,
            tone.span(),
            entry,
            "signal.components.amplitude",
        )?,
        Dimension::FORCE,
        entry,
        "signal.components.amplitude",
    )?;
    Ok(Term {
        amplitude,
        shape: Shape::Sine { frequency, phase },
    })
}

/// A chirp: f0, f1, duration (the simulation's when absent), amplitude.
fn chirp(ctx: &mut Ctx, s: &Sig, raw: &RawFile) -> Result<Term> {
    let rs = s.raw();
    let f0 = s.required_number(ctx, &rs.f0, "f0", Dimension::FREQUENCY)?;
    let f1 = s.required_number(ctx, &rs.f1, "f1", Dimension::FREQUENCY)?;
    let duration = match &rs.duration {
        Some(d) => s.positive(
            ctx,
            ctx.number(d, Dimension::TIME, s.entry, "signal.duration")?,
            "duration",
        )?,
        None => simulation_duration(ctx, raw)?,
    };
    Ok(Term {
        amplitude: s.amplitude(ctx, None)?,
        shape: Shape::Chirp { f0, f1, duration },
    })
}

/// An impulse: t0, positive width, amplitude.
fn impulse(ctx: &mut Ctx, s: &Sig) -> Result<Term> {
    let rs = s.raw();
    let t0 = s.required_number(ctx, &rs.t0, "t0", Dimension::TIME)?;
    let width = s.positive(
        ctx,
        s.required_number(ctx, &rs.width, "width", Dimension::TIME)?,
        "width",
    )?;
    Ok(Term {
        amplitude: s.amplitude(ctx, None)?,
        shape: Shape::Impulse { t0, width },
    })
}
