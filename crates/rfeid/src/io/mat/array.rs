//! One MATLAB array (`miMATRIX` element): array flags, dimensions, name and,
//! for numeric classes, the real (and imaginary) part.
//!
//! Sub-elements, in order: array flags (`miUINT32`, 8 bytes: the class in
//! the low byte of the first word, the flags complex = 0x08, global = 0x04,
//! logical = 0x02 in the next byte), dimensions (`miINT32`, at least two),
//! array name (`miINT8`), then the class-specific data. The real part may be
//! stored in a smaller type than the class (MATLAB writes whole-valued
//! doubles as `miUINT8`, for example); its values are converted to `f64`.
//! Cells, structs, objects and sparse matrices are recognized by class and
//! not read further.
use super::element::{type_name, Buf, Element, MI_INT32, MI_INT8, MI_UINT32, MI_UINT8, MI_UTF8};
use super::error::MatError;

/// The class of a MATLAB array.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MatClass {
    /// `mxCELL_CLASS`.
    Cell,
    /// `mxSTRUCT_CLASS`.
    Struct,
    /// `mxOBJECT_CLASS`.
    Object,
    /// `mxCHAR_CLASS`.
    Char,
    /// `mxSPARSE_CLASS`.
    Sparse,
    /// `mxDOUBLE_CLASS`.
    Double,
    /// `mxSINGLE_CLASS`.
    Single,
    /// `mxINT8_CLASS`.
    Int8,
    /// `mxUINT8_CLASS` (also logical arrays, with the logical flag).
    UInt8,
    /// `mxINT16_CLASS`.
    Int16,
    /// `mxUINT16_CLASS`.
    UInt16,
    /// `mxINT32_CLASS`.
    Int32,
    /// `mxUINT32_CLASS`.
    UInt32,
    /// `mxINT64_CLASS`.
    Int64,
    /// `mxUINT64_CLASS`.
    UInt64,
    /// `mxFUNCTION_CLASS`: a function handle.
    Function,
    /// `mxOPAQUE_CLASS`: MATLAB objects such as strings and tables.
    Opaque,
}

impl MatClass {
    fn from_code(code: u32) -> Option<MatClass> {
        use MatClass::*;
        Some(match code {
            1 => Cell,
            2 => Struct,
            3 => Object,
            4 => Char,
            5 => Sparse,
            6 => Double,
            7 => Single,
            8 => Int8,
            9 => UInt8,
            10 => Int16,
            11 => UInt16,
            12 => Int32,
            13 => UInt32,
            14 => Int64,
            15 => UInt64,
            16 => Function,
            17 => Opaque,
            _ => return None,
        })
    }

    /// Whether arrays of this class hold numbers (double, single, integers).
    pub fn is_numeric(self) -> bool {
        use MatClass::*;
        matches!(
            self,
            Double | Single | Int8 | UInt8 | Int16 | UInt16 | Int32 | UInt32 | Int64 | UInt64
        )
    }
}

/// One variable of a MAT-file.
#[derive(Debug, Clone, PartialEq)]
pub struct MatVariable {
    /// Its name.
    pub name: String,
    /// Its class.
    pub class: MatClass,
    /// Its dimensions (empty for opaque objects).
    pub dims: Vec<usize>,
    /// Complex data (the imaginary part is not kept).
    pub complex: bool,
    /// A logical array (class uint8 with the logical flag).
    pub logical: bool,
    /// The real part in column-major order, as `f64`; empty unless the
    /// class is numeric.
    pub values: Vec<f64>,
}

impl MatVariable {
    /// What the variable is, for messages: `a double array`, `a char array` …
    pub fn describe(&self) -> String {
        use MatClass::*;
        if self.logical {
            return "a logical array".into();
        }
        let s = match self.class {
            Cell => "a cell array",
            Struct => "a struct",
            Object => "an object",
            Char => "a char array",
            Sparse => "a sparse matrix",
            Function => "a function handle",
            Opaque => "a MATLAB object (string, table, …)",
            Double => "a double array",
            Single => "a single array",
            Int8 => "an int8 array",
            UInt8 => "a uint8 array",
            Int16 => "an int16 array",
            UInt16 => "a uint16 array",
            Int32 => "an int32 array",
            UInt32 => "a uint32 array",
            Int64 => "an int64 array",
            UInt64 => "a uint64 array",
        };
        s.into()
    }

    /// The dimensions written `2×3`.
    pub fn dims_text(&self) -> String {
        let d: Vec<String> = self.dims.iter().map(|d| d.to_string()).collect();
        d.join("×")
    }

    /// Whether at most one dimension differs from 1 (1×N, N×1, 1×1×N …).
    pub fn is_vector(&self) -> bool {
        self.dims.iter().filter(|&&d| d != 1).count() <= 1
    }
}

/// Reads the array in the `miMATRIX` element `el` of `buf`; `None` for an
/// empty element (MATLAB writes those for empty cells).
pub fn parse_matrix(buf: &Buf<'_>, el: &Element<'_>) -> Result<Option<MatVariable>, MatError> {
    if el.data.is_empty() {
        return Ok(None);
    }
    let end = el.data_end;
    let flags = buf.element(el.data_start, end, "array flags")?;
    let (class, complex, logical) = array_flags(buf, &flags)?;
    let mut next = flags.next;
    let mut dims = Vec::new();
    if class != MatClass::Opaque {
        let d = buf.element(next, end, "array dimensions")?;
        dims = dimensions(buf, &d)?;
        next = d.next;
    }
    let n = buf.element(next, end, "array name")?;
    let name = array_name(buf, &n)?;
    let mut var = MatVariable {
        name,
        class,
        dims,
        complex,
        logical,
        values: Vec::new(),
    };
    if class.is_numeric() {
        var.values = numeric_data(buf, el, &var, n.next)?;
    }
    Ok(Some(var))
}

/// The array flags sub-element: the class, and whether complex and logical.
fn array_flags(buf: &Buf<'_>, flags: &Element<'_>) -> Result<(MatClass, bool, bool), MatError> {
    if flags.kind != MI_UINT32 || flags.data.len() != 8 {
        return Err(buf.malformed(
            flags.offset,
            format!(
                "array flags must be 8 bytes of miUINT32, found {} bytes of {}",
                flags.data.len(),
                type_name(flags.kind)
            ),
        ));
    }
    let word = buf
        .endian
        .u32([flags.data[0], flags.data[1], flags.data[2], flags.data[3]]);
    let code = word & 0xff;
    let class = MatClass::from_code(code)
        .ok_or_else(|| buf.malformed(flags.offset, format!("unknown array class {code}")))?;
    Ok((class, word & 0x0800 != 0, word & 0x0200 != 0))
}

/// The array name sub-element: `miINT8` (or `miUINT8`, `miUTF8`) text.
fn array_name(buf: &Buf<'_>, n: &Element<'_>) -> Result<String, MatError> {
    if ![MI_INT8, MI_UINT8, MI_UTF8].contains(&n.kind) {
        return Err(buf.malformed(
            n.offset,
            format!(
                "the array name must be miINT8 text, found {}",
                type_name(n.kind)
            ),
        ));
    }
    Ok(String::from_utf8_lossy(n.data).into_owned())
}

/// A numeric array's real part (from `pos`), checked against its dimensions;
/// a complex array's imaginary part is checked too, then dropped.
fn numeric_data(
    buf: &Buf<'_>,
    el: &Element<'_>,
    var: &MatVariable,
    pos: usize,
) -> Result<Vec<f64>, MatError> {
    let count = var
        .dims
        .iter()
        .try_fold(1usize, |p, &d| p.checked_mul(d))
        .ok_or_else(|| {
            buf.malformed(
                el.offset,
                format!(
                    "variable '{}': dimensions {} overflow",
                    var.name,
                    var.dims_text()
                ),
            )
        })?;
    let (real, values) = numeric_part(buf, var, pos, el.data_end, count, "real")?;
    if var.complex {
        numeric_part(buf, var, real.next, el.data_end, count, "imaginary")?;
    }
    Ok(values)
}

/// One part (real or imaginary) of a numeric array: `count` numbers.
fn numeric_part<'a>(
    buf: &Buf<'a>,
    var: &MatVariable,
    pos: usize,
    end: usize,
    count: usize,
    which: &str,
) -> Result<(Element<'a>, Vec<f64>), MatError> {
    let what = format!("{which} part of variable '{}'", var.name);
    let p = buf.element(pos, end, &what)?;
    let v = buf.numbers(&p, &var.name)?;
    if v.len() != count {
        return Err(buf.malformed(
            p.offset,
            format!(
                "variable '{}': dimensions {} need {count} values, its {which} part holds {}",
                var.name,
                var.dims_text(),
                v.len()
            ),
        ));
    }
    Ok((p, v))
}

/// The dimensions sub-element: at least two non-negative `miINT32`.
fn dimensions(buf: &Buf<'_>, d: &Element<'_>) -> Result<Vec<usize>, MatError> {
    if d.kind != MI_INT32 || d.data.len() % 4 != 0 || d.data.len() < 8 {
        return Err(buf.malformed(
            d.offset,
            format!(
                "array dimensions must be at least two miINT32, found {} bytes of {}",
                d.data.len(),
                type_name(d.kind)
            ),
        ));
    }
    d.data
        .chunks_exact(4)
        .map(|c| {
            let v = buf.endian.u32([c[0], c[1], c[2], c[3]]) as i32;
            usize::try_from(v)
                .map_err(|_| buf.malformed(d.offset, format!("negative array dimension {v}")))
        })
        .collect()
}
