//! One dataset-58 function record, read in full.
//!
//! Dataset 58 ("function at nodal DOF"): after the `-1` and the dataset
//! number line come 11 ASCII header lines — ID lines 1–5 (80A1; line 1 is
//! the function's description, used here as its name), record 6 "DOF
//! identification" (`2(I5,I10),2(1X,10A1,I10,I4)`: function type, function
//! id, version, load case, response entity, node, direction, reference
//! entity, node, direction), record 7 "data form" (`3I10,3E13.5`: ordinate
//! data type 2/4/5/6 = real single/real double/complex single/complex
//! double, number of points, spacing 1 even/0 uneven, abscissa minimum,
//! increment, z value), records 8–11 "data characteristics" of abscissa,
//! ordinate numerator, denominator and z axis (`I10,3I5,2(1X,20A1)`, field 1
//! the specific data type: 17 time, 18 frequency, 8 displacement, 11
//! velocity, 12 acceleration …) — then the data: ordinates only for even
//! spacing, (abscissa, ordinate) pairs for uneven spacing, real and
//! imaginary parts for complex data; in ASCII as `6E13.5` (single),
//! `4E20.12` (double, even) or `2(E13.5,E20.12)` (double, uneven).
use super::binary::{self, BinaryHeader, Layout};
use super::error::Ctx;
use super::fields::{data_line, fixed, int};
use super::header::{data_form, dof_identification, DataForm};
use super::lines::{Cursor, Line};
use super::{Abscissa, OrdinateType, UffError, UffRecord};

/// Reads the rest of a dataset-58 record whose number line is `head`.
pub fn parse_58(
    cur: &mut Cursor<'_>,
    head: &Line<'_>,
    is_binary: bool,
    ctx: &Ctx<'_>,
) -> Result<UffRecord, UffError> {
    let bin = if is_binary {
        Some(binary_header(head, ctx)?)
    } else {
        None
    };
    let h = header_lines(cur, ctx)?;
    let id_lines: [String; 5] = std::array::from_fn(|i| h[i].trimmed());
    let dof = dof_identification(&h[5], ctx)?;
    let form = data_form(&h[6], ctx)?;
    let spec = |l: &Line<'_>| int(&fixed(l.text, &[10])[0]).unwrap_or(0);
    let per_point = if form.ordinate.is_complex() { 2 } else { 1 };
    let stride = usize::from(!form.even) + per_point;
    let values = match bin {
        None => ascii_data(cur, &form, stride, ctx, &h[6])?,
        Some(b) => binary_data(cur, &b, &form, per_point, ctx, &h[10])?,
    };
    let (abscissa, ordinates) = split(&values, &form, stride);
    Ok(UffRecord {
        number: ctx.context.record.unwrap_or(0),
        line: ctx.context.start_line,
        binary: is_binary,
        id_lines,
        function_type: dof[0],
        response_node: dof[1],
        response_direction: dof[2],
        reference_node: dof[3],
        reference_direction: dof[4],
        ordinate_type: form.ordinate,
        num_points: form.n,
        abscissa_data_type: spec(&h[7]),
        ordinate_data_type: spec(&h[8]),
        abscissa,
        values: ordinates,
    })
}

/// A 58b record's binary header: 11 ASCII lines, IEEE 754 numbers.
fn binary_header(head: &Line<'_>, ctx: &Ctx<'_>) -> Result<BinaryHeader, UffError> {
    let b = binary::header(head, ctx)?;
    if b.n_ascii != 11 {
        return Err(ctx.malformed(
            head,
            format!(
                "a 58b header announces {} ASCII lines; dataset 58 has 11",
                b.n_ascii
            ),
        ));
    }
    if b.fp_format != 2 {
        return Err(UffError::Unsupported {
            path: ctx.path.into(),
            context: ctx.context,
            line: head.number,
            message: format!(
                "floating-point format {} (only 2, IEEE 754, is read)",
                b.fp_format
            ),
        });
    }
    Ok(b)
}

/// The record's 11 ASCII header lines.
fn header_lines<'a>(cur: &mut Cursor<'a>, ctx: &Ctx<'_>) -> Result<Vec<Line<'a>>, UffError> {
    let mut h: Vec<Line<'_>> = Vec::with_capacity(11);
    while h.len() < 11 {
        match cur.next_line() {
            Some(l) if !l.is_delimiter() => h.push(l),
            other => {
                let (line, offset) =
                    other.map_or((cur.line(), cur.pos()), |l| (l.number, l.offset));
                return Err(ctx.truncated_at(
                    line,
                    offset,
                    format!("the header ends after {} of its 11 lines", h.len()),
                ));
            }
        }
    }
    Ok(h)
}

/// The values of an ASCII record, in the field widths of its ordinate type
/// and spacing; `form_line` is the data-form line, for a count that overflows.
fn ascii_data(
    cur: &mut Cursor<'_>,
    form: &DataForm,
    stride: usize,
    ctx: &Ctx<'_>,
    form_line: &Line<'_>,
) -> Result<Vec<f64>, UffError> {
    let widths: &[usize] = match (form.ordinate, form.even) {
        (OrdinateType::RealSingle | OrdinateType::ComplexSingle, _) => &[13],
        (_, true) => &[20],
        (OrdinateType::RealDouble, false) => &[13, 20],
        (OrdinateType::ComplexDouble, false) => &[13, 20, 20],
    };
    let needed = form
        .n
        .checked_mul(stride)
        .ok_or_else(|| ctx.malformed(form_line, format!("{} points is too many", form.n)))?;
    ascii_values(cur, needed, widths, ctx)
}

/// The values of a binary record, located and decoded; the cursor moves past them.
fn binary_data(
    cur: &mut Cursor<'_>,
    b: &BinaryHeader,
    form: &DataForm,
    per_point: usize,
    ctx: &Ctx<'_>,
    last_header_line: &Line<'_>,
) -> Result<Vec<f64>, UffError> {
    let size = match form.ordinate {
        OrdinateType::RealSingle | OrdinateType::ComplexSingle => 4,
        _ => 8,
    };
    let base = Layout {
        n: form.n,
        size,
        per_point,
        x_size: 0,
    };
    let start = cur.pos();
    let (layout, end) = binary::locate(
        cur.bytes(),
        start,
        b.n_bytes,
        base,
        !form.even,
        ctx,
        last_header_line,
    )?;
    let v = binary::decode(cur.bytes(), start, layout, b.little);
    cur.jump(end);
    Ok(v)
}

/// Splits the values in file order into the abscissa and the real
/// ordinates (none for complex data).
fn split(values: &[f64], form: &DataForm, stride: usize) -> (Abscissa, Vec<f64>) {
    let abscissa = if form.even {
        Abscissa::Even {
            min: form.min,
            increment: form.increment,
            count: form.n,
        }
    } else {
        Abscissa::Uneven(values.iter().step_by(stride).copied().collect())
    };
    let first = usize::from(!form.even);
    let ordinates = if form.ordinate.is_complex() {
        Vec::new()
    } else {
        values.iter().skip(first).step_by(stride).copied().collect()
    };
    (abscissa, ordinates)
}

/// Reads `needed` ASCII numbers, then the closing `-1`.
fn ascii_values(
    cur: &mut Cursor<'_>,
    needed: usize,
    widths: &[usize],
    ctx: &Ctx<'_>,
) -> Result<Vec<f64>, UffError> {
    let left = cur.bytes().len().saturating_sub(cur.pos());
    let mut values = Vec::with_capacity(needed.min(left / 2));
    while values.len() < needed {
        let Some(l) = cur.next_line() else {
            return Err(ctx.truncated_at(
                cur.line(),
                cur.pos(),
                format!("the file ends after {} of {needed} values", values.len()),
            ));
        };
        if l.is_delimiter() {
            return Err(ctx.truncated_at(
                l.number,
                l.offset,
                format!("the record ends after {} of {needed} values", values.len()),
            ));
        }
        let v = data_line(l.text, widths).map_err(|bad| {
            if l.complete {
                ctx.malformed(&l, format!("'{bad}' is not a number"))
            } else {
                ctx.truncated_at(
                    l.number,
                    l.offset + l.text.len(),
                    format!(
                        "the file ends inside a number after {} of {needed} values",
                        values.len()
                    ),
                )
            }
        })?;
        if values.len() + v.len() > needed {
            return Err(ctx.malformed(
                &l,
                format!("more values than the {needed} the header announces"),
            ));
        }
        values.extend(v);
    }
    match cur.next_nonblank() {
        Some(l) if l.is_delimiter() => Ok(values),
        Some(l) => Err(ctx.malformed(
            &l,
            format!(
                "expected the closing '    -1' after {needed} values, found '{}'",
                l.excerpt()
            ),
        )),
        None => Err(ctx.truncated_at(
            cur.line(),
            cur.pos(),
            "the file ends before the closing '    -1'".into(),
        )),
    }
}
