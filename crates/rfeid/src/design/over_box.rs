//! A design for parameters not yet known: the choice that maximises the
//! average `log det F` over N LP_τ points of the parameter box (eq. 18–19),
//! and how it compares with each point's own best choice and with the
//! choice at the values.
use super::choose::{choose, criterion, Search};
use super::fisher::{fisher_parts, FisherParts};
use super::fisher_bound::cramer_rao_fisher;
use super::{DesignError, DesignSettings};
use crate::identification::box_map::BoxMap;
use crate::identification::options::OptionError;
use crate::identification::plan::lp_tau_plan;
use crate::identification::uncertainty::UncertaintySettings;
use crate::model::Model;
use nalgebra::DMatrix;
use rayon::prelude::*;

/// The box design.
#[derive(Debug, Clone, PartialEq)]
pub struct BoxChoice {
    /// The robust choice (candidate indices, ascending).
    pub robust: Vec<usize>,
    /// How it was found.
    pub search: Search,
    /// The choice at the parameters' values alone.
    pub at_values: Vec<usize>,
    /// Points of the box used (those that simulated).
    pub points: usize,
    /// Points whose simulation failed (left out), with the first reason.
    pub failed: usize,
    /// The first failure's reason.
    pub first_failure: Option<String>,
    /// Points whose own best choice is the robust one (or as good, to
    /// rounding: equivalent sets count).
    pub agree: usize,
    /// The robust choice's D-efficiency at each point against that point's
    /// own best, `exp((log det F(robust) − log det F(best))/r)` (NaN where
    /// every set is singular there).
    pub efficiency: Vec<f64>,
    /// Points where F is singular whatever is chosen: there every choice is
    /// as good (they count in `agree`), and none can be judged.
    pub singular: usize,
}

/// Most memory the box's Fisher matrices may take (points × candidates ×
/// r² values), bytes.
const MAX_BYTES: f64 = 4.0 * (1u64 << 30) as f64;

/// The parameters' values at plan point `u` (normalised, one coordinate
/// per identified parameter), the others at their values.
fn point_values(model: &Model, u: &[f64]) -> Vec<f64> {
    let mut x = model.nominal();
    for (&i, &ui) in model.identified().iter().zip(u) {
        let p = &model.parameters[i];
        let (lo, hi) = p.bounds.expect("identified parameters have boxes");
        x[i] = BoxMap::new(lo, hi, p.scale).to_physical(ui);
    }
    x
}

/// Whether F of the placed sensors `base` with the candidates `chosen` is
/// singular by the test of `identify`'s standard errors (a finite log det
/// of a singular F is rounding).
fn singular(base: &DMatrix<f64>, cand: &[DMatrix<f64>], chosen: &[usize]) -> bool {
    let f = chosen.iter().fold(base.clone(), |m, &i| m + &cand[i]);
    let ones = vec![1.0; f.ncols()];
    let settings = UncertaintySettings::default();
    cramer_rao_fisher(&f, 1 << 40, &ones, &ones, 1.0, &settings).is_err()
}

/// At one box point (its placed Fisher part `b` and candidates' `c`, one
/// point's slices):
/// whether the robust choice `robust` is also that point's own best choice
/// of `k`, and its D-efficiency there; `(true, NaN)` where every choice is
/// singular (none is better than another).
fn point_verdict(
    b: &[DMatrix<f64>],
    c: &[Vec<DMatrix<f64>>],
    robust: &[usize],
    k: usize,
    greedy: bool,
) -> (bool, f64) {
    let best = choose(b, c, k, greedy);
    let mine = criterion(b, c, robust);
    if best.log_det == f64::NEG_INFINITY || singular(&b[0], &c[0], &best.chosen) {
        // The best set is singular too (to rounding).
        return (true, f64::NAN);
    }
    let same = mine >= best.log_det - 1e-9 * best.log_det.abs().max(1.0);
    let r = b[0].ncols() as f64;
    (same, ((mine - best.log_det) / r).exp().min(1.0))
}

/// The D-optimal K for the average over `n` LP_τ points of the box;
/// `values` holds the pieces at the parameters' values.
pub fn choose_over_box(
    model: &Model,
    values: &FisherParts,
    k: usize,
    n: usize,
    settings: &DesignSettings,
    tick: &(dyn Fn() + Sync),
) -> Result<BoxChoice, DesignError> {
    let r = values.columns.len();
    let bytes = n as f64 * model.candidates.len() as f64 * (r * r * 8) as f64;
    if bytes > MAX_BYTES {
        let detail = format!(
            "{n} with {} candidates would hold {:.1} GiB of Fisher matrices (at most 4 GiB): use fewer points",
            model.candidates.len(),
            bytes / (1u64 << 30) as f64
        );
        return Err(DesignError::Option(OptionError::new("over_box", detail)));
    }
    let plan =
        lp_tau_plan(model.identified().len(), n).map_err(|e| DesignError::Plan(e.to_string()))?;
    let results: Vec<Result<FisherParts, DesignError>> = (0..plan.len())
        .into_par_iter()
        .map(|p| {
            if settings.cancel.is_set() {
                return Err(DesignError::Cancelled);
            }
            let parts = fisher_parts(model, &point_values(model, plan.point(p)));
            tick();
            parts
        })
        .collect();
    if settings.cancel.is_set() {
        return Err(DesignError::Cancelled);
    }
    let failed = results.iter().filter(|r| r.is_err()).count();
    let first_failure = results
        .iter()
        .find_map(|r| r.as_ref().err().map(|e| e.to_string()));
    let parts: Vec<FisherParts> = results.into_iter().filter_map(Result::ok).collect();
    if parts.is_empty() {
        return Err(DesignError::EveryPointFailed {
            points: n,
            first: first_failure.unwrap_or_default(),
        });
    }
    let base: Vec<DMatrix<f64>> = parts.iter().map(FisherParts::placed).collect();
    let cand: Vec<Vec<DMatrix<f64>>> = parts.iter().map(FisherParts::candidates).collect();
    let robust = choose(&base, &cand, k, settings.force_greedy);
    let at_values = choose(
        &[values.placed()],
        &[values.candidates()],
        k,
        settings.force_greedy,
    )
    .chosen;
    let own: Vec<(bool, f64)> = (0..parts.len())
        .into_par_iter()
        .map(|p| {
            point_verdict(
                &base[p..=p],
                &cand[p..=p],
                &robust.chosen,
                k,
                settings.force_greedy,
            )
        })
        .collect();
    Ok(BoxChoice {
        robust: robust.chosen,
        search: robust.search,
        at_values,
        points: parts.len(),
        failed,
        first_failure,
        agree: own.iter().filter(|o| o.0).count(),
        efficiency: own.iter().map(|o| o.1).collect(),
        singular: own.iter().filter(|o| o.1.is_nan()).count(),
    })
}
