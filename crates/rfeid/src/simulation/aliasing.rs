//! Response content that sampled data cannot show: natural frequencies of
//! the model at a parameter point, and excitation frequencies, above the
//! Nyquist frequency (half the sample rate).
use super::modal::modal_analysis;
use super::steps::integrator;
use super::Simulator;
use crate::model::{Model, Shape};

/// Warnings, in words, about content of the model's response at `params`
/// above the data's Nyquist frequency: none if there is none (or if the
/// modal analysis fails; the simulation reports that itself).
pub fn above_nyquist(model: &Model, params: &[f64]) -> Vec<String> {
    let nyquist = model.sampling.sample_rate / 2.0;
    let mut warnings = Vec::new();
    let sim = Simulator::with_integrator(model, integrator(1));
    if let Ok(modal) = modal_analysis(&sim, params) {
        let above: Vec<f64> = modal
            .modes
            .iter()
            .map(|m| m.frequency_hz)
            .filter(|f| *f > nyquist)
            .collect();
        if let Some(fastest) = above.iter().cloned().reduce(f64::max) {
            warnings.push(format!(
                "{} of the model's {} modes (linearised at rest, at the estimate) lie above the \
                 data's Nyquist frequency of {nyquist} Hz, the fastest at {fastest:.1} Hz: the data \
                 cannot show that content, so the parameters that set those modes rest on the \
                 rest of the response only; sample faster if you can",
                above.len(),
                modal.modes.len()
            ));
        }
    }
    for exc in &model.excitations {
        let highest = exc
            .signal
            .terms
            .iter()
            .filter_map(|t| match t.shape {
                Shape::Sine { frequency, .. } => Some(frequency.abs()),
                Shape::Chirp { f0, f1, .. } => Some(f0.abs().max(f1.abs())),
                Shape::Impulse { .. } | Shape::Table { .. } => None,
            })
            .fold(0.0, f64::max);
        if highest > nyquist {
            warnings.push(format!(
                "excitation '{}' reaches {highest} Hz, above the data's Nyquist frequency of \
                 {nyquist} Hz: the data cannot show the response at those frequencies",
                exc.name
            ));
        }
    }
    warnings
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::simulation::test_models::oscillator;

    #[test]
    fn modes_and_excitations_above_nyquist_are_named() {
        let m = oscillator(100.0, 30.0, 1000.0);
        assert!(above_nyquist(&m, &m.nominal()).is_empty());
        let m = oscillator(700.0, 30.0, 1000.0);
        let w = above_nyquist(&m, &m.nominal());
        assert_eq!(w.len(), 1, "{w:?}");
        assert!(
            w[0].contains("700.0 Hz") && w[0].contains("500 Hz"),
            "{w:?}"
        );
        let m = oscillator(100.0, 600.0, 1000.0);
        let w = above_nyquist(&m, &m.nominal());
        assert_eq!(w.len(), 1, "{w:?}");
        assert!(w[0].contains("excitation 'p' reaches 600 Hz"), "{w:?}");
    }
}
