//! The global strategy at default settings on wide boxes (issue 8 §2): a
//! representative subset of the cases that `examples/wide_boxes.rs`
//! tabulates (every box one or two decades wide, the truth at a seeded
//! random log position 15–85 % of it, 1 % noise). Each case must end
//! trustworthy with every estimate within 3 standard errors of the truth.
//! Measured: knee–column (2 bodies, m = 2, sine), one decade, seed 1:
//! worst 1.95 (h_t2); tailstock (4 bodies, m = 1.5 and 2, multisine and a
//! measured force), two decades, seed 3: worst 1.23 (a_n3).
use crate::wide_cases;

use wide_cases::{data, default_settings, example, run, widened, worst_z};

fn case(name: &str, factor: f64, seed: u64) {
    let model = widened(&example(name), factor, seed);
    let r = run(&model, data(&model, 0.01, seed), &default_settings());
    let (z, worst) = worst_z(&r);
    let v = r.verdict.as_ref().expect("a verdict");
    eprintln!(
        "{name}, factor {factor}, seed {seed}: worst {z:.2} ({worst}), trustworthy {}",
        v.trustworthy
    );
    assert!(v.trustworthy, "{name}: {:?}", v.reasons);
    assert!(z <= 3.0, "{name}: {worst} {z:.2} standard errors off");
}

#[test]
fn knee_column_one_decade() {
    case("knee-column", 10.0, 1);
}

#[test]
fn tailstock_two_decades() {
    case("tailstock", 100.0, 3);
}
