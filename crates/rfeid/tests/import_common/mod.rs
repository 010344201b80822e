//! Shared helpers of the data-import tests: the fixtures written by
//! `tools/fixtures/make_import_fixtures.py` (scipy `savemat`, pyuff) and
//! scratch copies of them with bytes changed.
#![allow(dead_code)]

use rfeid::io::timeseries::{read_csv, TimeSeries};
use std::path::{Path, PathBuf};

/// A fixture in `tests/data/import/`.
pub fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/import")
        .join(name)
}

/// The reference signals: `signals.csv` (time, disp_x, vel_x, acc_x).
pub fn reference() -> TimeSeries {
    read_csv(&fixture("signals.csv")).expect("signals.csv reads")
}

/// Writes `bytes` to a scratch file named `name` (the extension picks the
/// format) and returns its path.
pub fn scratch(name: &str, bytes: &[u8]) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("rfeid-import-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("scratch dir");
    let p = dir.join(name);
    std::fs::write(&p, bytes).expect("scratch write");
    p
}

/// The bytes of a fixture.
pub fn bytes(name: &str) -> Vec<u8> {
    std::fs::read(fixture(name)).expect("fixture reads")
}

/// `text` with the first occurrence of `from` replaced by `to` (same
/// length, so binary offsets stay put); panics if `from` is absent.
pub fn patch(bytes: &[u8], from: &[u8], to: &[u8]) -> Vec<u8> {
    assert_eq!(from.len(), to.len(), "patch keeps the length");
    let at = bytes
        .windows(from.len())
        .position(|w| w == from)
        .unwrap_or_else(|| panic!("'{}' not in the fixture", String::from_utf8_lossy(from)));
    let mut out = bytes.to_vec();
    out[at..at + to.len()].copy_from_slice(to);
    out
}

/// Like [`patch`], at the `n`-th (0-based) occurrence.
pub fn patch_nth(bytes: &[u8], from: &[u8], to: &[u8], n: usize) -> Vec<u8> {
    let at = bytes
        .windows(from.len())
        .enumerate()
        .filter(|(_, w)| *w == from)
        .nth(n)
        .map(|(i, _)| i)
        .unwrap_or_else(|| {
            panic!(
                "occurrence {n} of '{}' missing",
                String::from_utf8_lossy(from)
            )
        });
    let mut out = bytes.to_vec();
    out[at..at + to.len()].copy_from_slice(to);
    out
}

/// A MATLAB Level 5 MAT-file (little-endian, uncompressed) holding each
/// `(name, values)` as a 1×N double vector.
pub fn mat_bytes(vars: &[(&str, &[f64])]) -> Vec<u8> {
    let mut out = vec![b' '; 116];
    out[..19].copy_from_slice(b"MATLAB 5.0 MAT-file");
    out.extend([0u8; 8]);
    out.extend(0x0100u16.to_le_bytes());
    out.extend(b"IM");
    let sub = |out: &mut Vec<u8>, kind: u32, data: &[u8]| {
        out.extend(kind.to_le_bytes());
        out.extend((data.len() as u32).to_le_bytes());
        out.extend(data);
        out.resize(out.len().div_ceil(8) * 8, 0);
    };
    for (name, values) in vars {
        let mut m = Vec::new();
        sub(&mut m, 6, &[6, 0, 0, 0, 0, 0, 0, 0]); // array flags: double
        let dims: Vec<u8> = [1i32, values.len() as i32]
            .iter()
            .flat_map(|d| d.to_le_bytes())
            .collect();
        sub(&mut m, 5, &dims);
        sub(&mut m, 1, name.as_bytes());
        let data: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
        sub(&mut m, 9, &data);
        out.extend(14u32.to_le_bytes());
        out.extend((m.len() as u32).to_le_bytes());
        out.extend(m);
    }
    out
}
