//! Regression: a model whose number of power-law springs is not a multiple
//! of four panicked (index out of range) instead of returning
//! `SimulationError::Diverged` once its state stopped being finite: the
//! padding slots of the last 4-row panel got δ = 0·NaN = NaN and were then
//! looked up among the real springs.
use rfeid::io::model_file::parse_model;
use rfeid::simulation::{SimulationError, Simulator, Workspace};
use std::path::Path;

/// One body on one absurdly stiff power-law spring: within the first step a
/// stage's force a·δ|δ| overflows to infinity and the next stage's state is
/// NaN, before the once-per-sample size check can see anything.
const MODEL: &str = r#"
[simulation]
duration = 1.0
sample_rate = 100.0

[[body]]
name = "mass"
mass = 1.0
inertia = [1.0, 1.0, 1.0]
com = [0.0, 0.0, 0.0]

[[element]]
name = "contact"
body = "mass"
to = "ground"
at = [0.0, 0.0, 0.0]
ux = { law = "power", a = 1.0e300, m = 2.0 }

[[excitation]]
body = "mass"
at = [0.0, 0.0, 0.0]
direction = [1, 0, 0]
signal = { type = "sine", amplitude = 1.0e6, frequency = 10.0 }

[[sensor]]
name = "a"
body = "mass"
at = [0.0, 0.0, 0.0]
direction = [1, 0, 0]
quantity = "acceleration"
"#;

#[test]
fn a_single_power_law_spring_that_blows_up_gives_diverged_not_a_panic() {
    let model = parse_model(MODEL, Path::new("regression.toml")).expect("valid model");
    let sim = Simulator::new(&model);
    let mut out = sim.response_buffer();
    let err = sim
        .run(&model.nominal(), &mut Workspace::default(), &mut out)
        .unwrap_err();
    assert!(matches!(err, SimulationError::Diverged { .. }), "{err}");
}
