//! The universal-file reader against files written by pyuff (dataset 58,
//! ASCII and binary 58b, with datasets 151 and 164 to skip): the same
//! numbers as the CSV, bit for bit, and errors that name the file, the
//! record and the line for truncated, mistyped, complex or garbage input.
use crate::import_common;

use import_common::*;
use rfeid::io::uff::{parse_uff58, read_uff58, Abscissa, OrdinateType, UffError};
use rfeid::model::RecordRef;
use std::path::Path;

fn bits(v: &[f64]) -> Vec<u64> {
    v.iter().map(|x| x.to_bits()).collect()
}

#[test]
fn ascii_and_binary_records_hold_the_csv_numbers_bit_for_bit() {
    let csv = reference();
    for (file, binary) in [("signals_ascii.uff", false), ("signals_binary.uff", true)] {
        let uff = read_uff58(&fixture(file)).unwrap_or_else(|e| panic!("{e}"));
        for (i, name) in ["disp_x", "vel_x", "acc_x"].into_iter().enumerate() {
            let r = uff.record(i + 1).unwrap();
            assert_eq!(r.name(), name);
            assert_eq!(r.number, i + 1, "datasets 151/164 are not counted");
            assert_eq!(r.binary, binary);
            assert_eq!(r.ordinate_type, OrdinateType::RealDouble);
            assert_eq!(r.function_type, 1);
            assert_eq!((r.response_node, r.response_direction), (1, i as i64 + 1));
            assert_eq!((r.abscissa_data_type, r.ordinate_data_type), (17, 12));
            assert_eq!(r.num_points, 50);
            assert_eq!(
                r.abscissa,
                Abscissa::Even {
                    min: 0.0,
                    increment: 0.001,
                    count: 50
                }
            );
            assert_eq!(
                bits(&r.values),
                bits(csv.column(name).unwrap()),
                "{file}: {name}"
            );
            assert_eq!(
                bits(&r.abscissa.values()),
                bits(&csv.time),
                "{file}: {name}"
            );
        }
    }
}

#[test]
fn uneven_abscissa_and_single_precision_records_read() {
    let csv = reference();
    let disp = csv.column("disp_x").unwrap();
    let ascii = read_uff58(&fixture("signals_ascii.uff")).unwrap();
    let r = ascii
        .find(&RecordRef::Name("disp_x_uneven".into()))
        .unwrap();
    assert_eq!(r.number, 4);
    assert_eq!(bits(&r.values), bits(disp));
    // ASCII abscissa values are E13.5 text: equal to 6 digits.
    let Abscissa::Uneven(x) = &r.abscissa else {
        panic!("uneven expected")
    };
    for (a, t) in x.iter().zip(&csv.time) {
        assert!((a - t).abs() <= 1e-15, "{a} vs {t}");
    }
    // Binary 58b with uneven abscissa: pyuff 2.5.8 announces only the
    // ordinates' 400 bytes but writes 800; the closing -1 tells.
    let binary = read_uff58(&fixture("signals_binary.uff")).unwrap();
    let r = binary.record(4).unwrap();
    assert_eq!(r.name(), "disp_x_uneven");
    assert_eq!(bits(&r.values), bits(disp));
    assert_eq!(r.abscissa, Abscissa::Uneven(csv.time.clone()));
    // Single precision (6E13.5): within the 6 significant digits written.
    let r = ascii.find(&RecordRef::Index(5)).unwrap();
    assert_eq!(
        (r.name(), r.ordinate_type),
        ("vel_x_single", OrdinateType::RealSingle)
    );
    for (v, c) in r.values.iter().zip(csv.column("vel_x").unwrap()) {
        assert!((v - c).abs() <= 5e-6 * c.abs() + 1e-300, "{v} vs {c}");
    }
}

#[test]
fn windows_line_endings_read_the_same() {
    let text = bytes("signals_ascii.uff");
    let crlf: Vec<u8> = text
        .iter()
        .flat_map(|&b| {
            if b == b'\n' {
                vec![b'\r', b'\n']
            } else {
                vec![b]
            }
        })
        .collect();
    let a = parse_uff58(&text, Path::new("a.uff")).unwrap();
    let b = parse_uff58(&crlf, Path::new("a.uff")).unwrap();
    assert_eq!(a, b);
}

#[test]
fn records_are_found_by_number_and_name_or_listed() {
    let uff = read_uff58(&fixture("signals_ascii.uff")).unwrap();
    assert_eq!(uff.find(&RecordRef::Index(2)).unwrap().name(), "vel_x");
    assert_eq!(
        uff.find(&RecordRef::Name("acc_x".into())).unwrap().number,
        3
    );
    for wanted in [
        RecordRef::Index(9),
        RecordRef::Index(0),
        RecordRef::Name("acc_z".into()),
    ] {
        let e = uff.find(&wanted).unwrap_err();
        assert!(matches!(e, UffError::UnknownRecord { .. }), "{e:?}");
        let msg = e.to_string();
        assert!(msg.contains("signals_ascii.uff"), "{msg}");
        assert!(
            msg.contains(&format!("no function record {wanted}")),
            "{msg}"
        );
        assert!(
            msg.contains("1 'disp_x', 2 'vel_x', 3 'acc_x'"),
            "lists them: {msg}"
        );
    }
    // Two records of one name: the name is ambiguous.
    let twice = patch(&bytes("signals_ascii.uff"), b"vel_x ", b"disp_x");
    let uff = parse_uff58(&twice, Path::new("twice.uff")).unwrap();
    let e = uff.find(&RecordRef::Name("disp_x".into())).unwrap_err();
    assert!(matches!(e, UffError::Ambiguous { .. }), "{e:?}");
    assert!(
        e.to_string()
            .contains("records 1, 2 are all named 'disp_x'"),
        "{e}"
    );
}

#[test]
fn a_complex_record_is_recognized_and_refused_as_a_signal() {
    let uff = read_uff58(&fixture("complex.uff")).unwrap();
    let r = uff.record(1).unwrap();
    assert_eq!(
        (r.name(), r.ordinate_type),
        ("H11", OrdinateType::ComplexDouble)
    );
    assert!(r.values.is_empty());
    let e = uff.real_record(&RecordRef::Index(1)).unwrap_err();
    assert!(matches!(e, UffError::Complex { record: 1, .. }), "{e:?}");
    let msg = e.to_string();
    assert!(
        msg.contains("complex.uff: record 1 ('H11') holds complex data (complex double (6))"),
        "{msg}"
    );
}

/// The lines of the ASCII fixture, and the index of the line `text`.
fn lines() -> Vec<String> {
    String::from_utf8(bytes("signals_ascii.uff"))
        .unwrap()
        .lines()
        .map(str::to_string)
        .collect()
}

fn line_of(lines: &[String], text: &str) -> usize {
    lines.iter().position(|l| l.trim() == text).unwrap()
}

fn join(lines: &[String]) -> Vec<u8> {
    (lines.join("\n") + "\n").into_bytes()
}

#[test]
fn a_truncated_record_names_the_record_and_the_line() {
    // One data line of record 2 (vel_x) removed: its -1 comes early.
    let mut l = lines();
    let id = line_of(&l, "vel_x");
    l.remove(id + 12);
    let e = parse_uff58(&join(&l), Path::new("short.uff")).unwrap_err();
    match &e {
        UffError::Truncated {
            context,
            line,
            message,
            ..
        } => {
            assert_eq!(context.record, Some(2));
            // 11 header lines, 12 of the 13 data lines, then the -1 (1-based).
            assert_eq!(*line, id + 11 + 12 + 1, "the closing -1's line");
            assert!(message.contains("after 46 of 50 values"), "{message}");
        }
        other => panic!("expected Truncated, got {other:?}"),
    }
    let msg = e.to_string();
    assert!(
        msg.starts_with("short.uff: record 2 (dataset 58 from line "),
        "{msg}"
    );
    // The file cut inside record 3.
    let l = lines();
    let id = line_of(&l, "acc_x");
    let e = parse_uff58(&join(&l[..id + 14]), Path::new("cut.uff")).unwrap_err();
    assert!(
        matches!(&e, UffError::Truncated { context, .. } if context.record == Some(3)),
        "{e:?}"
    );
    assert!(
        e.to_string()
            .contains("the file ends after 12 of 50 values"),
        "{e}"
    );
    // A binary record cut inside its data.
    let b = bytes("signals_binary.uff");
    let at = b.windows(5).rposition(|w| w == b"acc_x").unwrap() + 1200;
    let e = parse_uff58(&b[..at], Path::new("cut.uff")).unwrap_err();
    assert!(
        matches!(&e, UffError::Truncated { context, .. } if context.record == Some(3)),
        "{e:?}"
    );
    assert!(e.to_string().contains("binary data need 400 bytes"), "{e}");
}

#[test]
fn wrong_types_and_garbage_are_format_errors_with_the_line() {
    let text = bytes("signals_ascii.uff");
    // Record 7 of the first record (line 25) with ordinate type 3.
    let bad = patch(&text, b"         4        50", b"         3        50");
    let e = parse_uff58(&bad, Path::new("t3.uff")).unwrap_err();
    match &e {
        UffError::Malformed {
            context,
            line,
            message,
            ..
        } => {
            assert_eq!((context.record, *line), (Some(1), 25));
            assert!(message.contains("ordinate data type 3"), "{message}");
        }
        other => panic!("expected Malformed, got {other:?}"),
    }
    assert!(
        e.to_string()
            .starts_with("t3.uff: record 1 (dataset 58 from line 17): line 25"),
        "{e}"
    );
    // A value that is not a number (record 1, first data line 30).
    let bad = patch(&text, b"1.55241800865e-06", b"1.55241800865x-06");
    let e = parse_uff58(&bad, Path::new("x.uff")).unwrap_err();
    assert!(matches!(&e, UffError::Malformed { line: 30, .. }), "{e:?}");
    assert!(
        e.to_string()
            .contains("'1.55241800865x-06' is not a number"),
        "{e}"
    );
    // Spacing that is neither 0 nor 1.
    let bad = patch(&text, b"        50         1", b"        50         7");
    let e = parse_uff58(&bad, Path::new("s.uff")).unwrap_err();
    assert!(e.to_string().contains("abscissa spacing 7"), "{e}");
    // A binary record in DEC VMS floating point.
    let bad = patch(
        &bytes("signals_binary.uff"),
        b"    58b     1     2",
        b"    58b     1     1",
    );
    let e = parse_uff58(&bad, Path::new("vms.uff")).unwrap_err();
    assert!(matches!(e, UffError::Unsupported { .. }), "{e:?}");
    assert!(e.to_string().contains("floating-point format 1"), "{e}");
    // Not a universal file at all.
    for garbage in [bytes("signals.csv"), bytes("signals.mat"), Vec::new()] {
        let e = parse_uff58(&garbage, Path::new("g.uff")).unwrap_err();
        assert!(matches!(e, UffError::NotUff { line: 1, .. }), "{e:?}");
        assert!(
            e.to_string()
                .starts_with("g.uff: not a universal file: line 1"),
            "{e}"
        );
    }
}
