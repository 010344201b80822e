//! D-optimal choice of K candidate sensors: maximise `log det (F_placed +
//! Σ_{i∈S} F_i)` over sets S of K candidates (SPEC §6; `F_placed` = 0 when
//! no sensor is placed). Exhaustive where the subsets are few; else greedy,
//! then Fedorov exchanges (swap one in, one out, while log det grows), from
//! several first picks when the base is singular ([`greedy_exchange`]). Every point of a box design
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
/// holds each point's placed information (0 with no placed sensor: the K
/// are then the whole test), `cand[p][i]` candidate i's at point p. Exhaustive when at most [`EXHAUSTIVE_LIMIT`] subsets, else
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
    let mut chosen = greedy_exchange(base, cand, k);
    chosen.sort_unstable();
    Choice {
        log_det: criterion(base, cand, &chosen),
        chosen,
        search: Search::GreedyExchange,
    }
}

/// Starts of greedy from a singular base: its first candidate is each of
/// this many best alone in turn.
const STARTS: usize = 4;

/// Greedy additions then exchanges, on the ridged information
/// ([`ridged`]). From a regular base, one run. From a singular one (no
/// placed sensor, or placed sensors that leave a parameter undetermined),
/// greedy's first pick has nothing to complement and is the best sensor
/// alone, which the best set need not hold (nor can one exchange at a time
/// always leave it: on the knee–column with no placed sensor, the best
/// pair holds neither of the first greedy pick's): so the run is made from
/// each of the [`STARTS`] best single candidates, and the set with the
/// largest ridged criterion kept (ties to the earlier start).
fn greedy_exchange(base: &[DMatrix<f64>], cand: &[Vec<DMatrix<f64>>], k: usize) -> Vec<usize> {
    let ridge = ridged(base, cand);
    let singular = base.iter().map(log_det).sum::<f64>() == f64::NEG_INFINITY;
    let n = cand.first().map_or(0, Vec::len);
    let firsts: Vec<Option<usize>> = match singular && k > 1 && n > 1 {
        true => best_singles(&ridge, cand, STARTS)
            .into_iter()
            .map(Some)
            .collect(),
        false => vec![None],
    };
    let mut best: Option<(f64, Vec<usize>)> = None;
    for first in firsts {
        let mut s = greedy(&ridge, cand, k, first);
        exchange(&ridge, cand, &mut s);
        let v = criterion(&ridge, cand, &s);
        if best.as_ref().is_none_or(|b| v > b.0) {
            best = Some((v, s));
        }
    }
    best.map(|b| b.1).unwrap_or_default()
}

/// The `m` candidates with the largest criterion alone on `ridge`, best
/// first (lower index on ties).
fn best_singles(ridge: &[DMatrix<f64>], cand: &[Vec<DMatrix<f64>>], m: usize) -> Vec<usize> {
    let n = cand.first().map_or(0, Vec::len);
    let mut alone: Vec<(usize, f64)> = (0..n)
        .into_par_iter()
        .map(|i| (i, criterion(ridge, cand, &[i])))
        .collect();
    alone.sort_by(|a, b| b.1.total_cmp(&a.1).then(a.0.cmp(&b.0)));
    alone.into_iter().take(m).map(|a| a.0).collect()
}

/// Each point's `base` plus a small ridge `ε I`, ε = 1e-9 × the mean
/// eigenvalue of the base with every candidate, so that greedy steps and
/// exchanges from a singular start still rank the candidates.
///
/// This is what makes greedy well defined from an empty base (no placed
/// sensor: `base` = 0, so `log det` of every set of fewer sensors than a
/// regular F needs is −∞). On the ridged matrix, a set whose F has rank ρ
/// scores `Σ log λ₁…λ_ρ + (r − ρ) log ε` to first order, each missing rank
/// costing `log(λ/ε)` ≈ 20 or more: greedy is rank-first (it adds the
/// candidate that raises the rank most, then the one that adds most
/// volume), and once F is regular the ridge shifts log det by about
/// `ε tr F⁻¹`, far below the differences the choice rests on. The
/// criterion reported ([`Choice::log_det`]) is always the unridged one.
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

/// K greedy additions to the ridged base `ridge` ([`ridged`]: well
/// defined from a zero or singular base, rank first), each the candidate
/// that raises the criterion most; `first`, if given, is the first.
fn greedy(
    ridge: &[DMatrix<f64>],
    cand: &[Vec<DMatrix<f64>>],
    k: usize,
    first: Option<usize>,
) -> Vec<usize> {
    let n = cand.first().map_or(0, Vec::len);
    let mut m = ridge.to_vec();
    let mut s = Vec::with_capacity(k);
    if let Some(i) = first.filter(|&i| i < n && k > 0) {
        s.push(i);
        for (m, c) in m.iter_mut().zip(cand) {
            *m += &c[i];
        }
    }
    while s.len() < k {
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
/// while it raises the criterion on the ridged base `ridge` by more than
/// rounding (at most [`MAX_EXCHANGES`] passes).
fn exchange(ridge: &[DMatrix<f64>], cand: &[Vec<DMatrix<f64>>], s: &mut [usize]) {
    let n = cand.first().map_or(0, Vec::len);
    let mut current = criterion(ridge, cand, s);
    for _ in 0..MAX_EXCHANGES {
        let m = sums(ridge, cand, s);
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

    /// Greedy from an empty base, each candidate of rank one in three
    /// parameters: every set of one or two is singular (log det −∞), yet
    /// greedy (on the ridged information) finds the best regular set of
    /// three, as brute force does.
    #[test]
    fn greedy_from_an_empty_base_reaches_full_rank() {
        let v = [
            [1.0, 0.0, 0.0],
            [2.0, 0.1, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 0.5],
            [0.3, 0.3, 0.3],
            [0.0, 3.0, 3.0],
        ];
        let cand: Vec<DMatrix<f64>> = v
            .iter()
            .map(|v| {
                let v = nalgebra::DVector::from_row_slice(v);
                &v * v.transpose()
            })
            .collect();
        let base = [DMatrix::zeros(3, 3)];
        let cand = [cand];
        let brute = choose(&base, &cand, 3, false);
        let greedy = choose(&base, &cand, 3, true);
        assert!(brute.log_det.is_finite());
        assert_eq!(greedy.chosen, brute.chosen);
        assert_eq!(criterion(&base, &cand, &[0, 1]), f64::NEG_INFINITY);
        // Two cannot be regular: the choice is still made (the most
        // informative pair), its criterion −∞.
        let pair = choose(&base, &cand, 2, true);
        assert_eq!(pair.chosen.len(), 2);
        assert_eq!(pair.log_det, f64::NEG_INFINITY);
    }

    #[test]
    fn log_det_of_a_diagonal_matrix() {
        let m = DMatrix::from_diagonal(&nalgebra::DVector::from_vec(vec![2.0, 3.0, 0.5]));
        assert!((log_det(&m) - 3.0f64.ln()).abs() < 1e-14);
        assert_eq!(log_det(&DMatrix::zeros(2, 2)), f64::NEG_INFINITY);
    }
}
