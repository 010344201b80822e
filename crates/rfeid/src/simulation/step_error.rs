//! The error measure of the step choice (see `steps`): the relative RMS
//! difference of two responses, the largest over the sensors, over the
//! whole record or over windows of it.
use super::response::Response;
use super::run::SampleView;
use crate::measurement::rms;
use crate::model::{Model, SensorKind};
use std::time::Duration;

/// A response computed on the way to a step choice: the run at the chosen
/// steps and the parameters of the choice, and its wall time.
pub type ChosenRun = (Response, Duration);

/// A sample watcher for [`crate::simulation::Simulator::choose_watching`]:
/// called at each sample ([`SampleView`]), from sample 0 again whenever the
/// choice starts another run.
pub type Watcher<'w> = dyn FnMut(&SampleView<'_>) + Send + 'w;

/// Each sensor's RMS in `r`, floored at 1e-3 of the largest RMS among the
/// sensors of the same kind (a sensor that by symmetry reads almost nothing
/// would otherwise measure rounding noise against rounding noise).
pub(super) fn sensor_scales(model: &Model, r: &Response) -> Vec<f64> {
    let rms: Vec<f64> = (0..r.n_sensors).map(|c| rms(r.sensor(c))).collect();
    let kinds: Vec<SensorKind> = model.sensors.iter().map(|s| s.kind).collect();
    floored(&rms, &kinds)
}

/// Each sensor's RMS `rms[c]` floored at 1e-3 of the largest among the
/// sensors of the same kind (`kinds`), as [`sensor_scales`] takes them.
pub(super) fn floored(rms: &[f64], kinds: &[SensorKind]) -> Vec<f64> {
    (0..rms.len())
        .map(|c| {
            let same = (0..rms.len()).filter(|&d| kinds[d] == kinds[c]);
            rms[c].max(same.map(|d| rms[d]).fold(0.0, f64::max) * 1e-3)
        })
        .collect()
}

/// The largest over the sensors of `sq_sums[c] / count`, square-rooted and
/// divided by the sensor's scale; NaN (a non-finite signal) counts as
/// infinitely wrong.
fn worst_relative(scales: &[f64], sq_sums: &[f64], count: usize) -> f64 {
    let mut worst: f64 = 0.0;
    for (scale, sum) in scales.iter().zip(sq_sums) {
        if *sum == 0.0 {
            continue;
        }
        let e = (sum / count.max(1) as f64).sqrt() / scale;
        worst = if e.is_nan() {
            f64::INFINITY
        } else {
            worst.max(e)
        };
    }
    worst
}

/// Relative RMS difference of `a` from `b`, the largest over the sensors.
///
/// Each sensor's RMS difference is divided by its RMS in `b`, but by no
/// less than 1e-3 of the largest RMS among the sensors of the same kind.
pub fn relative_difference(model: &Model, a: &Response, b: &Response) -> f64 {
    let sums: Vec<f64> = (0..b.n_sensors)
        .map(|c| {
            let pairs = a.sensor(c).iter().zip(b.sensor(c));
            pairs.map(|(x, y)| (x - y) * (x - y)).sum()
        })
        .collect();
    worst_relative(&sensor_scales(model, b), &sums, b.n_samples)
}

/// The relative RMS difference of the response `a` from the finer runs
/// over the windows `fine` (each starting at its sample), the largest over
/// the sensors: [`relative_difference`] over the windows' samples, with each
/// sensor's scale taken from the whole of `a`.
pub fn windowed_difference(model: &Model, a: &Response, fine: &[(usize, Response)]) -> f64 {
    let mut sums = vec![0.0; a.n_sensors];
    let mut count = 0;
    for (first, w) in fine {
        for (c, sum) in sums.iter_mut().enumerate() {
            let coarse = &a.sensor(c)[*first..*first + w.n_samples];
            let pairs = coarse.iter().zip(w.sensor(c));
            *sum += pairs.map(|(x, y)| (x - y) * (x - y)).sum::<f64>();
        }
        count += w.n_samples;
    }
    worst_relative(&sensor_scales(model, a), &sums, count)
}
