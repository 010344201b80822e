//! The starts' ends clustered into minima.
use super::reason::{Minimum, StartEnd};
use crate::identification::chi_square::chi_square_quantile;

/// The J difference beyond which two ends are different minima,
/// `χ²_r(level) · J_best / (N − r − 1)` (eq. 29's s² times the quantile).
pub fn minima_threshold(best: f64, r: usize, observations: usize, level: f64) -> f64 {
    let dof = observations.saturating_sub(r + 1).max(1) as f64;
    chi_square_quantile(level, r.max(1)) * best / dof
}

/// Clusters the ends by J: sorted by J, an end starts a new minimum when its
/// J exceeds the current minimum's lowest J by more than
/// `χ²_r(level) · J_best / (N − r − 1)`. Returns the minima and that
/// threshold.
pub fn cluster_minima(
    ends: &[StartEnd],
    r: usize,
    observations: usize,
    level: f64,
) -> (Vec<Minimum>, f64) {
    let mut order: Vec<usize> = (0..ends.len()).collect();
    order.sort_by(|&a, &b| ends[a].cost.total_cmp(&ends[b].cost));
    let best = order.first().map_or(0.0, |&k| ends[k].cost);
    let threshold = minima_threshold(best, r, observations, level);
    let mut minima: Vec<Minimum> = Vec::new();
    for k in order {
        match minima.last_mut() {
            Some(m) if ends[k].cost - m.cost <= threshold => m.starts += 1,
            _ => minima.push(Minimum {
                cost: ends[k].cost,
                starts: 1,
                parameters: ends[k].parameters.clone(),
            }),
        }
    }
    (minima, threshold)
}
