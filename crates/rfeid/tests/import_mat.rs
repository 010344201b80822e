//! The MAT-file reader against files written by scipy's `savemat`
//! (uncompressed, compressed, mixed classes): the same numbers as the CSV,
//! bit for bit, and clear errors for everything that is not a real numeric
//! vector or not a well-formed Level 5 file.
use crate::import_common;

use import_common::*;
use rfeid::io::mat::{parse_mat, read_mat_vectors, MatClass, MatError};
use std::path::Path;

fn bits(v: &[f64]) -> Vec<u64> {
    v.iter().map(|x| x.to_bits()).collect()
}

#[test]
fn uncompressed_and_compressed_files_hold_the_csv_numbers_bit_for_bit() {
    let csv = reference();
    for file in ["signals.mat", "signals_compressed.mat"] {
        let mat = read_mat_vectors(&fixture(file)).unwrap_or_else(|e| panic!("{e}"));
        for name in ["disp_x", "vel_x", "acc_x"] {
            let v = mat.vector(name).unwrap_or_else(|| panic!("{file}: {name}"));
            assert_eq!(bits(v), bits(csv.column(name).unwrap()), "{file}: {name}");
        }
    }
    let plain = read_mat_vectors(&fixture("signals.mat")).unwrap();
    assert_eq!(plain.names(), ["time", "disp_x", "vel_x", "acc_x"]);
    assert_eq!(bits(plain.vector("time").unwrap()), bits(&csv.time));
    // vel_x is stored as a 50×1 column, the others as 1×50 rows.
    assert_eq!(plain.variable("vel_x").unwrap().dims, [50, 1]);
    assert_eq!(plain.variable("acc_x").unwrap().dims, [1, 50]);
    let packed = read_mat_vectors(&fixture("signals_compressed.mat")).unwrap();
    assert_eq!(packed.vector("fs"), Some(&[1000.0][..]));
}

#[test]
fn mixed_classes_convert_to_f64_exactly() {
    let csv = reference();
    let mat = read_mat_vectors(&fixture("mixed_classes.mat")).unwrap();
    let var = |n: &str| mat.variable(n).unwrap();
    assert_eq!(var("disp_x").class, MatClass::Double);
    assert_eq!(
        bits(mat.vector("disp_x").unwrap()),
        bits(csv.column("disp_x").unwrap())
    );
    // single: the CSV value rounded to f32, widened exactly.
    assert_eq!(var("vel_x").class, MatClass::Single);
    let single: Vec<f64> = csv
        .column("vel_x")
        .unwrap()
        .iter()
        .map(|&v| v as f32 as f64)
        .collect();
    assert_eq!(bits(mat.vector("vel_x").unwrap()), bits(&single));
    // int16 counts of 0.01 m/s².
    assert_eq!(var("acc_counts").class, MatClass::Int16);
    let counts: Vec<f64> = csv
        .column("acc_x")
        .unwrap()
        .iter()
        .map(|&a| (a / 0.01).round_ties_even())
        .collect();
    assert_eq!(mat.vector("acc_counts").unwrap(), &counts[..]);
    assert_eq!(mat.vector("acc_scale").unwrap(), [0.01]);
    let exact: [(&str, MatClass, &[f64]); 7] = [
        ("i8", MatClass::Int8, &[-128.0, 0.0, 127.0]),
        ("u8", MatClass::UInt8, &[0.0, 200.0, 255.0]),
        ("u16", MatClass::UInt16, &[65535.0, 1.0]),
        ("i32", MatClass::Int32, &[-2147483648.0, 7.0, 2147483647.0]),
        ("u32", MatClass::UInt32, &[0.0, 4294967295.0]),
        (
            "i64",
            MatClass::Int64,
            &[-1099511627776.0, 3.0, 1099511627776.0],
        ),
        ("u64", MatClass::UInt64, &[0.0, 4503599627370497.0]),
    ];
    for (name, class, values) in exact {
        assert_eq!(var(name).class, class, "{name}");
        assert_eq!(mat.vector(name).unwrap(), values, "{name}");
    }
}

#[test]
fn variables_that_are_not_real_numeric_vectors_are_named_errors() {
    let path = fixture("mixed_classes.mat");
    let mat = read_mat_vectors(&path).unwrap();
    let err = |name: &str| {
        assert!(mat.vector(name).is_none(), "{name}");
        let e = mat.require_vector(name).unwrap_err();
        let msg = e.to_string();
        assert!(msg.contains("mixed_classes.mat"), "names the file: {msg}");
        assert!(
            msg.contains(&format!("'{name}'")),
            "names the variable: {msg}"
        );
        (e, msg)
    };
    for (name, kind) in [
        ("note", "a char array"),
        ("flags", "a logical array"),
        ("cells", "a cell array"),
        ("info", "a struct"),
    ] {
        let (e, msg) = err(name);
        assert!(
            matches!(&e, MatError::NotNumeric { kind: k, .. } if k == kind),
            "{name}: {e:?}"
        );
        assert!(
            msg.ends_with(&format!(
                "variable '{name}' is {kind}, not a numeric vector"
            )),
            "{msg}"
        );
    }
    let (e, msg) = err("grid");
    assert!(
        matches!(&e, MatError::NotVector { dims, .. } if dims == "2×3"),
        "{e:?}"
    );
    assert!(msg.contains("2×3 matrix, not a vector"), "{msg}");
    assert!(matches!(err("empty").0, MatError::NotVector { .. }));
    assert!(matches!(err("cplx").0, MatError::Complex { .. }));
    let (e, msg) = err("acc_x");
    assert!(matches!(e, MatError::UnknownVariable { .. }), "{e:?}");
    assert!(
        msg.contains("variables: t, disp_x, vel_x, acc_counts"),
        "lists the variables: {msg}"
    );
}

#[test]
fn files_that_are_not_level_5_mat_files_are_refused() {
    let csv = bytes("signals.csv");
    let e = parse_mat(&csv, Path::new("data.mat")).unwrap_err();
    assert!(matches!(e, MatError::NotMat { .. }), "{e:?}");
    assert!(
        e.to_string()
            .starts_with("data.mat: not a MATLAB Level 5 MAT-file"),
        "{e}"
    );
    let mut v73 = bytes("signals.mat");
    v73[..19].copy_from_slice(b"MATLAB 7.3 MAT-file");
    let e = parse_mat(&v73, Path::new("new.mat")).unwrap_err();
    assert!(e.to_string().contains("v7.3 (HDF5)"), "{e}");
    let e = parse_mat(&[], Path::new("empty.mat")).unwrap_err();
    assert!(matches!(e, MatError::NotMat { .. }), "{e:?}");
    let mut v4 = bytes("signals.mat");
    v4[126..128].copy_from_slice(b"\0\0");
    let e = parse_mat(&v4, Path::new("v4.mat")).unwrap_err();
    assert!(e.to_string().contains("Level 4"), "{e}");
}

#[test]
fn a_truncated_file_names_the_element_and_its_byte_offset() {
    let full = bytes("signals.mat");
    // The last variable (acc_x, 1×50 double) is the last 8 + 456 bytes.
    let last = full.len() - 464;
    let cut = scratch("cut.mat", &full[..full.len() - 10]);
    let e = read_mat_vectors(&cut).unwrap_err();
    match &e {
        MatError::Truncated {
            at,
            needed,
            available,
            ..
        } => {
            assert!(at.offset as usize >= last, "{e}");
            assert!(needed > available, "{e}");
        }
        other => panic!("expected Truncated, got {other:?}"),
    }
    let msg = e.to_string();
    assert!(
        msg.contains("cut.mat") && msg.contains("byte ") && msg.contains("truncated"),
        "{msg}"
    );
    // Cut at the top level, the compressed element is truncated as a whole.
    let packed = bytes("signals_compressed.mat");
    let e = parse_mat(&packed[..packed.len() - 20], Path::new("packed.mat")).unwrap_err();
    assert!(matches!(e, MatError::Truncated { .. }), "{e:?}");
    assert!(e.to_string().contains("miCOMPRESSED"), "{e}");
    // Cut inside the zlib stream (the element's size cut to match): the
    // error points into the decompressed data of that element.
    let mut pos = 128;
    let mut last = 0;
    while pos < packed.len() {
        last = pos;
        pos += 8 + u32::from_le_bytes(packed[pos + 4..pos + 8].try_into().unwrap()) as usize;
    }
    let mut cut = packed[..packed.len() - 20].to_vec();
    let size = u32::from_le_bytes(cut[last + 4..last + 8].try_into().unwrap()) - 20;
    cut[last + 4..last + 8].copy_from_slice(&size.to_le_bytes());
    let e = parse_mat(&cut, Path::new("packed.mat")).unwrap_err();
    let at = match &e {
        MatError::Truncated { at, .. } | MatError::Malformed { at, .. } => at,
        other => panic!("expected Truncated or Malformed, got {other:?}"),
    };
    assert_eq!(at.compressed_at, Some(last as u64), "{e}");
    assert!(
        e.to_string()
            .contains(&format!("compressed element at byte {last}")),
        "{e}"
    );
}

#[test]
fn a_sub_element_of_the_wrong_type_is_a_format_error_with_its_offset() {
    let mut b = bytes("signals.mat");
    // First variable at byte 128: miMATRIX tag, then the array-flags tag
    // (miUINT32 = 6, 8 bytes) at byte 136.
    assert_eq!(&b[136..140], &6u32.to_le_bytes());
    b[136] = 7; // miSINGLE
    let e = parse_mat(&b, Path::new("flags.mat")).unwrap_err();
    match &e {
        MatError::Malformed { at, message, .. } => {
            assert_eq!(at.offset, 136);
            assert!(message.contains("array flags"), "{message}");
        }
        other => panic!("expected Malformed, got {other:?}"),
    }
}

/// A big-endian file built by hand from the format document, with the
/// name in a small data element: `x = [1.5 -2 3.25]`.
#[test]
fn a_big_endian_file_with_a_small_element_name_reads() {
    let mut f = vec![b' '; 116];
    f[..25].copy_from_slice(b"MATLAB 5.0 MAT-file, test");
    f.extend([0u8; 8]);
    f.extend(0x0100u16.to_be_bytes());
    f.extend(b"MI");
    let mut body = Vec::new();
    let tag = |b: &mut Vec<u8>, kind: u32, size: u32| {
        b.extend(kind.to_be_bytes());
        b.extend(size.to_be_bytes());
    };
    tag(&mut body, 6, 8);
    body.extend(6u32.to_be_bytes()); // mxDOUBLE_CLASS
    body.extend(0u32.to_be_bytes());
    tag(&mut body, 5, 8);
    body.extend(1i32.to_be_bytes());
    body.extend(3i32.to_be_bytes());
    body.extend(((1u32 << 16) | 1).to_be_bytes()); // small miINT8, 1 byte
    body.extend(b"x\0\0\0");
    tag(&mut body, 9, 24);
    for v in [1.5f64, -2.0, 3.25] {
        body.extend(v.to_be_bytes());
    }
    tag(&mut f, 14, body.len() as u32);
    f.extend(body);
    let mat = parse_mat(&f, Path::new("be.mat")).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(mat.names(), ["x"]);
    assert_eq!(mat.vector("x").unwrap(), [1.5, -2.0, 3.25]);
}
