//! No input makes the MAT-file or universal-file reader panic: every
//! fixture truncated at every byte, with seeded random bytes changed, and
//! with each 4-byte word set to 0 and to 0xFFFFFFFF (sizes, counts and
//! types at their extremes). Each run must return, `Ok` or `Err`.
use crate::import_common;

use import_common::*;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rfeid::io::mat::parse_mat;
use rfeid::io::uff::parse_uff58;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::Path;

/// Parses `bytes` with the reader for `file`'s format; `Some(n)` with the
/// number of variables or records on success, `None` on an error.
fn parse(file: &str, bytes: &[u8]) -> Option<usize> {
    let path = Path::new(file);
    if file.ends_with(".mat") {
        parse_mat(bytes, path).ok().map(|m| m.variables().len())
    } else {
        parse_uff58(bytes, path).ok().map(|u| u.records().len())
    }
}

/// Runs `parse` and turns a panic into a failure naming the case.
fn must_return(file: &str, case: &str, bytes: &[u8]) -> Option<usize> {
    catch_unwind(AssertUnwindSafe(|| parse(file, bytes)))
        .unwrap_or_else(|_| panic!("{file}: the reader panicked on {case}"))
}

const FILES: [&str; 6] = [
    "signals.mat",
    "signals_compressed.mat",
    "mixed_classes.mat",
    "signals_ascii.uff",
    "signals_binary.uff",
    "complex.uff",
];

#[test]
fn truncation_at_every_byte_never_panics_and_never_gains_data() {
    for file in FILES {
        let full = bytes(file);
        let all = parse(file, &full).expect("the fixture reads");
        let mut failed = 0;
        for k in 0..full.len() {
            match must_return(file, &format!("the first {k} bytes"), &full[..k]) {
                Some(n) => assert!(n <= all, "{file}: {k} bytes give {n} > {all} entries"),
                None => failed += 1,
            }
        }
        // Most cuts fall inside an element or record.
        assert!(failed > full.len() / 2, "{file}: only {failed} cuts failed");
    }
}

#[test]
fn seeded_random_byte_changes_never_panic() {
    let mut rng = ChaCha8Rng::seed_from_u64(0x5eed_f11e);
    for file in FILES {
        let full = bytes(file);
        for trial in 0..3000 {
            let mut b = full.clone();
            for _ in 0..rng.random_range(1..=4) {
                let i = rng.random_range(0..b.len());
                b[i] = rng.random();
            }
            must_return(file, &format!("trial {trial}"), &b);
        }
    }
}

#[test]
fn extreme_words_at_every_offset_never_panic() {
    for file in FILES {
        let full = bytes(file);
        for k in
            (0..full.len().saturating_sub(4)).step_by(if file.ends_with(".mat") { 4 } else { 7 })
        {
            for word in [[0u8; 4], [0xff; 4], *b"9999", *b"  -1"] {
                let mut b = full.clone();
                b[k..k + 4].copy_from_slice(&word);
                must_return(file, &format!("{word:?} at byte {k}"), &b);
            }
        }
    }
}
