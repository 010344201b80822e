//! One interface to the local searches: [`LocalSearch`], which
//! Levenberg–Marquardt ([`super::lm`]) and the paper's BFGS ([`super::bfgs`],
//! eq. 20–25) implement, and the one [`SearchOutcome`] both return.
//!
//! Like the solvers, this knows no model: it works on any
//! [`LeastSquares`] problem in normalised coordinates (eq. 17).
use super::bfgs::{Bfgs, BfgsResult};
use super::lm::{LevenbergMarquardt, LmResult};
use super::problem::LeastSquares;
use super::tally::Tally;
use super::termination::{SolveError, StopReason};
use serde::{Deserialize, Serialize};

/// The local search method, as RESULT.json names it (`lm`, `bfgs`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Method {
    /// Levenberg–Marquardt with the exact Jacobian.
    #[default]
    Lm,
    /// The paper's BFGS with finite-difference gradients (eq. 20–25).
    Bfgs,
}

impl std::fmt::Display for Method {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Method::Lm => "lm",
            Method::Bfgs => "bfgs",
        })
    }
}

/// One iterate of a local search: its number (0: the start), J and u.
#[derive(Debug, Clone, PartialEq)]
pub struct Step {
    /// Iteration number.
    pub iteration: usize,
    /// J (eq. 16) there.
    pub cost: f64,
    /// The normalised parameters.
    pub u: Vec<f64>,
}

/// A finished local search, whichever method.
#[derive(Debug, Clone, PartialEq)]
pub struct SearchOutcome {
    /// The estimate, normalised.
    pub u: Vec<f64>,
    /// J there.
    pub cost: f64,
    /// Why the search stopped.
    pub stop: StopReason,
    /// Iterations taken.
    pub iterations: usize,
    /// The evaluations the search made, as it counted them (a residual
    /// evaluation is a plain simulation, a Jacobian one with
    /// sensitivities).
    pub tally: Tally,
    /// Every iterate, the start first.
    pub history: Vec<Step>,
    /// The residuals and the whole Jacobian at `u`, when the search ended
    /// with them (Levenberg–Marquardt on a whole Jacobian), for the bounds
    /// to take rather than simulate again ([`SearchOutcome::without_jacobian`]
    /// drops them).
    pub linearised: Option<Linearised>,
}

/// The residuals r(u) and the Jacobian ∂r/∂u (N × n) at a search's end.
#[derive(Debug, Clone, PartialEq)]
pub struct Linearised {
    /// r(u), weighted like J.
    pub residuals: Vec<f64>,
    /// ∂r/∂u.
    pub jacobian: nalgebra::DMatrix<f64>,
}

impl SearchOutcome {
    /// The outcome without its [`SearchOutcome::linearised`] (N × n
    /// numbers), to be kept among others.
    pub fn without_jacobian(self) -> Self {
        SearchOutcome {
            linearised: None,
            ..self
        }
    }

    /// This search continued by `next`, which started where this one
    /// ended (on a changed criterion: other steps per sample, say): `next`'s
    /// end, stop and Jacobian; the iterations and evaluations of both; the
    /// history of both, `next`'s numbered on from this one's (its start, the
    /// same point with the changed criterion's J, under this one's last
    /// number).
    pub fn then(mut self, next: SearchOutcome) -> Self {
        let offset = self.iterations;
        self.history.extend(next.history.into_iter().map(|s| Step {
            iteration: s.iteration + offset,
            ..s
        }));
        SearchOutcome {
            u: next.u,
            cost: next.cost,
            stop: next.stop,
            iterations: self.iterations + next.iterations,
            tally: self.tally + next.tally,
            history: self.history,
            linearised: next.linearised,
        }
    }
}

/// A local search inside the box `[0, 1]^n`.
pub trait LocalSearch {
    /// Minimises J from `u0`, calling `observer(iteration, cost)` at the
    /// start and after every iteration.
    fn search<P: LeastSquares>(
        &self,
        problem: &P,
        u0: &[f64],
        observer: &mut dyn FnMut(usize, f64),
    ) -> Result<SearchOutcome, SolveError<P::Error>>;
}

/// Implements [`LocalSearch`] for a solver whose `minimize_observed`
/// result converts into a [`SearchOutcome`].
macro_rules! local_search {
    ($solver:ty) => {
        impl LocalSearch for $solver {
            fn search<P: LeastSquares>(
                &self,
                problem: &P,
                u0: &[f64],
                observer: &mut dyn FnMut(usize, f64),
            ) -> Result<SearchOutcome, SolveError<P::Error>> {
                self.minimize_observed(problem, u0, observer)
                    .map(SearchOutcome::from)
            }
        }
    };
}

local_search!(LevenbergMarquardt);
local_search!(Bfgs);

impl<E> From<LmResult<E>> for SearchOutcome {
    fn from(r: LmResult<E>) -> Self {
        let tally = Tally {
            simulations: r.residual_evaluations,
            with_sensitivities: r.jacobian_evaluations,
            failed: r.failed_evaluations,
        };
        let history = r.history.into_iter().map(|h| (h.iteration, h.cost, h.u));
        // A factor R instead of J when the problem took it by blocks.
        let linearised = (r.jacobian.nrows() == r.residuals.len()).then_some(Linearised {
            residuals: r.residuals,
            jacobian: r.jacobian,
        });
        SearchOutcome {
            linearised,
            ..outcome(r.u, r.cost, r.stop_reason, r.iterations, tally, history)
        }
    }
}

impl<E> From<BfgsResult<E>> for SearchOutcome {
    fn from(r: BfgsResult<E>) -> Self {
        let tally = Tally {
            simulations: r.cost_evaluations,
            with_sensitivities: 0,
            failed: r.failed_evaluations,
        };
        let history = r.history.into_iter().map(|h| (h.iteration, h.cost, h.u));
        outcome(r.u, r.cost, r.stop_reason, r.iterations, tally, history)
    }
}
/// A search's outcome from its parts; `history` as (iteration, J, u).
fn outcome(
    u: Vec<f64>,
    cost: f64,
    stop: StopReason,
    iterations: usize,
    tally: Tally,
    history: impl Iterator<Item = (usize, f64, Vec<f64>)>,
) -> SearchOutcome {
    SearchOutcome {
        u,
        cost,
        stop,
        iterations,
        tally,
        history: history
            .map(|(iteration, cost, u)| Step { iteration, cost, u })
            .collect(),
        linearised: None,
    }
}
