//! Honest answers on coloured noise (the knee–column benchmark with noise
//! an anti-alias filter leaves): standard errors that cover the estimates'
//! errors, a trustworthy verdict on a correct model, and a suspect one on a
//! wrong model.
use crate::coloured_cases;

use coloured_cases::{coloured_data, default_settings, knee_column, rms, run, z_scores};
use rfeid::identification::pipeline::NoiseModel;
use rfeid::identification::verdict::Reason;
use rfeid::model::{Law, Power, Value};

/// 2 % noise low-passed at 1 kHz (sampling at 10 kHz), 4 seeds: the RMS of
/// |estimate − truth| / s.e. over all 64 estimates lies in [0.7, 1.4], none
/// beyond 4.5, and at least 3 of the 4 verdicts are trustworthy. With the
/// white noise model (the paper's output error) the same data give standard
/// errors too small (checked: RMS above 1.3; measured 1.44).
#[test]
fn coloured_noise_gets_honest_standard_errors() {
    let model = knee_column();
    let settings = default_settings();
    let white = rfeid::identification::pipeline::Settings {
        noise_model: NoiseModel::White,
        ..default_settings()
    };
    let (mut z, mut z_white, mut trusted) = (Vec::new(), Vec::new(), 0);
    for seed in 1..=4 {
        let data = coloured_data(&model, 0.02, 1000.0, seed);
        let r = run(&model, data.clone(), &settings);
        z.extend(z_scores(&r));
        trusted += usize::from(!r.is_suspect());
        assert!(r.noise.iter().all(|n| n.order > 0), "{:?}", r.noise);
        z_white.extend(z_scores(&run(&model, data, &white)));
    }
    let worst = z.iter().cloned().fold(0.0, f64::max);
    assert!((0.7..=1.4).contains(&rms(&z)), "RMS z {}", rms(&z));
    assert!(worst <= 4.5, "worst z {worst}");
    assert!(trusted >= 3, "{trusted} of 4 trustworthy");
    assert!(rms(&z_white) > 1.3, "white-noise RMS z {}", rms(&z_white));
}

/// A wrong model (a slideway exponent fixed at 2.5 instead of 2) on the same
/// coloured noise stays suspect: the noise model does not whiten away a misfit that
/// follows the input.
#[test]
fn a_wrong_model_on_coloured_noise_is_suspect() {
    let model = knee_column();
    let data = coloured_data(&model, 0.02, 1000.0, 1);
    let mut wrong = model.clone();
    let mut changed = 0;
    for c in wrong.elements.iter_mut().flat_map(|e| &mut e.components) {
        if let Law::Power(Power { m, .. }) = &mut c.law {
            *m = Value::Fixed(2.5);
            changed += 1;
        }
    }
    assert_eq!(changed, 4, "the knee–column's four slideway contacts");
    let r = run(&wrong, data, &default_settings());
    let v = r.verdict.as_ref().expect("a verdict");
    assert!(!v.trustworthy, "{:?}", v.reasons);
    assert!(
        v.reasons
            .iter()
            .any(|r| matches!(r, Reason::InputCorrelated { .. } | Reason::NotWhite { .. })),
        "{:?}",
        v.reasons
    );
}
