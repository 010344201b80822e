//! Physical units in model files: `"380 daN/um^2"` → 3.8·10¹⁵ N/m².
//!
//! Everything inside rfeid is SI: kilogram, metre, second, and the newton
//! (N = kg·m/s²) derived from them. A model file may write a numeric value as
//! a string carrying a unit; [`parse_quantity`] turns it into a [`Quantity`]
//! (value in SI plus its [`Dimension`]), and [`expect_dimension`] checks that
//! the dimension is the one the field needs.
//!
//! # Grammar
//!
//! ```text
//! quantity  = number [ unit-expr ]            (whitespace between them optional)
//! number    = [+|-] (digits [. [digits]] | . digits) [(e|E) [+|-] digits]
//! unit-expr = [ "1" "/" ] factor { op factor }   e.g. 1/m, 1/N^0.5/m
//! op        = "*" | "·" | "/"                 (whitespace around an op allowed)
//! factor    = symbol [ "^" exponent ]  |  symbol superscript
//! exponent  = [+|-|−] digits [. digits]       e.g. 2, -1, 1.5
//! superscript = [⁻] superscript-digits        e.g. m², s⁻¹
//! ```
//!
//! A `/` divides by the single factor that follows it and operators are read
//! left to right, so `daN*ms/um` is daN·ms·µm⁻¹ and `N/m/s` is N·m⁻¹·s⁻¹.
//! A reciprocal unit is written `1/m` (`"1e3 1/m"` is 10³ m⁻¹), as
//! [`Dimension`]'s `Display` prints it, or `m^-1`.
//! Parentheses are not supported. Unit symbols are case sensitive (`mm` is
//! not `Mm`) and are listed, with their SI scale, in [`UNITS`]; both the micro
//! sign `µ` (U+00B5) and the Greek letter `μ` (U+03BC) are accepted, as is
//! `u`. A bare number has no unit and is dimensionless. NaN and infinity
//! are rejected, as is a value that overflows once converted to SI.
//!
//! Angles are dimensionless (rad = 1, deg = π/180), so a rotational stiffness
//! in N·m/rad has the dimension of a moment, N·m.
//!
//! A power-law joint coefficient has the unit N/m^m with a possibly
//! fractional m (eq. 6), so dimension exponents are `f64`, compared with a
//! tolerance of 10⁻⁹.
//!
//! # Examples
//!
//! ```
//! use rfeid::units::{expect_dimension, parse_quantity, Dimension};
//!
//! let q = parse_quantity("15 daN/um").unwrap();
//! assert_eq!(q.dim, Dimension::STIFFNESS);
//! assert!((q.value - 1.5e8).abs() < 1e-6);
//!
//! let h = parse_quantity("2.1 daN·ms/µm").unwrap();
//! assert!((expect_dimension(h, Dimension::DAMPING).unwrap() - 2.1e4).abs() < 1e-9);
//!
//! let err = expect_dimension(parse_quantity("3 kg").unwrap(), Dimension::STIFFNESS);
//! assert_eq!(
//!     err.unwrap_err().to_string(),
//!     "expected a stiffness unit (N/m), found kg"
//! );
//! ```
//!
//! Parsing never panics; any malformed text gives a [`UnitError`].

use std::f64::consts::PI;
use std::fmt::{self, Write as _};
use std::str::FromStr;

/// Two dimension exponents closer than this are equal.
const EXPONENT_TOLERANCE: f64 = 1e-9;

/// The physical dimension of a quantity: exponents of mass (kg), length (m)
/// and time (s).
///
/// Exponents are `f64` because a power-law coefficient such as daN/µm^1.5 has
/// a fractional one. Equality compares each exponent within 10⁻⁹ (so it is
/// not exactly transitive; exponents here are small rationals, far apart
/// compared with the tolerance).
#[derive(Debug, Clone, Copy)]
pub struct Dimension {
    /// Exponent of mass (kg).
    pub mass: f64,
    /// Exponent of length (m).
    pub length: f64,
    /// Exponent of time (s).
    pub time: f64,
}

impl Dimension {
    /// A pure number (also angles: rad, deg).
    pub const DIMENSIONLESS: Dimension = Dimension::new(0.0, 0.0, 0.0);
    /// Mass, kg.
    pub const MASS: Dimension = Dimension::new(1.0, 0.0, 0.0);
    /// Length, m.
    pub const LENGTH: Dimension = Dimension::new(0.0, 1.0, 0.0);
    /// Time, s.
    pub const TIME: Dimension = Dimension::new(0.0, 0.0, 1.0);
    /// Force, N = kg·m/s².
    pub const FORCE: Dimension = Dimension::new(1.0, 1.0, -2.0);
    /// Translational stiffness, N/m.
    pub const STIFFNESS: Dimension = Dimension::FORCE.div(Dimension::LENGTH);
    /// Translational damping, N·s/m.
    pub const DAMPING: Dimension = Dimension::STIFFNESS.mul(Dimension::TIME);
    /// Moment, N·m; also rotational stiffness N·m/rad, since angles are
    /// dimensionless.
    pub const MOMENT: Dimension = Dimension::FORCE.mul(Dimension::LENGTH);
    /// Rotational damping, N·m·s (N·m·s/rad).
    pub const ROTATIONAL_DAMPING: Dimension = Dimension::MOMENT.mul(Dimension::TIME);
    /// Moment of inertia, kg·m².
    pub const INERTIA: Dimension = Dimension::MASS.mul(Dimension::LENGTH.powf(2.0));
    /// Frequency, 1/s (Hz).
    pub const FREQUENCY: Dimension = Dimension::TIME.powf(-1.0);

    /// The dimension kg^mass · m^length · s^time.
    #[must_use]
    pub const fn new(mass: f64, length: f64, time: f64) -> Self {
        Dimension { mass, length, time }
    }

    /// The dimension of a product: exponents add.
    #[must_use]
    #[allow(clippy::should_implement_trait)] // inherent so that it is `const`
    pub const fn mul(self, other: Dimension) -> Dimension {
        Dimension::new(
            self.mass + other.mass,
            self.length + other.length,
            self.time + other.time,
        )
    }

    /// The dimension of a quotient: exponents subtract.
    #[must_use]
    #[allow(clippy::should_implement_trait)] // inherent so that it is `const`
    pub const fn div(self, other: Dimension) -> Dimension {
        Dimension::new(
            self.mass - other.mass,
            self.length - other.length,
            self.time - other.time,
        )
    }

    /// The dimension of a power: exponents are multiplied by `exponent`.
    #[must_use]
    pub const fn powf(self, exponent: f64) -> Dimension {
        Dimension::new(
            self.mass * exponent,
            self.length * exponent,
            self.time * exponent,
        )
    }

    /// Whether every exponent is zero (within 10⁻⁹).
    #[must_use]
    pub fn is_dimensionless(self) -> bool {
        self == Dimension::DIMENSIONLESS
    }

    /// The preferred symbol and the name of this dimension, if it is one of
    /// the named ones.
    fn named(self) -> Option<(&'static str, &'static str)> {
        NAMED
            .iter()
            .find(|n| n.0 == self)
            .map(|&(_, symbol, name)| (symbol, name))
    }
}

impl PartialEq for Dimension {
    fn eq(&self, other: &Self) -> bool {
        (self.mass - other.mass).abs() <= EXPONENT_TOLERANCE
            && (self.length - other.length).abs() <= EXPONENT_TOLERANCE
            && (self.time - other.time).abs() <= EXPONENT_TOLERANCE
    }
}

impl std::ops::Mul for Dimension {
    type Output = Dimension;
    fn mul(self, other: Dimension) -> Dimension {
        Dimension::mul(self, other)
    }
}

impl std::ops::Div for Dimension {
    type Output = Dimension;
    fn div(self, other: Dimension) -> Dimension {
        Dimension::div(self, other)
    }
}

/// Named dimensions (dimension, preferred symbol, name in messages);
/// [`Dimension`]'s `Display` prefers these symbols.
#[rustfmt::skip]
const NAMED: &[(Dimension, &str, &str)] = &[
    (Dimension::DIMENSIONLESS, "dimensionless", "dimensionless"),
    (Dimension::MASS, "kg", "mass"),
    (Dimension::LENGTH, "m", "length"),
    (Dimension::TIME, "s", "time"),
    (Dimension::FORCE, "N", "force"),
    (Dimension::STIFFNESS, "N/m", "stiffness"),
    (Dimension::DAMPING, "N·s/m", "damping"),
    (Dimension::MOMENT, "N·m", "moment or rotational stiffness"),
    (Dimension::ROTATIONAL_DAMPING, "N·m·s", "rotational damping"),
    (Dimension::INERTIA, "kg·m²", "moment of inertia"),
    (Dimension::FREQUENCY, "1/s", "frequency"),
];

/// Prints an SI form: a named symbol when there is one ("N/m", "N·s/m",
/// "kg·m²", "1/s", "dimensionless"), otherwise a product of N, kg, m and s
/// with `^` exponents and one `/` before each denominator factor ("N/m^2",
/// "N/m^1.5", "kg/m^3", "N/m/s", "1/m"), which [`parse_quantity`] reads
/// back, so a message may say which unit a field needs in this form.
///
/// N is used when both the mass and the time exponent are non-zero (so
/// kg/s² becomes N/m); otherwise kg (so kg·m² stays kg·m²).
impl fmt::Display for Dimension {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let Some((symbol, _)) = self.named() {
            return f.pad(symbol);
        }
        let nonzero = |e: f64| e.abs() > EXPONENT_TOLERANCE;
        // kg^a m^b s^c = N^a m^(b-a) s^(c+2a)
        let (newton, kg, m, s) = if nonzero(self.mass) && nonzero(self.time) {
            let a = self.mass;
            (a, 0.0, self.length - a, self.time + 2.0 * a)
        } else {
            (0.0, self.mass, self.length, self.time)
        };
        let factors = [("N", newton), ("kg", kg), ("m", m), ("s", s)];
        let mut out = String::new();
        for (symbol, e) in factors.iter().filter(|(_, e)| *e > EXPONENT_TOLERANCE) {
            if !out.is_empty() {
                out.push('·');
            }
            push_factor(&mut out, symbol, *e);
        }
        if out.is_empty() {
            out.push('1');
        }
        for (symbol, e) in factors.iter().filter(|(_, e)| *e < -EXPONENT_TOLERANCE) {
            out.push('/');
            push_factor(&mut out, symbol, -*e);
        }
        f.pad(&out)
    }
}

/// Appends `symbol` or `symbol^exponent`; a near-integer exponent is printed
/// as an integer.
fn push_factor(out: &mut String, symbol: &str, exponent: f64) {
    out.push_str(symbol);
    let rounded = exponent.round();
    if (exponent - rounded).abs() <= EXPONENT_TOLERANCE {
        if rounded != 1.0 {
            let _ = write!(out, "^{rounded}");
        }
    } else {
        let _ = write!(out, "^{exponent}");
    }
}

/// A physical quantity: a value in SI units and its dimension.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Quantity {
    /// The value in SI units (kg, m, s, N, rad).
    pub value: f64,
    /// The dimension of the value.
    pub dim: Dimension,
}

/// Prints the SI value followed by its unit, e.g. `150000000 N/m`; a
/// dimensionless value is printed alone.
impl fmt::Display for Quantity {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.dim.is_dimensionless() {
            write!(f, "{}", self.value)
        } else {
            write!(f, "{} {}", self.value, self.dim)
        }
    }
}

/// Same as [`parse_quantity`].
impl FromStr for Quantity {
    type Err = UnitError;
    fn from_str(text: &str) -> Result<Self, Self::Err> {
        parse_quantity(text)
    }
}

/// Every unit symbol understood by [`parse_quantity`]: (symbol, value of one
/// unit in SI, dimension). Symbols are case sensitive and purely alphabetic.
pub static UNITS: &[(&str, f64, Dimension)] = &[
    // length
    ("m", 1.0, Dimension::LENGTH),
    ("km", 1e3, Dimension::LENGTH),
    ("cm", 1e-2, Dimension::LENGTH),
    ("mm", 1e-3, Dimension::LENGTH),
    ("um", 1e-6, Dimension::LENGTH),
    ("µm", 1e-6, Dimension::LENGTH), // U+00B5 micro sign
    ("μm", 1e-6, Dimension::LENGTH), // U+03BC Greek small letter mu
    ("nm", 1e-9, Dimension::LENGTH),
    // mass
    ("g", 1e-3, Dimension::MASS),
    ("kg", 1.0, Dimension::MASS),
    ("t", 1e3, Dimension::MASS),
    // time
    ("s", 1.0, Dimension::TIME),
    ("ms", 1e-3, Dimension::TIME),
    ("us", 1e-6, Dimension::TIME),
    ("µs", 1e-6, Dimension::TIME),
    ("μs", 1e-6, Dimension::TIME),
    // force
    ("N", 1.0, Dimension::FORCE),
    ("mN", 1e-3, Dimension::FORCE),
    ("daN", 10.0, Dimension::FORCE),
    ("kN", 1e3, Dimension::FORCE),
    ("MN", 1e6, Dimension::FORCE),
    // frequency
    ("Hz", 1.0, Dimension::FREQUENCY),
    ("kHz", 1e3, Dimension::FREQUENCY),
    // angle (dimensionless)
    ("rad", 1.0, Dimension::DIMENSIONLESS),
    ("mrad", 1e-3, Dimension::DIMENSIONLESS),
    ("urad", 1e-6, Dimension::DIMENSIONLESS),
    ("µrad", 1e-6, Dimension::DIMENSIONLESS),
    ("μrad", 1e-6, Dimension::DIMENSIONLESS),
    ("deg", PI / 180.0, Dimension::DIMENSIONLESS),
];

/// Why a value with a unit could not be read, or has the wrong dimension.
///
/// `text` is the whole value as written (trimmed), for context.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
pub enum UnitError {
    /// The text is empty or only whitespace.
    #[error("empty value: expected a number, optionally followed by a unit")]
    Empty,
    /// The text does not start with a decimal number.
    #[error("\"{text}\" does not start with a number")]
    BadNumber {
        /// The text as written.
        text: String,
    },
    /// The number is written as NaN or infinity.
    #[error("\"{text}\" is not a finite number")]
    NotFinite {
        /// The text as written.
        text: String,
    },
    /// The number, or its conversion to SI, overflows (or a non-zero value
    /// underflows to zero) in 64-bit floating point.
    #[error("\"{text}\" is out of the range of 64-bit floating point in SI units")]
    OutOfRange {
        /// The text as written.
        text: String,
    },
    /// A unit symbol not in [`UNITS`].
    #[error(
        "unknown unit \"{unit}\" in \"{text}\"{}; known units: {}",
        case_hint(.unit),
        known_units()
    )]
    UnknownUnit {
        /// The unknown symbol.
        unit: String,
        /// The text as written.
        text: String,
    },
    /// A `^` (or `⁻`) not followed by a number.
    #[error("bad exponent in \"{text}\": expected a number such as 2, -1 or 1.5 after '^'")]
    BadExponent {
        /// The text as written.
        text: String,
    },
    /// An operator at the start or end of the unit, or two in a row.
    #[error("operator '{op}' in \"{text}\" is missing a unit on one side")]
    DanglingOperator {
        /// The operator: `*`, `·` or `/`.
        op: char,
        /// The text as written.
        text: String,
    },
    /// A character that cannot start a unit symbol or follow one.
    #[error("unexpected '{found}' in \"{text}\"; {}", unexpected_hint(*found, text))]
    UnexpectedChar {
        /// The offending character.
        found: char,
        /// The text as written.
        text: String,
    },
    /// A valid quantity whose dimension is not the one required.
    #[error("expected {}, found {}", describe_expected(.expected), describe_found(.found))]
    WrongDimension {
        /// The dimension of the value given.
        found: Dimension,
        /// The dimension required.
        expected: Dimension,
    },
}

/// `" (did you mean \"kN\"?)"` when `unit` matches known symbols but for case.
fn case_hint(unit: &str) -> String {
    let matches: Vec<&str> = UNITS
        .iter()
        .map(|u| u.0)
        .filter(|s| s.to_lowercase() == unit.to_lowercase())
        .collect();
    if matches.is_empty() {
        String::new()
    } else {
        format!(" (did you mean \"{}\"?)", matches.join("\" or \""))
    }
}

/// The ASCII unit symbols, comma separated, with a note on µ.
fn known_units() -> String {
    let ascii: Vec<&str> = UNITS.iter().map(|u| u.0).filter(|s| s.is_ascii()).collect();
    format!("{} (µ or μ may replace u)", ascii.join(", "))
}

fn describe_expected(expected: &Dimension) -> String {
    match expected.named() {
        Some((_, name)) if expected.is_dimensionless() => format!("a {name} value"),
        Some((symbol, name)) => format!("a {name} unit ({symbol})"),
        None => format!("a unit of {expected}"),
    }
}

fn describe_found(found: &Dimension) -> String {
    if found.is_dimensionless() {
        "a dimensionless value".to_string()
    } else {
        found.to_string()
    }
}

/// What to write instead of an unexpected character: a decimal comma
/// between digits (`20,5 N`) gets the decimal point, anything else how units
/// are joined.
fn unexpected_hint(found: char, text: &str) -> &'static str {
    let digits = |a: Option<char>, b: Option<char>| {
        a.is_some_and(|c| c.is_ascii_digit()) && b.is_some_and(|c| c.is_ascii_digit())
    };
    let decimal_comma = found == ','
        && text
            .char_indices()
            .filter(|&(_, c)| c == ',')
            .any(|(i, _)| digits(text[..i].chars().next_back(), text[i + 1..].chars().next()));
    match decimal_comma {
        true => "the decimal separator is a point: write 20.5, not 20,5",
        false => "units are joined by '*', '·' or '/'",
    }
}

/// Parses a number optionally followed by a unit expression (see the module
/// documentation for the grammar) into a [`Quantity`] in SI units.
///
/// A bare number is dimensionless and kept as is. Surrounding whitespace is
/// ignored. Never panics.
///
/// # Errors
///
/// A [`UnitError`] naming what is wrong: empty text, no leading number, NaN
/// or infinity, an unknown unit symbol, a bad exponent, a misplaced operator
/// or character, or a value out of `f64` range once converted to SI.
pub fn parse_quantity(text: &str) -> Result<Quantity, UnitError> {
    parse(text).map(|(quantity, _)| quantity)
}

/// Returns the SI value of `q` if its dimension is `expected`, otherwise
/// [`UnitError::WrongDimension`].
///
/// # Errors
///
/// [`UnitError::WrongDimension`] if `q.dim` differs from `expected`.
pub fn expect_dimension(q: Quantity, expected: Dimension) -> Result<f64, UnitError> {
    if q.dim == expected {
        Ok(q.value)
    } else {
        Err(UnitError::WrongDimension {
            found: q.dim,
            expected,
        })
    }
}

/// Parses `text` as a value of dimension `expected` and returns it in SI.
///
/// Unlike [`parse_quantity`] followed by [`expect_dimension`], a bare number
/// (no unit at all) is taken to be already in SI units of `expected`, as model
/// files allow; `"20 deg"` is still only accepted where a dimensionless value
/// is expected.
///
/// # Errors
///
/// Those of [`parse_quantity`], and [`UnitError::WrongDimension`] if a unit
/// is written and its dimension is not `expected`.
pub fn parse_as(text: &str, expected: Dimension) -> Result<f64, UnitError> {
    match parse(text)? {
        (q, false) => Ok(q.value),
        (q, true) => expect_dimension(q, expected),
    }
}

/// Parses `text`; the flag tells whether a unit was written.
fn parse(text: &str) -> Result<(Quantity, bool), UnitError> {
    let text = text.trim();
    if text.is_empty() {
        return Err(UnitError::Empty);
    }
    let (number, rest) = split_number(text)?;
    let value: f64 = number.parse().map_err(|_| UnitError::BadNumber {
        text: text.to_string(),
    })?;
    let out_of_range = || UnitError::OutOfRange {
        text: text.to_string(),
    };
    if !value.is_finite() {
        return Err(out_of_range());
    }
    let rest = rest.trim_start();
    if rest.is_empty() {
        let q = Quantity {
            value,
            dim: Dimension::DIMENSIONLESS,
        };
        return Ok((q, false));
    }
    let (scale, dim) = parse_unit(rest, text)?;
    let finite_dim = dim.mass.is_finite() && dim.length.is_finite() && dim.time.is_finite();
    if !(scale.is_finite() && scale > 0.0 && finite_dim) {
        return Err(out_of_range());
    }
    let si = value * scale;
    if !si.is_finite() || (si == 0.0 && value != 0.0) {
        return Err(out_of_range());
    }
    Ok((Quantity { value: si, dim }, true))
}

/// Splits `text` (trimmed, non-empty) into its leading decimal number and
/// the rest.
fn split_number(text: &str) -> Result<(&str, &str), UnitError> {
    let bytes = text.as_bytes();
    let digits_from = |mut i: usize| {
        while i < bytes.len() && bytes[i].is_ascii_digit() {
            i += 1;
        }
        i
    };
    let bad = || UnitError::BadNumber {
        text: text.to_string(),
    };
    let mut i = 0;
    if matches!(bytes.first(), Some(b'+' | b'-')) {
        i = 1;
    }
    // Only ASCII bytes are consumed, so every index used to slice is a char
    // boundary.
    let word: String = text[i..]
        .chars()
        .take_while(|c| c.is_alphabetic())
        .collect();
    if ["nan", "inf", "infinity"].contains(&word.to_lowercase().as_str()) {
        return Err(UnitError::NotFinite {
            text: text.to_string(),
        });
    }
    let int_end = digits_from(i);
    let mut end = int_end;
    let mut n_digits = int_end - i;
    if bytes.get(end) == Some(&b'.') {
        let frac_end = digits_from(end + 1);
        n_digits += frac_end - (end + 1);
        end = frac_end;
    }
    if n_digits == 0 {
        return Err(bad());
    }
    if matches!(bytes.get(end), Some(b'e' | b'E')) {
        let mut j = end + 1;
        if matches!(bytes.get(j), Some(b'+' | b'-')) {
            j += 1;
        }
        let exp_end = digits_from(j);
        if exp_end == j {
            return Err(bad());
        }
        end = exp_end;
    }
    Ok((&text[..end], &text[end..]))
}

/// A position in a unit expression.
struct Cursor<'a> {
    s: &'a str,
    pos: usize,
}

impl<'a> Cursor<'a> {
    fn peek(&self) -> Option<char> {
        self.s[self.pos..].chars().next()
    }

    fn bump(&mut self) {
        if let Some(c) = self.peek() {
            self.pos += c.len_utf8();
        }
    }

    fn skip_whitespace(&mut self) {
        while self.peek().is_some_and(char::is_whitespace) {
            self.bump();
        }
    }

    /// Consumes characters while `pred` holds and returns them.
    fn take_while(&mut self, pred: impl Fn(char) -> bool) -> &'a str {
        let start = self.pos;
        while self.peek().is_some_and(&pred) {
            self.bump();
        }
        &self.s[start..self.pos]
    }
}

/// Parses a unit expression into (SI value of one unit, dimension). `text`
/// is the whole input, for error messages.
fn parse_unit(expr: &str, text: &str) -> Result<(f64, Dimension), UnitError> {
    let mut cursor = Cursor { s: expr, pos: 0 };
    let mut scale = 1.0;
    let mut dim = Dimension::DIMENSIONLESS;
    // A leading `1/` (a reciprocal unit, `1/m`) divides by what follows.
    let mut op = reciprocal(&mut cursor);
    loop {
        cursor.skip_whitespace();
        let (factor_scale, factor_dim) = parse_factor(&mut cursor, op, text)?;
        if op == Some('/') {
            scale /= factor_scale;
            dim = dim.div(factor_dim);
        } else {
            scale *= factor_scale;
            dim = dim.mul(factor_dim);
        }
        cursor.skip_whitespace();
        match cursor.peek() {
            None => return Ok((scale, dim)),
            Some(c @ ('*' | '·' | '/')) => {
                cursor.bump();
                op = Some(c);
            }
            Some(c) => {
                return Err(UnitError::UnexpectedChar {
                    found: c,
                    text: text.to_string(),
                })
            }
        }
    }
}

/// Consumes a leading `1` followed by `/` (whitespace allowed between
/// them) and returns the `/`; consumes nothing otherwise.
fn reciprocal(cursor: &mut Cursor<'_>) -> Option<char> {
    let rest = cursor.s[cursor.pos..].strip_prefix('1')?;
    let after_space = rest.trim_start();
    after_space.strip_prefix('/')?;
    cursor.pos = cursor.s.len() - after_space.len() + 1;
    Some('/')
}

/// Parses `symbol [^ exponent | superscript]` into (SI scale, dimension),
/// the exponent applied. `op` is the operator before it, if any.
fn parse_factor(
    cursor: &mut Cursor<'_>,
    op: Option<char>,
    text: &str,
) -> Result<(f64, Dimension), UnitError> {
    let symbol = cursor.take_while(char::is_alphabetic);
    if symbol.is_empty() {
        return Err(match (cursor.peek(), op) {
            (Some(c @ ('*' | '·' | '/')), _) | (None, Some(c)) => UnitError::DanglingOperator {
                op: c,
                text: text.to_string(),
            },
            (Some(c), _) => UnitError::UnexpectedChar {
                found: c,
                text: text.to_string(),
            },
            (None, None) => UnitError::Empty,
        });
    }
    let Some(&(_, scale, dim)) = UNITS.iter().find(|u| u.0 == symbol) else {
        return Err(UnitError::UnknownUnit {
            unit: symbol.to_string(),
            text: text.to_string(),
        });
    };
    match parse_exponent(cursor, text)? {
        None => Ok((scale, dim)),
        Some(e) => Ok((scale.powf(e), dim.powf(e))),
    }
}

/// Parses an optional `^ exponent` or superscript exponent after a symbol.
fn parse_exponent(cursor: &mut Cursor<'_>, text: &str) -> Result<Option<f64>, UnitError> {
    let bad = || UnitError::BadExponent {
        text: text.to_string(),
    };
    // Superscript form, directly after the symbol: m², s⁻¹.
    if cursor
        .peek()
        .is_some_and(|c| c == '⁻' || superscript_digit(c).is_some())
    {
        let mut digits = String::new();
        if cursor.peek() == Some('⁻') {
            cursor.bump();
            digits.push('-');
        }
        while let Some(d) = cursor.peek().and_then(superscript_digit) {
            cursor.bump();
            digits.push(d);
        }
        return parse_exponent_digits(&digits).map(Some).ok_or_else(bad);
    }
    let before = cursor.pos;
    cursor.skip_whitespace();
    if cursor.peek() != Some('^') {
        cursor.pos = before;
        return Ok(None);
    }
    cursor.bump();
    cursor.skip_whitespace();
    let mut digits = String::new();
    match cursor.peek() {
        Some('-' | '−') => {
            cursor.bump();
            digits.push('-');
        }
        Some('+') => cursor.bump(),
        _ => {}
    }
    digits.push_str(cursor.take_while(|c| c.is_ascii_digit()));
    if cursor.peek() == Some('.') {
        cursor.bump();
        let fraction = cursor.take_while(|c| c.is_ascii_digit());
        if fraction.is_empty() {
            return Err(bad());
        }
        digits.push('.');
        digits.push_str(fraction);
    }
    parse_exponent_digits(&digits).map(Some).ok_or_else(bad)
}

/// `[-]digits[.digits]` as a finite `f64`; `None` if there are no digits.
fn parse_exponent_digits(digits: &str) -> Option<f64> {
    if !digits.bytes().any(|b| b.is_ascii_digit()) {
        return None;
    }
    digits.parse::<f64>().ok().filter(|e| e.is_finite())
}

/// The ASCII digit for a superscript digit.
fn superscript_digit(c: char) -> Option<char> {
    match c {
        '⁰' => Some('0'),
        '¹' => Some('1'),
        '²' => Some('2'),
        '³' => Some('3'),
        '⁴'..='⁹' => char::from_digit(c as u32 - '⁴' as u32 + 4, 10),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;
    use proptest::test_runner::{Config, RngSeed};

    /// Fixed seed, no regression files: the same cases on every run.
    fn config(seed: u64) -> Config {
        Config {
            cases: 512,
            rng_seed: RngSeed::Fixed(seed),
            failure_persistence: None,
            ..Config::default()
        }
    }

    fn close(a: f64, b: f64, rel: f64) -> bool {
        (a - b).abs() <= rel * a.abs().max(b.abs())
    }

    #[track_caller]
    fn check(text: &str, value: f64, dim: Dimension) {
        let q = parse_quantity(text).unwrap_or_else(|e| panic!("{text:?}: {e}"));
        assert!(
            close(q.value, value, 1e-14),
            "{text:?}: {} != {value}",
            q.value
        );
        assert_eq!(q.dim, dim, "{text:?}");
    }

    fn err(text: &str) -> UnitError {
        parse_quantity(text).expect_err(text)
    }

    #[test]
    fn exact_examples() {
        use Dimension as D;
        check(
            "380 daN/um^2",
            380.0 * 10.0 / 1e-12,
            D::FORCE.div(D::LENGTH.powf(2.0)),
        );
        check("380 daN/um^2", 3.8e15, D::new(1.0, -1.0, -2.0));
        check("2.1 daN*ms/um", 2.1e4, D::DAMPING);
        check("3.6 daN·ms/µm", 3.6e4, D::DAMPING);
        check("3.6 daN · ms / μm", 3.6e4, D::DAMPING);
        check("15 daN/um", 1.5e8, D::STIFFNESS);
        check("1 kN", 1000.0, D::FORCE);
        check("25 mm", 0.025, D::LENGTH);
        check("25mm", 0.025, D::LENGTH);
        check("  25 mm\t", 0.025, D::LENGTH);
        check("20 deg", 20.0 * PI / 180.0, D::DIMENSIONLESS);
        check("1000", 1000.0, D::DIMENSIONLESS);
        check("1e-3 m", 1e-3, D::LENGTH);
        check("-4.5e2 N*m/rad", -450.0, D::MOMENT);
        check("9.81 m/s^2", 9.81, D::new(0.0, 1.0, -2.0));
        check("2 kg*m^2", 2.0, D::INERTIA);
        check("2 kg·m²", 2.0, D::INERTIA);
        check("80 Hz", 80.0, D::FREQUENCY);
        check("80 s^-1", 80.0, D::FREQUENCY);
        check("80 s⁻¹", 80.0, D::FREQUENCY);
        check("80 s^−1", 80.0, D::FREQUENCY);
        check("0.3 s", 0.3, D::TIME);
        check(".5 m", 0.5, D::LENGTH);
        check("5. m", 5.0, D::LENGTH);
        check("5.E+1m", 50.0, D::LENGTH);
        check("+2 t", 2000.0, D::MASS);
        check("5 g", 5e-3, D::MASS);
        check("1 N/m/s", 1.0, D::new(1.0, 0.0, -3.0));
        check("1 kN*m/rad*s", 1000.0, D::ROTATIONAL_DAMPING);
        check("3 mrad", 3e-3, D::DIMENSIONLESS);
        check("1.5 kHz", 1500.0, D::FREQUENCY);
        check("2 ms ^ 2", 2e-6, D::TIME.powf(2.0));
        let power_law = D::FORCE.div(D::LENGTH.powf(1.5));
        check("7 daN/um^1.5", 7.0 * 10.0 / 1e-9, power_law);
        // Reciprocal units: a leading `1/`.
        check("1e3 1/m", 1e3, D::LENGTH.powf(-1.0));
        check("1e3 1 / mm", 1e6, D::LENGTH.powf(-1.0));
        check("2 1/s", 2.0, D::FREQUENCY);
        check(
            "4 1/kN^0.5/m",
            4.0 / 1e3f64.sqrt(),
            D::FORCE.powf(-0.5).div(D::LENGTH),
        );
        assert_eq!(power_law.length, -0.5);
    }

    #[test]
    fn every_table_entry_parses_to_itself() {
        for &(symbol, scale, dim) in UNITS {
            assert!(symbol.chars().all(char::is_alphabetic), "{symbol}");
            let q = parse_quantity(&format!("1 {symbol}")).unwrap();
            assert_eq!((q.value, q.dim), (scale, dim), "{symbol}");
            let same = UNITS.iter().filter(|u| u.0 == symbol).count();
            assert_eq!(same, 1, "{symbol} listed twice");
        }
    }

    /// The variant of an error and the text it quotes, if any.
    fn kind(e: &UnitError) -> (&'static str, Option<&str>) {
        match e {
            UnitError::Empty => ("Empty", None),
            UnitError::BadNumber { text } => ("BadNumber", Some(text)),
            UnitError::NotFinite { text } => ("NotFinite", Some(text)),
            UnitError::OutOfRange { text } => ("OutOfRange", Some(text)),
            UnitError::UnknownUnit { text, .. } => ("UnknownUnit", Some(text)),
            UnitError::BadExponent { text } => ("BadExponent", Some(text)),
            UnitError::DanglingOperator { text, .. } => ("DanglingOperator", Some(text)),
            UnitError::UnexpectedChar { text, .. } => ("UnexpectedChar", Some(text)),
            UnitError::WrongDimension { .. } => ("WrongDimension", None),
        }
    }

    #[test]
    fn errors() {
        let cases = [
            ("", "Empty"),
            ("  \t", "Empty"),
            ("abc", "BadNumber"),
            ("N", "BadNumber"),
            ("- 1 N", "BadNumber"),
            (".e3", "BadNumber"),
            ("2e m", "BadNumber"),
            ("1 furlong", "UnknownUnit"),
            ("1 Mm", "UnknownUnit"),
            ("1 µ m", "UnknownUnit"),
            ("1 N/", "DanglingOperator"),
            ("1 N*/m", "DanglingOperator"),
            ("1 /m", "DanglingOperator"),
            ("1 1/", "DanglingOperator"),
            ("1 10/m", "UnexpectedChar"),
            ("1 1*m", "UnexpectedChar"),
            ("1 N ·", "DanglingOperator"),
            ("1 N^", "BadExponent"),
            ("1 N^x", "BadExponent"),
            ("1 N^-", "BadExponent"),
            ("1 m^2.", "BadExponent"),
            ("1 m⁻", "BadExponent"),
            ("1 N m", "UnexpectedChar"),
            ("1,5 N", "UnexpectedChar"),
            ("1 m2", "UnexpectedChar"),
            ("1 m^2^2", "UnexpectedChar"),
            ("1 (N/m)", "UnexpectedChar"),
            ("nan m", "NotFinite"),
            ("inf N", "NotFinite"),
            ("-Infinity", "NotFinite"),
            ("1e999", "OutOfRange"),
            ("1e300 MN/nm^2", "OutOfRange"),
            ("1e-300 nm^10", "OutOfRange"),
            ("1 km^400/km^400", "OutOfRange"),
        ];
        for (input, variant) in cases {
            let e = err(input);
            let (found, quoted) = kind(&e);
            assert_eq!(found, variant, "{input:?}: {e:?}");
            if let Some(quoted) = quoted {
                assert_eq!(quoted, input.trim(), "{input:?}");
            }
        }
        // A decimal comma gets the decimal point as its hint; other
        // unexpected characters, how units are joined.
        assert!(err("20,5 N").to_string().contains("write 20.5, not 20,5"));
        assert!(err("1 N m").to_string().contains("units are joined by"));
        assert!(err("1 N, m").to_string().contains("units are joined by"));
        let unit = |e| match e {
            UnitError::UnknownUnit { unit, .. } => unit,
            e => panic!("{e:?}"),
        };
        assert_eq!(unit(err("1 N*furlong/s")), "furlong");
        assert!(matches!(
            err("1 N*/m"),
            UnitError::DanglingOperator { op: '/', .. }
        ));
        assert!(matches!(
            err("1 N ·"),
            UnitError::DanglingOperator { op: '·', .. }
        ));
        assert!(matches!(
            err("1 m2"),
            UnitError::UnexpectedChar { found: '2', .. }
        ));
    }

    #[test]
    fn wrong_dimension() {
        let kg = parse_quantity("3 kg").unwrap();
        let e = expect_dimension(kg, Dimension::STIFFNESS).unwrap_err();
        assert_eq!(
            e,
            UnitError::WrongDimension {
                found: Dimension::MASS,
                expected: Dimension::STIFFNESS
            }
        );
        assert_eq!(e.to_string(), "expected a stiffness unit (N/m), found kg");
        assert_eq!(expect_dimension(kg, Dimension::MASS), Ok(3.0));

        let e = expect_dimension(parse_quantity("3").unwrap(), Dimension::DAMPING).unwrap_err();
        assert_eq!(
            e.to_string(),
            "expected a damping unit (N·s/m), found a dimensionless value"
        );
        let e = expect_dimension(kg, Dimension::DIMENSIONLESS).unwrap_err();
        assert_eq!(e.to_string(), "expected a dimensionless value, found kg");
        let coefficient = Dimension::FORCE.div(Dimension::LENGTH.powf(2.0));
        let e = expect_dimension(kg, coefficient).unwrap_err();
        assert_eq!(e.to_string(), "expected a unit of N/m^2, found kg");
    }

    #[test]
    fn parse_as_takes_bare_numbers_as_si() {
        assert_eq!(parse_as("1000", Dimension::STIFFNESS), Ok(1000.0));
        assert!(close(
            parse_as("15 daN/um", Dimension::STIFFNESS).unwrap(),
            1.5e8,
            1e-14
        ));
        assert!(parse_as("20 deg", Dimension::DIMENSIONLESS).is_ok());
        assert!(matches!(
            parse_as("20 deg", Dimension::MOMENT),
            Err(UnitError::WrongDimension { .. })
        ));
        assert_eq!(
            parse_as("x", Dimension::MASS),
            Err(UnitError::BadNumber { text: "x".into() })
        );
    }

    #[test]
    fn messages() {
        let msg = err("1 furlong").to_string();
        assert!(msg.starts_with("unknown unit \"furlong\" in \"1 furlong\"; known units: m, km"));
        assert!(
            msg.contains("daN") && msg.contains("deg") && msg.contains("µ"),
            "{msg}"
        );
        let msg = err("1 KN").to_string();
        assert!(msg.contains("(did you mean \"kN\"?)"), "{msg}");
        let msg = err("1 mn").to_string();
        assert!(msg.contains("(did you mean \"mN\" or \"MN\"?)"), "{msg}");
        // Lowercase, no trailing period.
        let samples = ["", "abc", "nan", "1e999", "1 N^", "1 N/", "1 N m", "1 Mm"];
        for s in samples {
            let msg = err(s).to_string();
            assert!(!msg.ends_with('.'), "{msg}");
            assert!(!msg.starts_with(char::is_uppercase), "{msg}");
        }
    }

    #[test]
    fn display() {
        use Dimension as D;
        let cases = [
            (D::DIMENSIONLESS, "dimensionless"),
            (D::MASS, "kg"),
            (D::LENGTH, "m"),
            (D::TIME, "s"),
            (D::FORCE, "N"),
            (D::STIFFNESS, "N/m"),
            (D::DAMPING, "N·s/m"),
            (D::MOMENT, "N·m"),
            (D::ROTATIONAL_DAMPING, "N·m·s"),
            (D::INERTIA, "kg·m²"),
            (D::FREQUENCY, "1/s"),
            (D::FORCE.div(D::LENGTH.powf(2.0)), "N/m^2"),
            (D::FORCE.div(D::LENGTH.powf(1.5)), "N/m^1.5"),
            (D::new(0.0, 1.0, -2.0), "m/s^2"),
            (D::new(1.0, -3.0, 0.0), "kg/m^3"),
            (D::new(1.0, 0.0, -3.0), "N/m/s"),
            (D::new(0.0, -1.0, -1.0), "1/m/s"),
            (D::new(-1.0, 0.0, 2.0), "m/N"),
            (D::new(1.0, 1.0 + 1e-12, -2.0), "N"),
        ];
        for (dim, text) in cases {
            assert_eq!(dim.to_string(), text, "{dim:?}");
        }
        assert_eq!(format!("{:>5}", D::STIFFNESS), "  N/m");
        // Every form printed reads back as its dimension.
        let bouc_wen_beta = D::FORCE.powf(-0.5).div(D::LENGTH);
        assert_eq!(bouc_wen_beta.to_string(), "1/N^0.5/m");
        let printed = cases.iter().map(|(dim, _)| *dim).chain([bouc_wen_beta]);
        for dim in printed.filter(|d| !d.is_dimensionless()) {
            let q = parse_quantity(&format!("2 {dim}")).unwrap_or_else(|e| panic!("{dim}: {e}"));
            assert_eq!(q.dim, dim, "{dim}");
        }
        let q = parse_quantity("15 daN/um").unwrap();
        assert_eq!(q.to_string(), "150000000 N/m");
        assert_eq!(parse_quantity("1000").unwrap().to_string(), "1000");
        assert_eq!("1 kN".parse::<Quantity>(), parse_quantity("1 kN"));
    }

    #[test]
    fn dimension_algebra() {
        use Dimension as D;
        assert_eq!(D::STIFFNESS * D::TIME, D::DAMPING);
        assert_eq!(D::MOMENT / D::LENGTH, D::FORCE);
        assert_eq!(D::FREQUENCY.powf(-1.0), D::TIME);
        assert_ne!(D::STIFFNESS, D::DAMPING);
        assert_eq!(D::new(1.0, 2.0, 3.0), D::new(1.0 + 5e-10, 2.0, 3.0 - 5e-10));
        assert_ne!(D::new(1.0, 2.0, 3.0), D::new(1.0 + 2e-9, 2.0, 3.0));
        assert!(D::new(0.0, 1e-12, 0.0).is_dimensionless());
    }

    /// Unit symbols, each with the value of one unit in SI written
    /// independently of [`UNITS`].
    const FAMILIES: &[(&str, &str, f64)] = &[
        ("kN", "N", 1e3),
        ("MN", "N", 1e6),
        ("daN", "N", 10.0),
        ("mN", "N", 1e-3),
        ("km", "m", 1e3),
        ("cm", "m", 1e-2),
        ("mm", "m", 1e-3),
        ("um", "m", 1e-6),
        ("µm", "um", 1.0),
        ("μm", "um", 1.0),
        ("nm", "m", 1e-9),
        ("kg", "g", 1e3),
        ("t", "kg", 1e3),
        ("ms", "s", 1e-3),
        ("us", "s", 1e-6),
        ("µs", "us", 1.0),
        ("μs", "us", 1.0),
        ("kHz", "Hz", 1e3),
        ("mrad", "rad", 1e-3),
        ("urad", "rad", 1e-6),
        ("deg", "rad", PI / 180.0),
        ("daN/um^2", "N/m^2", 1e13),
        ("daN*ms/um", "N*s/m", 1e4),
    ];

    fn moderate() -> impl Strategy<Value = f64> {
        prop_oneof![
            Just(0.0),
            prop::num::f64::NORMAL.prop_filter("moderate", |x| (1e-250..1e250).contains(&x.abs())),
        ]
    }

    fn symbol() -> impl Strategy<Value = &'static str> {
        prop::sample::select(UNITS.iter().map(|u| u.0).collect::<Vec<_>>())
    }

    /// A symbol with an optional exponent, and the exponent (1 if none).
    fn factor() -> impl Strategy<Value = (String, f64)> {
        let exponents = [
            "", "^2", "^-1", "^3", "^-2", "^0.5", "^1.5", "^-1.5", "²", "³", "⁻¹",
        ];
        let values = [1.0, 2.0, -1.0, 3.0, -2.0, 0.5, 1.5, -1.5, 2.0, 3.0, -1.0];
        (symbol(), 0..exponents.len())
            .prop_map(move |(s, i)| (format!("{s}{}", exponents[i]), values[i]))
    }

    fn unit_of(symbol_with_exponent: &str) -> Quantity {
        parse_quantity(&format!("1 {symbol_with_exponent}")).unwrap()
    }

    proptest! {
        #![proptest_config(config(0x5eed_0001))]

        #[test]
        fn scaling_is_consistent(x in moderate(), family in 0..FAMILIES.len()) {
            let (big, small, ratio) = FAMILIES[family];
            let a = parse_quantity(&format!("{x:e} {big}")).unwrap();
            let b = parse_quantity(&format!("{x} {small}")).unwrap();
            prop_assert!(close(a.value, ratio * b.value, 1e-12), "{x} {big}: {} vs {}", a.value, b.value);
            prop_assert_eq!(a.dim, b.dim);
        }

        #[test]
        fn dimensions_compose(
            (a, ea) in factor(),
            (b, _) in factor(),
            (c, _) in factor(),
        ) {
            let (qa, qb, qc) = (unit_of(&a), unit_of(&b), unit_of(&c));
            let cases = [
                (format!("{a}/{b}"), qa.dim.div(qb.dim), qa.value / qb.value),
                (format!("{a}*{b}"), qa.dim.mul(qb.dim), qa.value * qb.value),
                (format!("{a} · {b}"), qa.dim.mul(qb.dim), qa.value * qb.value),
                (format!("{a}/{b}/{c}"), qa.dim.div(qb.dim).div(qc.dim), qa.value / qb.value / qc.value),
                (format!("{a}*{b}/{c}"), qa.dim.mul(qb.dim).div(qc.dim), qa.value * qb.value / qc.value),
                (format!("{a}/{b}*{c}"), qa.dim.div(qb.dim).mul(qc.dim), qa.value / qb.value * qc.value),
            ];
            for (expr, dim, value) in cases {
                let q = unit_of(&expr);
                prop_assert_eq!(q.dim, dim, "{}", expr);
                prop_assert!(close(q.value, value, 1e-13), "{}: {} vs {}", expr, q.value, value);
            }
            // The exponent is applied to the symbol's dimension.
            let bare: String = a.chars().take_while(|ch| ch.is_alphabetic()).collect();
            prop_assert_eq!(qa.dim, unit_of(&bare).dim.powf(ea));
        }

        #[test]
        fn display_reads_back(
            factors in prop::collection::vec((factor(), prop::bool::ANY), 1..4),
        ) {
            let mut expr = String::new();
            for (i, ((f, _), divide)) in factors.iter().enumerate() {
                if i > 0 {
                    expr.push(if *divide { '/' } else { '*' });
                }
                expr.push_str(f);
            }
            let dim = unit_of(&expr).dim;
            let shown = dim.to_string();
            if !dim.is_dimensionless() && !shown.starts_with("1/") {
                let back = unit_of(&shown);
                prop_assert_eq!(back.dim, dim, "{} shown as {}", expr, shown);
                prop_assert!(close(back.value, 1.0, 1e-15), "{}", shown);
            }
        }

        #[test]
        fn bare_numbers_round_trip(x in any::<f64>().prop_filter("finite", |x| x.is_finite())) {
            for text in [format!("{x:e}"), format!("{x}"), format!(" {x:E}\n")] {
                let q = parse_quantity(&text).unwrap();
                prop_assert_eq!(q.value.to_bits(), x.to_bits(), "{}", text);
                prop_assert!(q.dim.is_dimensionless());
            }
        }

        #[test]
        fn arbitrary_text_never_panics(text in any::<String>()) {
            let _ = parse_quantity(&text);
        }

        #[test]
        fn unit_like_text_never_panics(
            tokens in prop::collection::vec(prop::sample::select(vec![
                "1", "2.5", "-", "+", ".", "e", "E", "3", " ", "^", "*", "/", "·", "²", "⁻", "³",
                "m", "um", "µm", "μ", "daN", "N", "kg", "s", "Hz", "deg", "rad", "nan", "inf",
                "x", "(", ")", "−", "9999", "e400", "\u{0}", "é",
            ]), 0..12),
        ) {
            let text = tokens.concat();
            if let Ok(q) = parse_quantity(&text) {
                prop_assert!(q.value.is_finite(), "{}", text);
                prop_assert!(q.dim.mass.is_finite() && q.dim.length.is_finite() && q.dim.time.is_finite());
            }
        }

        #[test]
        fn regex_text_never_panics(text in "[0-9 .eE+\\-^*/·µμmkgsNdaHzrt²⁻x]{0,24}") {
            let _ = parse_quantity(&text);
        }
    }
}
