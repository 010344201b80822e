//! Seeded mutation of the command line's inputs: model files, and CSV, MAT
//! and UFF data. Whatever the damage, `rfeid` ends by itself (no panic, no
//! signal), with a documented exit status, and leaves no output and no
//! temporary file after a non-zero exit. Bounded to a few seconds.
#![cfg(unix)]
use crate::support;

use std::path::Path;
use support::{oscillator_model, rfeid, scratch_dir, temporaries};

/// Exit statuses the README documents for a finished run: success, a failed
/// computation, bad input, and a suspect verdict (result written).
const DOCUMENTED: [i32; 5] = [0, 1, 2, 3, 4];

/// Mutations per input file.
const MUTANTS: usize = 30;

/// SplitMix64: a small seeded generator, the same on every machine.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
}

/// Numbers that stress readers and the computation.
const NASTY: [&str; 10] = [
    "1e308", "-1e308", "1e154", "0", "-0", "nan", "inf", "1e-320", "x", "",
];

/// One seeded mutation of `bytes`: a flipped byte, a cut, a repeated or
/// deleted span, random bytes, or (in text) a number replaced by a nasty one.
fn mutate(bytes: &[u8], rng: &mut Rng) -> Vec<u8> {
    let mut b = bytes.to_vec();
    if b.is_empty() {
        return b;
    }
    let n = b.len();
    match rng.below(6) {
        0 => {
            for _ in 0..1 + rng.below(4) {
                let i = rng.below(n);
                b[i] ^= 1 << rng.below(8);
            }
        }
        1 => b.truncate(rng.below(n)),
        2 => {
            let i = rng.below(n);
            let len = 1 + rng.below(64.min(n - i));
            let span = b[i..i + len].to_vec();
            b.splice(i..i, span);
        }
        3 => {
            let i = rng.below(n);
            let len = rng.below(64.min(n - i) + 1);
            b.drain(i..i + len);
        }
        4 => {
            let i = rng.below(n);
            let junk: Vec<u8> = (0..1 + rng.below(16)).map(|_| rng.next() as u8).collect();
            b.splice(i..i, junk);
        }
        _ => {
            // Replace a number-looking token of a text file.
            let text = String::from_utf8_lossy(bytes).into_owned();
            let starts: Vec<usize> = text
                .char_indices()
                .filter(|(i, c)| {
                    c.is_ascii_digit()
                        && (*i == 0 || !text.as_bytes()[i - 1].is_ascii_alphanumeric())
                })
                .map(|(i, _)| i)
                .collect();
            if starts.is_empty() {
                return b;
            }
            let s = starts[rng.below(starts.len())];
            let e = text[s..]
                .find(|c: char| !(c.is_ascii_alphanumeric() || c == '.' || c == '-' || c == '+'))
                .map_or(text.len(), |k| s + k);
            let mut t = text.clone();
            t.replace_range(s..e, NASTY[rng.below(NASTY.len())]);
            b = t.into_bytes();
        }
    }
    b
}

/// Runs `identify` on the model and data in `dir` and checks the outcome.
fn run_and_check(dir: &Path, model: &Path, data: &Path, what: &str) -> i32 {
    let result = dir.join("result.json");
    let report = dir.join("report");
    let _ = std::fs::remove_file(&result);
    let _ = std::fs::remove_dir_all(&report);
    let out = rfeid()
        .arg("identify")
        .arg(model)
        .arg("--data")
        .arg(data)
        .arg("-o")
        .arg(&result)
        .arg("--report")
        .arg(&report)
        .args(["--plan", "4", "--starts", "2", "-q", "--threads", "1"])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    let Some(code) = out.status.code() else {
        panic!("{what}: ended by a signal: {:?}\n{stderr}", out.status);
    };
    assert!(!stderr.contains("panicked"), "{what}: panic\n{stderr}");
    assert!(
        DOCUMENTED.contains(&code),
        "{what}: exit status {code}\n{stderr}"
    );
    if !matches!(code, 0 | 3 | 4) {
        assert!(!result.exists(), "{what}: result left after exit {code}");
        assert!(!report.exists(), "{what}: report left after exit {code}");
    }
    assert_eq!(temporaries(dir), Vec::<String>::new(), "{what}");
    code
}

#[test]
fn mutated_inputs_never_crash_and_leave_nothing_behind() {
    let dir = scratch_dir("mutation");
    let fixtures = Path::new(env!("CARGO_MANIFEST_DIR")).join("../rfeid/tests/data/import");
    let model = oscillator_model(&dir);
    let model_text = std::fs::read(&model).unwrap();
    let csv = fixtures.join("signals.csv");
    let mut rng = Rng(0x5eed_0010);
    let mut codes = [0usize; 5];
    // Mutated models with good data.
    let mutant_model = dir.join("mutant.toml");
    for k in 0..MUTANTS {
        std::fs::write(&mutant_model, mutate(&model_text, &mut rng)).unwrap();
        let c = run_and_check(&dir, &mutant_model, &csv, &format!("model mutant {k}"));
        codes[c as usize] += 1;
    }
    // Mutated data of each format with the good model.
    for name in [
        "signals.csv",
        "signals.mat",
        "signals_compressed.mat",
        "signals_ascii.uff",
        "signals_binary.uff",
    ] {
        let bytes = std::fs::read(fixtures.join(name)).unwrap();
        let mutant = dir.join(format!("mutant-{name}"));
        for k in 0..MUTANTS {
            std::fs::write(&mutant, mutate(&bytes, &mut rng)).unwrap();
            let c = run_and_check(&dir, &model, &mutant, &format!("{name} mutant {k}"));
            codes[c as usize] += 1;
        }
    }
    eprintln!("exit statuses 0/1/2/3/4: {codes:?}");
    // The mutations must reach the readers' error paths and leave some
    // inputs readable: a test that only ever saw one outcome tests little.
    assert!(codes[0] > 0 && codes[2] > 0, "{codes:?}");
}
