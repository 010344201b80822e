//! The excitation forces a run evaluates with its table segments kept
//! (`System::forces_kept`) against the plain evaluation.
use super::test_models::oscillator;
use super::Simulator;
use crate::model::{Segment, Shape, Signal, Term, Value};

/// The term `amplitude · shape`.
fn term(amplitude: f64, shape: Shape) -> Term {
    let amplitude = Value::Fixed(amplitude);
    Term { amplitude, shape }
}

/// Every instant of `probes`, from both sides, in increasing order and
/// then scrambled: the forces with kept segments equal the plain ones bit
/// for bit, for signals of one term each and for signals of several.
#[test]
fn kept_segments_give_the_plain_forces_bit_for_bit() {
    let rate = 1000.0;
    let even: Vec<f64> = (0..60).map(|k| k as f64 / rate).collect();
    let uneven: Vec<f64> = (0..60).map(|k| (k as f64).powf(1.3) * 6e-4).collect();
    let values: Vec<f64> = (0..60).map(|k| (k as f64 * 0.41).cos()).collect();
    let table = |times: &Vec<f64>| Shape::linear_table(times.clone(), values.clone());
    let one_each = vec![
        vec![term(2.0, table(&even))],
        vec![term(-0.7, Shape::Constant)],
        vec![term(0.5, table(&uneven))],
    ];
    let several = vec![
        vec![term(1.5, table(&uneven)), term(0.3, Shape::Constant)],
        vec![term(-1.0, table(&even))],
        vec![
            term(
                0.2,
                Shape::Sine {
                    frequency: 37.0,
                    phase: 0.4,
                },
            ),
            term(0.9, table(&even)),
            term(1.1, table(&uneven)),
        ],
    ];
    let probes: Vec<f64> = (0..=3000)
        .map(|i| 0.06 * i as f64 / 3000.0 - 0.002)
        .chain(even.iter().chain(&uneven).copied())
        .collect();
    assert_ne!(probes.len() % 7919, 0);
    let scrambled = (0..probes.len()).map(|i| probes[i * 7919 % probes.len()]);
    let order: Vec<f64> = probes.iter().copied().chain(scrambled).collect();
    for signals in [one_each, several] {
        let mut model = oscillator(40.0, 10.0, rate);
        let first = model.excitations[0].clone();
        model.excitations = (signals.into_iter().enumerate())
            .map(|(e, terms)| {
                let mut excitation = first.clone();
                excitation.name = format!("p{e}");
                excitation.signal = Signal {
                    kind: "test",
                    terms,
                };
                excitation
            })
            .collect();
        let sim = Simulator::new(&model);
        let sys = sim.system(&model.nominal()).expect("builds");
        let e = model.excitations.len();
        let mut segments = vec![Segment::default(); sys.signal_terms()];
        let (mut kept, mut plain) = (vec![0.0; e], vec![0.0; e]);
        for &t in &order {
            for before in [true, false] {
                sys.forces_kept(t, before, &mut kept, &mut segments);
                sys.forces_side(t, before, &mut plain);
                for (a, b) in kept.iter().zip(&plain) {
                    assert_eq!(a.to_bits(), b.to_bits(), "t = {t}, before {before}");
                }
            }
        }
    }
}
