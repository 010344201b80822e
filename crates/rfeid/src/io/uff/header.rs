//! Records 6 and 7 of a dataset-58 header: DOF identification and data form.
use super::error::Ctx;
use super::fields::{fixed, int, real, tokens};
use super::lines::Line;
use super::{OrdinateType, UffError};

/// Record 6: function type, response node and direction, reference node
/// and direction.
pub fn dof_identification(l: &Line<'_>, ctx: &Ctx<'_>) -> Result<[i64; 5], UffError> {
    let f = fixed(l.text, &[5, 10, 5, 10, 11, 10, 4, 11, 10, 4]);
    let pick = |v: &[String], idx: [usize; 5]| -> Option<[i64; 5]> {
        let mut out = [0; 5];
        for (o, i) in out.iter_mut().zip(idx) {
            let s = v.get(i)?;
            *o = if s.is_empty() { 0 } else { int(s)? };
        }
        Some(out)
    };
    pick(&f, [0, 5, 6, 8, 9])
        .filter(|_| !f[0].is_empty())
        .or_else(|| {
            let t = tokens(l.text);
            (t.len() == 10).then(|| pick(&t, [0, 5, 6, 8, 9])).flatten()
        })
        .ok_or_else(|| {
            ctx.malformed(
                l,
                format!(
                    "record 6 (DOF identification) needs integer function type, nodes and \
                     directions, found '{}'",
                    l.excerpt()
                ),
            )
        })
}

/// Record 7.
#[derive(Debug, Clone, Copy)]
pub struct DataForm {
    /// Ordinate data type.
    pub ordinate: OrdinateType,
    /// Number of points.
    pub n: usize,
    /// Even abscissa spacing.
    pub even: bool,
    /// Abscissa minimum.
    pub min: f64,
    /// Abscissa increment.
    pub increment: f64,
}

/// Record 7: ordinate type, points, spacing, abscissa minimum and increment.
pub fn data_form(l: &Line<'_>, ctx: &Ctx<'_>) -> Result<DataForm, UffError> {
    let parse = |f: &[String]| -> Option<(i64, i64, i64, f64, f64)> {
        let or0 = |s: &String| if s.is_empty() { Some(0.0) } else { real(s) };
        Some((
            int(f.first()?)?,
            int(f.get(1)?)?,
            int(f.get(2)?)?,
            or0(f.get(3)?)?,
            or0(f.get(4)?)?,
        ))
    };
    let f = fixed(l.text, &[10, 10, 10, 13, 13, 13]);
    let t = tokens(l.text);
    let (code, n, spacing, min, increment) = parse(&f)
        .or_else(|| (t.len() >= 5).then(|| parse(&t)).flatten())
        .ok_or_else(|| {
            ctx.malformed(
                l,
                format!(
                    "record 7 (data form) needs ordinate type, points, spacing, abscissa \
                     minimum and increment, found '{}'",
                    l.excerpt()
                ),
            )
        })?;
    let ordinate = OrdinateType::from_code(code).ok_or_else(|| {
        ctx.malformed(
            l,
            format!("ordinate data type {code} (2, 4, 5 or 6 expected)"),
        )
    })?;
    let n = usize::try_from(n)
        .map_err(|_| ctx.malformed(l, format!("negative number of points {n}")))?;
    let even = match spacing {
        0 => false,
        1 => true,
        _ => {
            return Err(ctx.malformed(
                l,
                format!("abscissa spacing {spacing} (0 uneven or 1 even expected)"),
            ))
        }
    };
    Ok(DataForm {
        ordinate,
        n,
        even,
        min,
        increment,
    })
}
