//! Numbers and units as a person reads them.

/// `v` with `digits` significant digits; exponent notation (`1.23×10⁻⁵`)
/// only outside 10⁻³ ≤ |v| < 10⁶.
pub(crate) fn sig(v: f64, digits: usize) -> String {
    if v.is_nan() {
        return "NaN".into();
    }
    if v.is_infinite() {
        return if v > 0.0 {
            "∞".into()
        } else {
            "−∞".into()
        };
    }
    if v == 0.0 {
        return "0".into();
    }
    let digits = digits.max(1);
    let mag = v.abs().log10().floor() as i32;
    let text = if (-3..6).contains(&mag) {
        let decimals = (digits as i32 - 1 - mag).max(0) as usize;
        format!("{v:.decimals$}")
    } else {
        let s = format!("{v:.prec$e}", prec = digits - 1);
        match s.split_once('e') {
            Some((mantissa, exp)) => {
                let exp: i32 = exp.parse().unwrap_or(0);
                format!("{mantissa}×10{}", superscript(exp))
            }
            None => s,
        }
    };
    minus(&text)
}

/// Like [`sig`], without trailing zeros after the decimal point
/// (`2`, `0.8`, `900`), for values that are given rather than estimated.
pub(crate) fn short(v: f64, digits: usize) -> String {
    let s = sig(v, digits);
    if s.contains('.') && !s.contains('×') {
        s.trim_end_matches('0').trim_end_matches('.').to_owned()
    } else {
        s
    }
}

/// Replaces ASCII hyphen-minus by the typographic minus sign.
pub(crate) fn minus(text: &str) -> String {
    text.replace('-', "−")
}

/// An integer in Unicode superscript digits, e.g. `10⁻³`'s `⁻³`.
pub(crate) fn superscript(n: i32) -> String {
    const DIGITS: [char; 10] = ['⁰', '¹', '²', '³', '⁴', '⁵', '⁶', '⁷', '⁸', '⁹'];
    let mut out = String::new();
    if n < 0 {
        out.push('⁻');
    }
    for ch in n.unsigned_abs().to_string().chars() {
        out.push(DIGITS[ch.to_digit(10).unwrap_or(0) as usize]);
    }
    out
}

/// A unit symbol as written in a model file (`daN*ms/um^2`), typeset
/// (`daN·ms/µm²`). Empty stays empty.
pub(crate) fn unit(symbol: &str) -> String {
    let mut out = String::new();
    let mut token = String::new();
    let flush = |token: &mut String, out: &mut String| {
        match token.as_str() {
            "um" => out.push_str("µm"),
            "us" => out.push_str("µs"),
            "ohm" => out.push('Ω'),
            t => out.push_str(t),
        }
        token.clear();
    };
    let mut chars = symbol.chars().peekable();
    while let Some(ch) = chars.next() {
        match ch {
            '*' => {
                flush(&mut token, &mut out);
                out.push('·');
            }
            '/' | ' ' | '(' | ')' => {
                flush(&mut token, &mut out);
                out.push(ch);
            }
            '^' => {
                flush(&mut token, &mut out);
                let mut exp = String::new();
                while let Some(&c) = chars.peek() {
                    if c.is_ascii_digit() || (exp.is_empty() && c == '-') {
                        exp.push(c);
                        chars.next();
                    } else {
                        break;
                    }
                }
                match exp.parse::<i32>() {
                    Ok(e) => out.push_str(&superscript(e)),
                    Err(_) => {
                        out.push('^');
                        out.push_str(&exp);
                    }
                }
            }
            c => token.push(c),
        }
    }
    flush(&mut token, &mut out);
    out
}

/// Seconds, to a sensible precision.
pub(crate) fn seconds(t: f64) -> String {
    if t < 1e-3 {
        format!("{} µs", sig(t * 1e6, 3))
    } else if t < 1.0 {
        format!("{} ms", sig(t * 1e3, 3))
    } else {
        format!("{} s", sig(t, 3))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn significant_digits_and_exponents() {
        assert_eq!(sig(380.0, 4), "380.0");
        assert_eq!(sig(0.0123456, 3), "0.0123");
        assert_eq!(sig(-1.5e-5, 2), "−1.5×10⁻⁵");
        assert_eq!(sig(3.8e9, 3), "3.80×10⁹");
        assert_eq!(sig(0.0, 3), "0");
        assert_eq!(short(2.0, 4), "2");
        assert_eq!(short(0.8, 3), "0.8");
        assert_eq!(short(-0.26, 3), "−0.26");
        assert_eq!(short(2.5e7, 3), "2.50×10⁷");
    }

    #[test]
    fn units_are_typeset() {
        assert_eq!(unit("daN/um^2"), "daN/µm²");
        assert_eq!(unit("daN*ms/um"), "daN·ms/µm");
        assert_eq!(unit("m/s^2"), "m/s²");
        assert_eq!(unit("s^-1"), "s⁻¹");
        assert_eq!(unit(""), "");
        assert_eq!(unit("kum"), "kum");
    }
}
