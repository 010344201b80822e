//! From the raw file to a validated [`Model`].
use super::error::ModelFileError;
use super::raw::*;
use crate::io::timeseries::read_csv;
use crate::io::units::{parse_quantity, Dimension};
use crate::model::geometry::{check_axes, AxesDefect};
use crate::model::*;
use nalgebra::{Matrix3, Vector3};
use std::collections::HashMap;
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use toml::Spanned;

/// Errors are boxed inside the builder, where they pass through many frames.
type Result<T> = std::result::Result<T, Box<ModelFileError>>;

/// A parameter's value or bound with the dimension of its unit, if it had one.
type Reading = (f64, Option<Dimension>);

/// Tolerance on `RᵀR − I` for axes.
const AXES_TOL: f64 = 1e-6;

/// A parameter as read, before its dimension is known from its uses.
struct ParamDraft {
    name: String,
    span: Range<usize>,
    value: (f64, Option<Dimension>),
    bounds: Option<(Reading, Reading)>,
    /// Spans of the value, min and max texts (min and max: the value's when absent).
    value_spans: [Range<usize>; 3],
    unit: DisplayUnit,
    uses: Vec<(Dimension, Range<usize>, String, String)>,
}

struct Ctx {
    path: PathBuf,
    dir: PathBuf,
    text: Arc<str>,
    params: Vec<ParamDraft>,
    param_index: HashMap<String, usize>,
}

impl Ctx {
    fn err(
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
    fn number(&self, v: &SNum, dim: Dimension, entry: &str, field: &str) -> Result<f64> {
        match v.get_ref() {
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

    fn finite(&self, x: f64, span: Range<usize>, entry: &str, field: &str) -> Result<f64> {
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

    fn quantity(
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
    fn value(&mut self, v: &SNum, dim: Dimension, entry: &str, field: &str) -> Result<Value> {
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

    fn vec3(&self, v: &SVec, dim: Dimension, entry: &str, field: &str) -> Result<Vector3<f64>> {
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

    fn direction(&self, v: &SVec, entry: &str, field: &str) -> Result<Vector3<f64>> {
        let d = self.vec3(v, Dimension::DIMENSIONLESS, entry, field)?;
        let norm = d.norm();
        if !(norm > 1e-12) {
            return Err(self.err(Some(v.span()), entry, field, "the direction is zero"));
        }
        Ok(d / norm)
    }

    fn axes(&self, v: &Option<Spanned<Vec<SVec>>>, entry: &str) -> Result<Matrix3<f64>> {
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
fn nearest_rotation(r: &Matrix3<f64>) -> Matrix3<f64> {
    let svd = r.svd(true, true);
    match (svd.u, svd.v_t) {
        (Some(u), Some(vt)) => u * vt,
        _ => *r,
    }
}

fn looks_numeric(t: &str) -> bool {
    let t = t.trim_start();
    t.starts_with(|c: char| c.is_ascii_digit() || c == '.' || c == '-' || c == '+')
}

fn bare(t: &str) -> bool {
    t.trim().parse::<f64>().is_ok()
}

fn list(names: &[&str]) -> String {
    if names.is_empty() {
        "none".into()
    } else {
        names.join(", ")
    }
}

fn required<'a, T>(
    ctx: &Ctx,
    v: &'a Option<T>,
    span: Range<usize>,
    entry: &str,
    field: &str,
) -> Result<&'a T> {
    v.as_ref()
        .ok_or_else(|| ctx.err(Some(span), entry, field, format!("'{field}' is missing")))
}

fn name_of(
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

fn check_unique(
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
fn unit_symbol(t: &str) -> &str {
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

/// A TOML syntax or schema error. An unknown key (a typo) is named as the
/// field, in the entry that holds it.
fn toml_error(ctx: &Ctx, text: &str, e: &toml::de::Error) -> Box<ModelFileError> {
    let message = e.message().to_string();
    let field = message
        .strip_prefix("unknown field `")
        .and_then(|m| m.split('`').next())
        .unwrap_or("")
        .to_string();
    let entry = e
        .span()
        .and_then(|span| entry_at(text, span.start))
        .unwrap_or_default();
    ctx.err(e.span(), &entry, &field, message)
}

/// The entry (`body "knee"`, `element #2`, `[simulation]` …) whose table
/// holds byte `pos`, named as the errors of [`build`] name it. A table's
/// span is its header, so the entry is the last header before `pos`.
fn entry_at(text: &str, pos: usize) -> Option<String> {
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

pub(super) fn build(text: &str, path: &Path) -> Result<Model> {
    let mut ctx = Ctx {
        path: path.into(),
        dir: path.parent().map(Path::to_path_buf).unwrap_or_default(),
        text: Arc::from(text),
        params: Vec::new(),
        param_index: HashMap::new(),
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
        ctx.param_index.insert(name.clone(), i);
        ctx.params.push(ParamDraft {
            name,
            span,
            value: (value, vdim),
            bounds,
            value_spans,
            unit,
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
            None => crate::io::data_file::DataSource::for_sensor(&name),
        };
        sensors.push(Sensor {
            name,
            body,
            at,
            direction,
            kind,
            data,
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
    Ok(Model {
        bodies,
        elements,
        parameters,
        excitations,
        sensors,
        sampling,
        gravity,
    })
}

fn component(
    ctx: &mut Ctx,
    c: &Spanned<RawComponent>,
    dof: usize,
    element: &str,
) -> Result<Component> {
    let cname = COMPONENT_NAMES[dof];
    let entry = format!("{element}, component {cname}");
    let rc = c.get_ref();
    let rotational = dof >= 3;
    let (k_dim, c_dim) = if rotational {
        (Dimension::MOMENT, Dimension::ROTATIONAL_DAMPING)
    } else {
        (Dimension::STIFFNESS, Dimension::DAMPING)
    };
    let law_name = match &rc.law {
        Some(l) => l.get_ref().trim().to_string(),
        None if rc.a.is_some() || rc.m.is_some() => "power".into(),
        None if rc.k.is_some() => "linear".into(),
        None => "none".into(),
    };
    let forbid = |ctx: &Ctx, v: &Option<SNum>, field: &str, law: &str| -> Result<()> {
        match v {
            Some(v) => Err(ctx.err(
                Some(v.span()),
                &entry,
                field,
                format!("'{field}' does not belong to the {law} law"),
            )),
            None => Ok(()),
        }
    };
    let law = match law_name.as_str() {
        "linear" => {
            forbid(ctx, &rc.a, "a", "linear")?;
            forbid(ctx, &rc.m, "m", "linear")?;
            let k = ctx.value(
                required(ctx, &rc.k, c.span(), &entry, "k")?,
                k_dim,
                &entry,
                "k",
            )?;
            non_negative(ctx, k, &rc.k, &entry, "k")?;
            Law::Linear { k }
        }
        "power" => {
            forbid(ctx, &rc.k, "k", "power")?;
            let m_raw = required(ctx, &rc.m, c.span(), &entry, "m")?;
            let m = ctx.value(m_raw, Dimension::DIMENSIONLESS, &entry, "m")?;
            let m_nominal = match m {
                Value::Fixed(x) => x,
                Value::Param(i) => ctx.params[i].value.0,
            };
            if !(m_nominal >= 1.0) {
                return Err(ctx.err(
                    Some(m_raw.span()),
                    &entry,
                    "m",
                    format!("the exponent must be at least 1 (found {m_nominal})"),
                ));
            }
            let a_dim = if rotational {
                Dimension::MOMENT
            } else {
                Dimension::FORCE.div(Dimension::LENGTH.powf(m_nominal))
            };
            let a = ctx.value(
                required(ctx, &rc.a, c.span(), &entry, "a")?,
                a_dim,
                &entry,
                "a",
            )?;
            non_negative(ctx, a, &rc.a, &entry, "a")?;
            Law::Power { a, m }
        }
        "none" => {
            if rc.c.is_none() {
                return Err(ctx.err(
                    Some(c.span()),
                    &entry,
                    "law",
                    "the component has neither a spring (k, or a and m) nor damping (c)",
                ));
            }
            Law::None
        }
        other => {
            let span = rc.law.as_ref().map(|l| l.span());
            return Err(ctx.err(
                span,
                &entry,
                "law",
                format!("unknown law '{other}' (linear or power)"),
            ));
        }
    };
    let damping = match &rc.c {
        Some(v) => {
            let d = ctx.value(v, c_dim, &entry, "c")?;
            non_negative(ctx, d, &rc.c, &entry, "c")?;
            d
        }
        None => Value::Fixed(0.0),
    };
    Ok(Component { dof, law, damping })
}

fn non_negative(ctx: &Ctx, v: Value, raw: &Option<SNum>, entry: &str, field: &str) -> Result<()> {
    if let Value::Fixed(x) = v {
        if x < 0.0 {
            return Err(ctx.err(
                raw.as_ref().map(|r| r.span()),
                entry,
                field,
                format!("must not be negative (found {x})"),
            ));
        }
    }
    Ok(())
}

fn signal(ctx: &mut Ctx, sig: &Spanned<RawSignal>, entry: &str, raw: &RawFile) -> Result<Signal> {
    let rs = sig.get_ref();
    let kind_raw = required(ctx, &rs.kind, sig.span(), entry, "signal.type")?;
    let kind: &'static str = match kind_raw.get_ref().trim() {
        "sine" => "sine",
        "multisine" => "multisine",
        "chirp" => "chirp",
        "impulse" => "impulse",
        "table" => "table",
        other => {
            return Err(ctx.err(
                Some(kind_raw.span()),
                entry,
                "signal.type",
                format!("unknown signal type '{other}' (sine, multisine, chirp, impulse or table)"),
            ))
        }
    };
    // Keys that do not belong to this type are errors, like unknown keys.
    let allowed: &[&str] = match kind {
        "sine" => &["amplitude", "frequency", "phase"],
        "multisine" => &["components"],
        "chirp" => &["amplitude", "f0", "f1", "duration"],
        "impulse" => &["amplitude", "t0", "width"],
        _ => &["amplitude", "file", "column"],
    };
    let present: [(&str, Option<Range<usize>>); 11] = [
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
    ];
    for (key, span) in present {
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
    let f = Dimension::FORCE;
    let hz = Dimension::FREQUENCY;
    let s = Dimension::TIME;
    let one = Dimension::DIMENSIONLESS;
    let req = |ctx: &Ctx, v: &Option<SNum>, field: &str, dim: Dimension| -> Result<f64> {
        ctx.number(
            required(ctx, v, sig.span(), entry, &format!("signal.{field}"))?,
            dim,
            entry,
            &format!("signal.{field}"),
        )
    };
    let amplitude = |ctx: &mut Ctx, v: &Option<SNum>, default: Option<f64>| -> Result<Value> {
        match (v, default) {
            (Some(v), _) => ctx.value(v, f, entry, "signal.amplitude"),
            (None, Some(d)) => Ok(Value::Fixed(d)),
            (None, None) => Err(ctx.err(
                Some(sig.span()),
                entry,
                "signal.amplitude",
                "'amplitude' is missing",
            )),
        }
    };
    let positive = |ctx: &Ctx, x: f64, field: &str| -> Result<f64> {
        if x > 0.0 {
            Ok(x)
        } else {
            Err(ctx.err(
                Some(sig.span()),
                entry,
                &format!("signal.{field}"),
                format!("must be positive (found {x})"),
            ))
        }
    };
    let terms = match kind {
        "sine" => {
            let frequency = req(ctx, &rs.frequency, "frequency", hz)?;
            let phase = rs
                .phase
                .as_ref()
                .map(|p| ctx.number(p, one, entry, "signal.phase"))
                .transpose()?
                .unwrap_or(0.0);
            vec![Term {
                amplitude: amplitude(ctx, &rs.amplitude, None)?,
                shape: Shape::Sine { frequency, phase },
            }]
        }
        "multisine" => {
            let comps = required(ctx, &rs.components, sig.span(), entry, "signal.components")?;
            if comps.get_ref().is_empty() {
                return Err(ctx.err(
                    Some(comps.span()),
                    entry,
                    "signal.components",
                    "a multisine needs at least one component",
                ));
            }
            let mut terms = Vec::new();
            for tone in comps.get_ref() {
                let t = tone.get_ref();
                let fr = ctx.number(
                    required(
                        ctx,
                        &t.frequency,
                        tone.span(),
                        entry,
                        "signal.components.frequency",
                    )?,
                    hz,
                    entry,
                    "signal.components.frequency",
                )?;
                let phase = t
                    .phase
                    .as_ref()
                    .map(|p| ctx.number(p, one, entry, "signal.components.phase"))
                    .transpose()?
                    .unwrap_or(0.0);
                let a = ctx.value(
                    required(
                        ctx,
                        &t.amplitude,
                        tone.span(),
                        entry,
                        "signal.components.amplitude",
                    )?,
                    f,
                    entry,
                    "signal.components.amplitude",
                )?;
                terms.push(Term {
                    amplitude: a,
                    shape: Shape::Sine {
                        frequency: fr,
                        phase,
                    },
                });
            }
            terms
        }
        "chirp" => {
            let f0 = req(ctx, &rs.f0, "f0", hz)?;
            let f1 = req(ctx, &rs.f1, "f1", hz)?;
            let duration = match &rs.duration {
                Some(d) => positive(ctx, ctx.number(d, s, entry, "signal.duration")?, "duration")?,
                None => simulation_duration(ctx, raw)?,
            };
            vec![Term {
                amplitude: amplitude(ctx, &rs.amplitude, None)?,
                shape: Shape::Chirp { f0, f1, duration },
            }]
        }
        "impulse" => {
            let t0 = req(ctx, &rs.t0, "t0", s)?;
            let width = positive(ctx, req(ctx, &rs.width, "width", s)?, "width")?;
            vec![Term {
                amplitude: amplitude(ctx, &rs.amplitude, None)?,
                shape: Shape::Impulse { t0, width },
            }]
        }
        _ => {
            let file = required(ctx, &rs.file, sig.span(), entry, "signal.file")?;
            let column = required(ctx, &rs.column, sig.span(), entry, "signal.column")?;
            let path = ctx.dir.join(file.get_ref());
            let ts = read_csv(&path)
                .map_err(|e| ctx.err(Some(file.span()), entry, "signal.file", e.to_string()))?;
            let values = ts
                .column(column.get_ref())
                .ok_or_else(|| {
                    ctx.err(
                        Some(column.span()),
                        entry,
                        "signal.column",
                        format!(
                            "no column '{}' in {} (columns: {})",
                            column.get_ref(),
                            path.display(),
                            ts.names.join(", ")
                        ),
                    )
                })?
                .to_vec();
            vec![Term {
                amplitude: amplitude(ctx, &rs.amplitude, Some(1.0))?,
                shape: Shape::Table {
                    times: ts.time,
                    values,
                },
            }]
        }
    };
    Ok(Signal { kind, terms })
}

fn simulation_duration(ctx: &Ctx, raw: &RawFile) -> Result<f64> {
    sampling(ctx, raw).map(|s| s.duration)
}

fn sampling(ctx: &Ctx, raw: &RawFile) -> Result<Sampling> {
    let entry = "[simulation]";
    let sim = raw.simulation.as_ref().ok_or_else(|| {
        ctx.err(
            None,
            entry,
            "",
            "the model has no [simulation] table (duration, sample_rate)",
        )
    })?;
    let rs = sim.get_ref();
    let duration = ctx.number(
        required(ctx, &rs.duration, sim.span(), entry, "duration")?,
        Dimension::TIME,
        entry,
        "duration",
    )?;
    let rate_raw = required(ctx, &rs.sample_rate, sim.span(), entry, "sample_rate")?;
    let sample_rate = ctx.number(rate_raw, Dimension::FREQUENCY, entry, "sample_rate")?;
    if !(duration > 0.0) {
        return Err(ctx.err(
            rs.duration.as_ref().map(|d| d.span()),
            entry,
            "duration",
            "must be positive",
        ));
    }
    if !(sample_rate > 0.0) {
        return Err(ctx.err(
            Some(rate_raw.span()),
            entry,
            "sample_rate",
            "must be positive",
        ));
    }
    let n = (duration * sample_rate).round();
    if !(2.0..=1e8).contains(&n) {
        return Err(ctx.err(
            Some(sim.span()),
            entry,
            "duration",
            format!("duration × sample_rate gives {n} samples; it must be 2 to 1e8"),
        ));
    }
    let substeps = match &rs.substeps {
        None => crate::simulation::DEFAULT_SUBSTEPS,
        Some(s) if (1..=1000).contains(s.get_ref()) => *s.get_ref() as usize,
        Some(s) => {
            return Err(ctx.err(
                Some(s.span()),
                entry,
                "substeps",
                "must be a whole number from 1 to 1000",
            ))
        }
    };
    Ok(Sampling {
        duration,
        sample_rate,
        substeps,
    })
}

fn finish_parameters(ctx: &Ctx) -> Result<Vec<Parameter>> {
    let mut out = Vec::new();
    for p in &ctx.params {
        let entry = format!("parameter \"{}\"", p.name);
        let Some((dim, _, _, _)) = p.uses.first() else {
            return Err(ctx.err(
                Some(p.span.clone()),
                &entry,
                "name",
                "the parameter is never used",
            ));
        };
        for (d, span, e, f) in &p.uses {
            if d != dim {
                return Err(ctx.err(
                    Some(span.clone()),
                    e,
                    f,
                    format!("parameter '{}' is used with the dimension {d} here, but {dim} at its first use ({}, {})", p.name, p.uses[0].2, p.uses[0].3),
                ));
            }
        }
        let check = |(v, vd): (f64, Option<Dimension>),
                     field: &str,
                     span: &Range<usize>|
         -> Result<f64> {
            match vd {
                Some(vd) if vd != *dim => Err(ctx.err(
                    Some(span.clone()),
                    &entry,
                    field,
                    format!("the unit has the dimension {vd}, but the parameter is used as {dim} ({}, {})", p.uses[0].2, p.uses[0].3),
                )),
                _ => Ok(v),
            }
        };
        let value = check(p.value, "value", &p.value_spans[0])?;
        let bounds = match p.bounds {
            None => None,
            Some((lo, hi)) => Some((
                check(lo, "min", &p.value_spans[1])?,
                check(hi, "max", &p.value_spans[2])?,
            )),
        };
        let lowest = bounds.map(|b| b.0).unwrap_or(value);
        for (_, span, e, f) in &p.uses {
            let need_positive = f == "mass" || f == "inertia";
            let need_non_negative = matches!(f.as_str(), "k" | "a" | "c");
            if (need_positive && !(lowest > 0.0))
                || (need_non_negative && lowest < 0.0)
                || (f == "m" && lowest < 1.0)
            {
                let what = if need_positive {
                    "positive"
                } else if f == "m" {
                    "at least 1"
                } else {
                    "non-negative"
                };
                return Err(ctx.err(
                    Some(span.clone()),
                    e,
                    f,
                    format!(
                        "parameter '{}' must be {what} over its whole box (lowest {lowest:e})",
                        p.name
                    ),
                ));
            }
        }
        out.push(Parameter {
            name: p.name.clone(),
            value,
            bounds,
            unit: p.unit.clone(),
            dimension: *dim,
        });
    }
    Ok(out)
}
