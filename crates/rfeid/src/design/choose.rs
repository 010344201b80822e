//! D-optimal choice of K candidate sensors: maximise `log det (F_placed +
//! Σ_{i∈S} F_i)` over sets S of K candidates (SPEC §6). Exhaustive where
//! the subsets are few; else greedy, then Fedorov exchanges (swap one in,
//! one out, while log det grows). Every point of a box design
//! (`--over-box`) adds its own term, so the criterion is the sum of log
//! dets over the points.
use nalgebra::DMatrix;
use rayon::prelude::*;

/// Most subsets tried one by one; beyond, greedy plus exchange.
pub const EXHAUSTIVE_LIMIT: u64 = 20_000;

/// How a set was chosen.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Search {
    /// Every subset of K candidates tried.
    Exhaustive,
    /// Greedy additions, then exchanges until none improves.
    GreedyExchange,
}

/// A chosen set.
#[derive(Debug, Clone, PartialEq)]
pub struct Choice {
    /// Candidate indices, ascending.
    pub chosen: Vec<usize>,
    /// The criterion: Σ over the points of `log det F` (−∞ if singular).
    pub log_det: f64,
    /// How it was found.
    pub search: Search,
}

/// `log det m` by Cholesky; −∞ when `m` is not positive definite.
pub fn log_det(m: &DMatrix<f64>) -> f64 {
    match m.clone().cholesky() {
        Some(c) => 2.0 * c.l_dirty().diagonal().iter().map(|d| d.ln()).sum::<f64>(),
        None => f64::NEG_INFINITY,
    }
}

/// The criterion of set `s`: `Σ_p log det (base_p + Σ_{i∈s} cand_p[i])`.
pub fn criterion(base: &[DMatrix<f64>], cand: &[Vec<DMatrix<f64>>], s: &[usize]) -> f64 {
    sums(base, cand, s).iter().map(log_det).sum()
}

/// Number of K-subsets of n, saturating.
pub(crate) fn binomial(n: usize, k: usize) -> u64 {
    if k > n {
        return 0;
    }
    let k = k.min(n - k);
    (0..k).fold(1u64, |acc, i| {
        acc.saturating_mul((n - i) as u64) / (i as u64 + 1)
    })
}

/// The K-subset of rank `rank` in lexicographic order of n.
fn unrank(mut rank: u64, n: usize, k: usize) -> Vec<usize> {
    let mut out = Vec::with_capacity(k);
    let mut next = 0;
    for slot in 0..k {
        let mut i = next;
        loop {
            let after = binomial(n - i - 1, k - slot - 1);
            if rank < after {
                break;
            }
            rank -= after;
            i += 1;
        }
        out.push(i);
        next = i + 1;
    }
    out
}

/// The D-optimal K of the candidates, added to the placed sensors: `base`
/// holds each point's placed information, `cand[p][i]` candidate i's at
/// point p. Exhaustive when at most [`EXHAUSTIVE_LIMIT`] subsets, else
/// greedy plus exchange; `force_greedy` takes the latter always (for the
/// tests that compare them). Ties go to the lower indices, so the choice
/// does not depend on the thread count.
pub fn choose(
    base: &[DMatrix<f64>],
    cand: &[Vec<DMatrix<f64>>],
    k: usize,
    force_greedy: bool,
) -> Choice {
    let n = cand.first().map_or(0, Vec::len);
    let subsets = binomial(n, k);
    if !force_greedy && subsets <= EXHAUSTIVE_LIMIT {
        let best = (0..subsets)
            .into_par_iter()
            .map(|rank| (criterion(base, cand, &unrank(rank, n, k)), rank))
            .reduce(
                || (f64::NEG_INFINITY, u64::MAX),
                |a, b| {
                    if b.0 > a.0 || (b.0 == a.0 && b.1 < a.1) {
                        b
                    } else {
                        a
                    }
                },
            );
        // Every subset singular: rank them on the ridged information.
        if best.0 > f64::NEG_INFINITY {
            let chosen = unrank(best.1, n, k);
            return Choice {
                log_det: criterion(base, cand, &chosen),
                chosen,
                search: Search::Exhaustive,
            };
        }
    }
    let mut chosen = greedy(base, cand, k);
    exchange(base, cand, &mut chosen);
    chosen.sort_unstable();
    Choice {
        log_det: criterion(base, cand, &chosen),
        chosen,
        search: Search::GreedyExchange,
    }
}

/// A small ridge, relative to the information's scale, so that greedy
/// steps from a singular start still rank the candidates.
fn ridged(base: &[DMatrix<f64>], cand: &[Vec<DMatrix<f64>>]) -> Vec<DMatrix<f64>> {
    base.iter()
        .zip(cand)
        .map(|(b, c)| {
            let r = b.nrows();
            let total = c.iter().fold(b.clone(), |m, f| m + f);
            let eps = 1e-9 * total.trace().max(f64::MIN_POSITIVE) / r as f64;
            b + DMatrix::identity(r, r) * eps
        })
        .collect()
}

/// Most exchange passes (each tries every swap; they rarely take more
/// than a few).
const MAX_EXCHANGES: usize = 50;

/// Each point's `base` plus the candidates of `s`.
fn sums(base: &[DMatrix<f64>], cand: &[Vec<DMatrix<f64>>], s: &[usize]) -> Vec<DMatrix<f64>> {
    base.iter()
        .zip(cand)
        .map(|(b, c)| s.iter().fold(b.clone(), |m, &i| m + &c[i]))
        .collect()
}

/// The best candidate of `pool` to add to the sums `m` (lowest index on
/// ties): `Σ_p log det (m_p + F_pi)`, each in O(r³).
fn best_addition(
    m: &[DMatrix<f64>],
    cand: &[Vec<DMatrix<f64>>],
    pool: &[usize],
) -> Option<(usize, f64)> {
    pool.par_iter()
        .map(|&i| {
            let v = m.iter().zip(cand).map(|(m, c)| log_det(&(m + &c[i]))).sum();
            (i, v)
        })
        .reduce_with(|a, b| {
            if b.1 > a.1 || (b.1 == a.1 && b.0 < a.0) {
                b
            } else {
                a
            }
        })
}

/// K greedy additions (on the ridged information).
fn greedy(base: &[DMatrix<f64>], cand: &[Vec<DMatrix<f64>>], k: usize) -> Vec<usize> {
    let n = cand.first().map_or(0, Vec::len);
    let mut m = ridged(base, cand);
    let mut s = Vec::with_capacity(k);
    for _ in 0..k {
        let pool: Vec<usize> = (0..n).filter(|i| !s.contains(i)).collect();
        let Some((i, _)) = best_addition(&m, cand, &pool) else {
            break;
        };
        s.push(i);
        for (m, c) in m.iter_mut().zip(cand) {
            *m += &c[i];
        }
    }
    s
}

/// Fedorov exchanges: the best swap of a chosen and an unchosen candidate,
/// while it raises the criterion by more than rounding (at most
/// [`MAX_EXCHANGES`] passes).
fn exchange(base: &[DMatrix<f64>], cand: &[Vec<DMatrix<f64>>], s: &mut [usize]) {
    let n = cand.first().map_or(0, Vec::len);
    let ridge = ridged(base, cand);
    let mut current = criterion(&ridge, cand, s);
    for _ in 0..MAX_EXCHANGES {
        let m = sums(&ridge, cand, s);
        let pool: Vec<usize> = (0..n).filter(|i| !s.contains(i)).collect();
        let mut best: Option<(usize, usize, f64)> = None;
        for (slot, &out) in s.iter().enumerate() {
            let without: Vec<DMatrix<f64>> = m.iter().zip(cand).map(|(m, c)| m - &c[out]).collect();
            if let Some((i, v)) = best_addition(&without, cand, &pool) {
                if best.is_none_or(|b| v > b.2) {
                    best = Some((slot, i, v));
                }
            }
        }
        match best {
            Some((slot, i, v)) if v > current + 1e-10 * current.abs().max(1.0) => {
                s[slot] = i;
                current = v;
            }
            _ => break,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unrank_walks_the_subsets_in_order() {
        let all: Vec<Vec<usize>> = (0..binomial(5, 3)).map(|r| unrank(r, 5, 3)).collect();
        assert_eq!(all.len(), 10);
        assert_eq!(all[0], vec![0, 1, 2]);
        assert_eq!(all[9], vec![2, 3, 4]);
        let mut sorted = all.clone();
        sorted.sort();
        sorted.dedup();
        assert_eq!(sorted, all);
    }

    #[test]
    fn log_det_of_a_diagonal_matrix() {
        let m = DMatrix::from_diagonal(&nalgebra::DVector::from_vec(vec![2.0, 3.0, 0.5]));
        assert!((log_det(&m) - 3.0f64.ln()).abs() < 1e-14);
        assert_eq!(log_det(&DMatrix::zeros(2, 2)), f64::NEG_INFINITY);
    }
}
