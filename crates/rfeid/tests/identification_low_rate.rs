//! Identification from data sampled at 1 kHz, a tenth of the benchmark's
//! rate, with the knee's modes (~850 Hz) near the Nyquist frequency. The
//! data are simulated at a fine step (64 steps per sample, far below the
//! tolerance) plus 2 % seeded noise; the identification uses the default
//! settings, so its steps per sample are chosen automatically. Each estimate
//! must land within 3 standard errors of the truth (measured: all within
//! 2.2, with 10 steps per sample chosen). One step per sample, the old
//! default, had a simulation error of 0.46 relative RMS at this rate.
use rfeid::identification::output_error::OutputError;
use rfeid::identification::pipeline::{identify, Settings, Silent};
use rfeid::io::model_file::load_model;
use rfeid::measurement::add_noise;
use rfeid::simulation::steps::integrator;
use rfeid::simulation::{Simulator, Workspace};
use std::path::Path;

#[test]
fn one_kilohertz_data_from_a_fine_step_lands_within_three_standard_errors() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/knee-column/model.toml");
    let mut model = load_model(&path).expect("example loads");
    model.sampling.sample_rate = 1000.0;
    let fine = Simulator::with_integrator(&model, integrator(64));
    let mut data = fine.response_buffer();
    fine.run(&model.nominal(), &mut Workspace::default(), &mut data)
        .expect("simulates");
    add_noise(&mut data, 0.02, 1);

    let settings = Settings {
        plan_points: 100,
        starts: 1,
        ..Settings::default()
    };
    let r = identify(
        OutputError::new(Simulator::new(&model), data, 0),
        &settings,
        &Silent,
    )
    .expect("identifies");
    let steps = r.simulation.expect("recorded");
    println!("{steps:?}");
    assert!(steps.automatic && steps.substeps > 1, "{steps:?}");
    assert!(
        steps.estimated_error.unwrap() <= steps.tolerance,
        "{steps:?}"
    );
    // The knee's modes near 850 Hz, beyond the 500 Hz Nyquist frequency
    // once the contacts deform, are named (tests/aliasing_knee_column.rs).
    assert!(
        r.warnings
            .iter()
            .map(|w| w.to_string())
            .any(|w| w.contains("along its response") && w.contains("500 Hz")),
        "{:?}",
        r.warnings
    );
    for p in &r.parameters {
        let se = p.std_error.expect("standard errors");
        let z = (p.estimate - p.nominal) / se;
        println!("{}: {z:+.2} standard errors", p.name);
        assert!(z.abs() <= 3.0, "{}: {z:+.2} standard errors off", p.name);
    }
}
