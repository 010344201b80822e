//! The Nyquist warning on the knee–column benchmark (issue 9, §3). Its
//! slideways' normal contacts are power laws with m = 2, whose slope is zero
//! at rest: linearised there, the fastest mode is at 512 Hz, and only the
//! model linearised along its response shows the knee's modes near 850 Hz,
//! once the contacts deform. Sampled at 1 kHz, the warning must name that
//! mode; sampled at 10 kHz, nothing is above the Nyquist frequency.
use rfeid::io::model_file::load_model;
use rfeid::model::Model;
use rfeid::simulation::aliasing::{above_nyquist, fastest_along_response};
use rfeid::simulation::steps::fastest_mode_hz;
use rfeid::simulation::Simulator;
use std::path::Path;

fn knee_column(rate: f64) -> Model {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/knee-column/model.toml");
    let mut model = load_model(&path).expect("the example loads");
    model.sampling.sample_rate = rate;
    model
}

#[test]
fn at_one_kilohertz_the_deformed_contacts_modes_are_named() {
    let model = knee_column(1000.0);
    let p = model.nominal();
    let sim = Simulator::new(&model);
    let at_rest = fastest_mode_hz(&model, &p).expect("modes at rest");
    let along = fastest_along_response(&sim, &p).expect("power-law joints");
    println!("at rest {at_rest:.1} Hz, along the response {along:?}");
    // Measured: 512.1 Hz at rest, 851.5 Hz along the response.
    assert!(along.frequency_hz > 1.5 * at_rest, "{along:?}");
    let w = above_nyquist(&sim, &p);
    println!("{w:#?}");
    assert_eq!(w.len(), 1, "{w:?}");
    let named = format!("{:.1} Hz", along.frequency_hz);
    assert!(w[0].contains(&named) && w[0].contains("500 Hz"), "{w:?}");
    assert!(w[0].contains(&along.component), "{w:?}");
    assert!(w[0].contains(&format!("{at_rest:.1} Hz")), "{w:?}");
}

#[test]
fn at_ten_kilohertz_nothing_is_above_the_nyquist_frequency() {
    let model = knee_column(10_000.0);
    let p = model.nominal();
    let sim = Simulator::new(&model);
    let along = fastest_along_response(&sim, &p).expect("power-law joints");
    println!("along the response {along:?}");
    let w = above_nyquist(&sim, &p);
    assert!(w.is_empty(), "{w:?}");
}
