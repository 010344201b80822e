//! The builder's context (file, text, parameters seen so far) and small helpers.
use crate::io::model_file::error::ModelFileError;
use crate::io::model_file::raw::*;
use crate::model::geometry::{check_axes, AxesDefect};
use crate::model::*;
use crate::units::{parse_quantity, Dimension};
use nalgebra::{Matrix3, Vector3};
use std::collections::HashMap;
use std::ops::Range;
use std::path::PathBuf;
use std::sync::Arc;
use toml::Spanned;

/// Errors are boxed inside the builder, where they pass through many frames.
pub(super) type Result<T> = std::result::Result<T, Box<ModelFileError>>;

/// A parameter's value or bound with the dimension of its unit, if it had one.
pub(super) type Reading = (f64, Option<Dimension>);

/// Tolerance on `RᵀR − I` for axes.
pub(super) const AXES_TOL: f64 = 1e-6;

/// A parameter as read, before its dimension is known from its uses.
pub(super) struct ParamDraft {
    pub(super) name: String,
    pub(super) span: Range<usize>,
    pub(super) value: (f64, Option<Dimension>),
    pub(super) bounds: Option<(Reading, Reading)>,
    /// Spans of the value, min and max texts (min and max: the value's when absent).
    pub(super) value_spans: [Range<usize>; 3],
    pub(super) unit: DisplayUnit,
    pub(super) scale: Scale,
    pub(super) per_experiment: bool,
    pub(super) uses: Vec<(Dimension, Range<usize>, String, String)>,
}

pub(super) struct Ctx {
    pub(super) path: PathBuf,
    pub(super) dir: PathBuf,
    pub(super) text: Arc<str>,
    pub(super) params: Vec<ParamDraft>,
    pub(super) param_index: HashMap<String, usize>,
    /// Files read besides the model file (signal tables).
    pub(super) files: std::cell::RefCell<Vec<PathBuf>>,
    /// Notes for the user (a table's time axis assumed), each naming its file.
    pub(super) notes: std::cell::RefCell<Vec<String>>,
}

impl Ctx {
    pub(super) fn err(
        &self,
        span: Option<Range<usize>>,
        entry: &str,
        field: &str,
        message: impl Into<String>,
    ) -> Box<ModelFileError> {
        Box::new(ModelFileError {
            path: self.path.clone(),
            source_text: Some(self.text.clone()),
            span,
            entry: entry.into(),
            field: field.into(),
            message: message.into(),
        })
    }

    /// A number with a unit of dimension `dim`; no parameter allowed.
    pub(super) fn number(&self, v: &SNum, dim: Dimension, entry: &str, field: &str) -> Result<f64> {
        match v.get_ref() {
            RawNum::Bool(b) => Err(self.boolean(*b, v, entry, field, false)),
            RawNum::Num(x) => self.finite(*x, v.span(), entry, field),
            RawNum::Text(t) => {
                if !looks_numeric(t) {
                    return Err(self.err(
                        Some(v.span()),
                        entry,
                        field,
                        format!("'{t}' is not a number (parameters are not allowed here)"),
                    ));
                }
                self.quantity(t, dim, v.span(), entry, field)
            }
        }
    }

    /// The error of a boolean written where a number belongs, saying what
    /// the field takes: a number or a quantity, and a parameter's name where
    /// `parameters` are allowed (the refusal of a parameter's name where they
    /// are not says "parameters are not allowed here" too).
    pub(super) fn boolean(
        &self,
        b: bool,
        v: &SNum,
        entry: &str,
        field: &str,
        parameters: bool,
    ) -> Box<ModelFileError> {
        let takes = match parameters {
            true => "a number, a string holding a quantity with a unit (\"15 daN/um\") or a parameter's name",
            false => "a number or a string holding a quantity with a unit (\"15 daN/um\"); parameters are not allowed here",
        };
        self.err(
            Some(v.span()),
            entry,
            field,
            format!("a boolean ({b}) is not allowed here: expected {takes}"),
        )
    }

    pub(super) fn finite(
        &self,
        x: f64,
        span: Range<usize>,
        entry: &str,
        field: &str,
    ) -> Result<f64> {
        if x.is_finite() {
            Ok(x)
        } else {
            Err(self.err(
                Some(span),
                entry,
                field,
                format!("{x} is not a finite number"),
            ))
        }
    }

    pub(super) fn quantity(
        &self,
        t: &str,
        dim: Dimension,
        span: Range<usize>,
        entry: &str,
        field: &str,
    ) -> Result<f64> {
        let q = parse_quantity(t)
            .map_err(|e| self.err(Some(span.clone()), entry, field, e.to_string()))?;
        if q.dim != dim && !(q.dim == Dimension::DIMENSIONLESS && bare(t)) {
            return Err(self.err(
                Some(span),
                entry,
                field,
                format!(
                    "'{t}' has the dimension {}, but {field} needs {}",
                    q.dim, dim
                ),
            ));
        }
        self.finite(q.value, span, entry, field)
    }

    /// A coefficient: a number with a unit, or a parameter name.
    pub(super) fn value(
        &mut self,
        v: &SNum,
        dim: Dimension,
        entry: &str,
        field: &str,
    ) -> Result<Value> {
        if let RawNum::Bool(b) = v.get_ref() {
            return Err(self.boolean(*b, v, entry, field, true));
        }
        if let RawNum::Text(t) = v.get_ref() {
            if !looks_numeric(t) {
                let Some(&i) = self.param_index.get(t.trim()) else {
                    let known: Vec<&str> = self.params.iter().map(|p| p.name.as_str()).collect();
                    return Err(self.err(
                        Some(v.span()),
                        entry,
                        field,
                        format!("unknown parameter '{t}' (known: {})", list(&known)),
                    ));
                };
                self.params[i]
                    .uses
                    .push((dim, v.span(), entry.into(), field.into()));
                return Ok(Value::Param(i));
            }
        }
        Ok(Value::Fixed(self.number(v, dim, entry, field)?))
    }

    pub(super) fn vec3(
        &self,
        v: &SVec,
        dim: Dimension,
        entry: &str,
        field: &str,
    ) -> Result<Vector3<f64>> {
        if v.get_ref().len() != 3 {
            return Err(self.err(
                Some(v.span()),
                entry,
                field,
                format!("needs 3 numbers, found {}", v.get_ref().len()),
            ));
        }
        let mut out = Vector3::zeros();
        for (i, x) in v.get_ref().iter().enumerate() {
            out[i] = self.number(x, dim, entry, field)?;
        }
        Ok(out)
    }

    pub(super) fn direction(&self, v: &SVec, entry: &str, field: &str) -> Result<Vector3<f64>> {
        let d = self.vec3(v, Dimension::DIMENSIONLESS, entry, field)?;
        let norm = d.norm();
        if !(norm > 1e-12) {
            return Err(self.err(Some(v.span()), entry, field, "the direction is zero"));
        }
        Ok(d / norm)
    }

    pub(super) fn axes(&self, v: &Option<Spanned<Vec<SVec>>>, entry: &str) -> Result<Matrix3<f64>> {
        let Some(v) = v else {
            return Ok(Matrix3::identity());
        };
        if v.get_ref().len() != 3 {
            return Err(self.err(
                Some(v.span()),
                entry,
                "axes",
                "needs three vectors [e1, e2, e3]",
            ));
        }
        let mut r = Matrix3::zeros();
        for (j, e) in v.get_ref().iter().enumerate() {
            r.set_column(j, &self.vec3(e, Dimension::DIMENSIONLESS, entry, "axes")?);
        }
        match check_axes(&r, AXES_TOL) {
            Ok(()) => Ok(nearest_rotation(&r)),
            Err(AxesDefect::NotOrthonormal { deviation }) => Err(self.err(
                Some(v.span()),
                entry,
                "axes",
                format!(
                    "the axes are not orthonormal (|RᵀR − I| = {deviation:.2e} > {AXES_TOL:e})"
                ),
            )),
            Err(AxesDefect::LeftHanded) => Err(self.err(
                Some(v.span()),
                entry,
                "axes",
                "the axes are left-handed (e1 × e2 must equal e3)",
            )),
        }
    }
}

/// The rotation nearest to an almost-orthonormal R (so that a frame written
/// to 8 digits is exact afterwards).
pub(super) fn nearest_rotation(r: &Matrix3<f64>) -> Matrix3<f64> {
    let svd = r.svd(true, true);
    match (svd.u, svd.v_t) {
        (Some(u), Some(vt)) => u * vt,
        _ => *r,
    }
}

pub(super) fn looks_numeric(t: &str) -> bool {
    let t = t.trim_start();
    t.starts_with(|c: char| c.is_ascii_digit() || c == '.' || c == '-' || c == '+')
}

pub(super) fn bare(t: &str) -> bool {
    t.trim().parse::<f64>().is_ok()
}

pub(super) fn list(names: &[&str]) -> String {
    if names.is_empty() {
        "none".into()
    } else {
        names.join(", ")
    }
}

pub(super) fn required<'a, T>(
    ctx: &Ctx,
    v: &'a Option<T>,
    span: Range<usize>,
    entry: &str,
    field: &str,
) -> Result<&'a T> {
    v.as_ref()
        .ok_or_else(|| ctx.err(Some(span), entry, field, format!("'{field}' is missing")))
}

pub(super) fn name_of(
    ctx: &Ctx,
    v: &Option<Spanned<String>>,
    span: Range<usize>,
    kind: &str,
    index: usize,
) -> Result<(String, Range<usize>)> {
    let entry = format!("{kind} #{}", index + 1);
    let n = required(ctx, v, span, &entry, "name")?;
    let name = n.get_ref().trim().to_string();
    if name.is_empty() {
        return Err(ctx.err(Some(n.span()), &entry, "name", "the name is empty"));
    }
    Ok((name, n.span()))
}

pub(super) fn check_unique(
    ctx: &Ctx,
    seen: &mut HashMap<String, usize>,
    name: &str,
    span: Range<usize>,
    kind: &str,
    index: usize,
) -> Result<()> {
    if let Some(first) = seen.insert(name.to_string(), index) {
        return Err(ctx.err(
            Some(span),
            &format!("{kind} \"{name}\""),
            "name",
            format!("duplicate {kind} name (also {kind} #{})", first + 1),
        ));
    }
    Ok(())
}

/// Splits a quantity's text into its number and its unit symbol.
pub(super) fn unit_symbol(t: &str) -> &str {
    let t = t.trim();
    let end = t
        .char_indices()
        .find(|&(i, c)| {
            !(c.is_ascii_digit()
                || c == '.'
                || c == '+'
                || c == '-'
                || ((c == 'e' || c == 'E') && i > 0))
        })
        .map(|(i, _)| i)
        .unwrap_or(t.len());
    t[end..].trim()
}

/// The keys of the file itself, outside any entry (the fields of `RawFile`).
const TOP_LEVEL_KEYS: [&str; 8] = [
    "simulation",
    "gravity",
    "body",
    "element",
    "parameter",
    "excitation",
    "sensor",
    "experiment",
];

/// A TOML syntax or schema error. An unknown key (a typo) is named as the
/// field, in the entry that holds it.
pub(super) fn toml_error(ctx: &Ctx, text: &str, e: &toml::de::Error) -> Box<ModelFileError> {
    let mut message = e.message().to_string();
    let header = e.span().and_then(|span| header_at(text, span.start));
    if let (Some(name), true) = (&header, message.contains("duplicate key")) {
        // `[experiment]` (one table) beside `[[experiment]]` entries.
        message = format!(
            "{message}: '{name}' is written both as one table [{name}] and as entries [[{name}]]; write every one as [[{name}]]"
        );
    }
    let field = message
        .strip_prefix("unknown field `")
        .and_then(|m| m.split('`').next())
        .map(str::to_string)
        .or(header)
        .or_else(|| e.span().and_then(|span| key_before(text, span.start)))
        .unwrap_or_default();
    let entry = e
        .span()
        .and_then(|span| entry_at(text, span.start))
        .unwrap_or_default();
    if !entry.is_empty() && TOP_LEVEL_KEYS.contains(&field.as_str()) {
        // `gravity = …` written below `[simulation]` belongs to that table.
        message = format!(
            "{message}; '{field}' is a top-level key: write it above the first [table] header (TOML puts a key into the table whose header comes before it)"
        );
    }
    ctx.err(e.span(), &entry, &field, message)
}

/// The key whose value starts at byte `pos`: the last `key =` before it on
/// its line (inline tables included), or on an earlier line for a value
/// inside a multi-line array.
fn key_before(text: &str, pos: usize) -> Option<String> {
    let before = text.get(..pos)?;
    for line in before.rsplit('\n').take(50) {
        if header_name(line).is_some() {
            // The value would start after its table's header.
            return None;
        }
        // A comment's `=` is no key's.
        let line = line.split_once('#').map_or(line, |(code, _)| code);
        if let Some((left, _)) = line.rsplit_once('=') {
            let key = left
                .rsplit(['{', ',', '['])
                .next()?
                .trim()
                .trim_matches('"');
            if !key.is_empty() {
                return Some(key.to_string());
            }
        }
    }
    None
}

/// The table name of the header on the line that holds byte `pos`.
fn header_at(text: &str, pos: usize) -> Option<String> {
    let start = text.get(..pos)?.rfind('\n').map_or(0, |i| i + 1);
    let line = text[start..].split('\n').next()?;
    header_name(line)
}

/// The name of a `[name]` or `[[name]]` header line (a comment may
/// follow); `None` for any other line (an array's row such as
/// `[0, 1, 0],` included).
fn header_name(line: &str) -> Option<String> {
    let code = line.split_once('#').map_or(line, |(code, _)| code).trim();
    let inner = match code.strip_prefix("[[") {
        Some(rest) => rest.strip_suffix("]]")?,
        None => code.strip_prefix('[')?.strip_suffix(']')?,
    };
    let name = inner.trim();
    let plain = |c: char| c.is_ascii_alphanumeric() || c == '_' || c == '-' || c == '.';
    (!name.is_empty() && name.chars().all(plain)).then(|| name.to_string())
}

/// The entry (`body "knee"`, `element #2`, `[simulation]` …) whose table
/// holds byte `pos`, named as the errors of [`build`] name it. A table's
/// span is its header, so the entry is the last header before `pos`.
pub(super) fn entry_at(text: &str, pos: usize) -> Option<String> {
    let loose: LooseFile = toml::from_str(text).ok()?;
    let mut headers: Vec<(usize, String)> = Vec::new();
    if let Some(sim) = &loose.simulation {
        headers.push((sim.span().start, "[simulation]".into()));
    }
    let kinds = [
        ("body", &loose.body),
        ("element", &loose.element),
        ("parameter", &loose.parameter),
        ("excitation", &loose.excitation),
        ("sensor", &loose.sensor),
        ("experiment", &loose.experiment),
    ];
    for (kind, entries) in kinds {
        for (i, e) in entries.iter().enumerate() {
            let name = e.get_ref().get("name").and_then(|n| n.as_str());
            let entry = match (name, kind) {
                (Some(n), _) => format!("{kind} \"{}\"", n.trim()),
                (None, "excitation") => format!("excitation \"excitation {}\"", i + 1),
                (None, _) => format!("{kind} #{}", i + 1),
            };
            headers.push((e.span().start, entry));
        }
    }
    headers
        .into_iter()
        .filter(|(start, _)| *start <= pos)
        .max_by_key(|(start, _)| *start)
        .map(|(_, entry)| entry)
}
