//! Stage 3, the weights: each sensor weighted by its noise level estimated
//! from its residuals ([`Weighting::EstimatedNoise`], eq. 14 with each
//! sensor's own σ²), at the best end and, when no end passes the fit
//! checks, before the restarts judge the ends.
use super::error::IdentifyError;
use super::judge::fit_passes;
use super::searcher::Searcher;
use super::settings::{Start, Weighting};
use super::starts::Ends;
use crate::identification::output_error::OutputError;
use crate::identification::search::SearchOutcome;

/// When no end passes the fit checks and the sensors are weighted by their
/// noise, the weights are estimated at the best end first, and the other
/// ends searched again with them: with the first weights a sensor of little
/// signal (a campaign's low force level) is left underfitted even at the
/// right minimum, and its residuals fail the checks. Only then do the
/// restarts judge the ends.
pub(super) fn before_restarts(
    problem: &mut OutputError<'_>,
    searcher: &Searcher<'_>,
    ends: &mut Ends,
) -> Result<(), IdentifyError> {
    let s = searcher.settings();
    let searches = &mut ends.searches;
    let reweight = s.weighting == Weighting::EstimatedNoise
        && s.start == Start::Plan
        && s.restarts > 0
        && !searches.is_empty()
        && !searches
            .iter()
            .any(|e| fit_passes(problem, &s.verdict, &e.u));
    if !reweight {
        return Ok(());
    }
    let k = (0..searches.len())
        .min_by(|&a, &b| searches[a].cost.total_cmp(&searches[b].cost))
        .unwrap_or(0);
    let end = estimate(problem, searcher, searches.remove(k))?;
    searches.insert(k, end);
    for j in (0..searches.len()).filter(|&j| j != k) {
        searches[j] = searcher.search(problem, &searches[j].u)?;
    }
    Ok(())
}

/// Sensor weights estimated from the residuals: each sensor weighted by the
/// inverse of its residual variance at the end of `best`, the search
/// continued with those weights, until they change by less than 1 % (at
/// most 5 rounds). Returns the end under the weights `problem` then holds.
pub(super) fn estimate(
    problem: &mut OutputError<'_>,
    searcher: &Searcher<'_>,
    mut best: SearchOutcome,
) -> Result<SearchOutcome, IdentifyError> {
    for _ in 0..5 {
        let fitted = problem
            .simulate_all(&best.u)
            .map_err(IdentifyError::Simulation)?;
        let weights = noise_weights(&problem.sensor_ssr(&fitted), &problem.weight_samples());
        let change = weights
            .iter()
            .zip(problem.weights())
            .map(|(a, b)| (a / b - 1.0).abs())
            .fold(0.0, f64::max);
        if change < 0.01 {
            // Keep the weights J was minimised with, so that the
            // reported criterion and weights belong together.
            break;
        }
        problem.set_weights(&weights);
        best = searcher.search(problem, &best.u)?;
    }
    Ok(best)
}

/// w_c = n_c / SSR_c, scaled so that the smallest is 1; a sensor fitted
/// exactly (zero residuals) gets the largest finite weight, not an
/// arbitrary one.
fn noise_weights(ssr: &[f64], samples: &[usize]) -> Vec<f64> {
    let weights: Vec<f64> = ssr
        .iter()
        .zip(samples)
        .map(|(s, used)| {
            if *s > 0.0 {
                *used as f64 / s
            } else {
                f64::INFINITY
            }
        })
        .collect();
    let largest = weights
        .iter()
        .cloned()
        .filter(|w| w.is_finite())
        .fold(1.0, f64::max);
    let weights: Vec<f64> = weights
        .iter()
        .map(|w| if w.is_finite() { *w } else { largest })
        .collect();
    let scale = weights.iter().cloned().fold(f64::INFINITY, f64::min);
    weights.iter().map(|w| w / scale).collect()
}
