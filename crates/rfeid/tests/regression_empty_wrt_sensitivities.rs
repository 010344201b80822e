//! Regression: `Simulator::run_with_sensitivities` with no parameters
//! panicked ("chunk size must be non-zero"): the sensitivity rows, r rounded
//! up to whole vectors, were zero long. Sensitivities to nothing are an empty
//! matrix beside the plain response.
use rfeid::io::model_file::load_model;
use rfeid::simulation::{Sensitivities, Simulator, Workspace};
use std::path::Path;

#[test]
fn sensitivities_to_no_parameter_are_empty_and_the_response_is_the_plain_one() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/knee-column/model.toml");
    let model = load_model(&path).expect("the example loads");
    let sim = Simulator::new(&model);
    let params = model.nominal();
    let mut ws = Workspace::default();
    let mut plain = sim.response_buffer();
    sim.run(&params, &mut ws, &mut plain).expect("runs");

    let mut out = sim.response_buffer();
    let mut sens = Sensitivities {
        wrt: vec![3],
        values: vec![1.0; 7],
    };
    sim.run_with_sensitivities(&params, &[], &mut ws, &mut out, &mut sens)
        .expect("runs");
    assert!(sens.wrt.is_empty() && sens.values.is_empty());
    assert!(out == plain);
}
