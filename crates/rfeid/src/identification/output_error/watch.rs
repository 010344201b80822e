//! The criterion at a plan point, watched as the simulation runs: J is a
//! sum of squares over the samples (eq. 13), so the sum over the samples
//! simulated so far is a lower bound of J, and a point whose running sum
//! passes a limit cannot have J below it. The plan ranks its points, and
//! stops simulating one there (`crate::identification::pipeline`, the
//! plan's batches).
//!
//! Each term of the running sum is the square of a residual exactly as J's
//! own: weighted by `√(w_e w_ec)`, calibrated as the simulator calibrates,
//! and whitened by the sensor's filter, which is causal (sample k's
//! whitened residual needs samples up to k alone), continued from check to
//! check as the factor by blocks continues it
//! ([`crate::identification::noise::ar::Whitener::apply_after`]). The
//! squares are never negative and rounding only adds to a sum of them, so
//! the running sum never decreases; it is summed in another order than J,
//! which the limit's margin covers (`crate::identification::pipeline`).
use super::part::{Part, PartWorkspace};
use super::{OutputError, OutputErrorWorkspace};
use crate::identification::problem::{finite_cost, EvalError};
use crate::simulation::{Response, SimulationError};
use rayon::prelude::*;
use std::time::Instant;

/// Samples between two checks of a watched evaluation's running sum, for a
/// record of `samples`: about 64 checks a record, each at least 16 samples
/// after the last and at most 1024.
fn check_every(samples: usize) -> usize {
    (samples / 64).clamp(16, 1024)
}

/// J at a point as [`OutputError::cost_watched`] found it.
#[derive(Debug, Clone, PartialEq)]
pub struct Watched {
    /// J (eq. 13) or why it could not be evaluated, as
    /// [`crate::identification::problem::evaluate_cost`] gives them, bit
    /// for bit; `None` when a running sum passed the limit and the
    /// evaluation stopped there (a campaign's: any experiment's own sum).
    pub outcome: Option<Result<f64, EvalError<SimulationError>>>,
    /// The largest running sum the checks saw (a campaign's: the largest
    /// experiment's), 0 before the first check. An evaluation against a
    /// limit stops if and only if this exceeds the limit, so a point
    /// evaluated whole (a shard's) records whether one with any limit
    /// would have stopped.
    pub reach: f64,
}

impl OutputError<'_> {
    /// J at `u` (residuals into `r`), each experiment's running sum
    /// checked every few samples; its simulation stops once the sum is
    /// above `limit` (never for `limit = +∞`). Counted as one plain
    /// simulation per experiment, abandoned or not.
    pub fn cost_watched(
        &self,
        ws: &mut OutputErrorWorkspace,
        u: &[f64],
        r: &mut [f64],
        limit: f64,
    ) -> Watched {
        if let Err(e) = self.check_cancel() {
            return Watched {
                outcome: Some(Err(EvalError::Problem(e))),
                reach: 0.0,
            };
        }
        let since = Instant::now();
        let run = |part: &Part<'_>, pws: &mut PartWorkspace, r: &mut [f64]| {
            let mut reach = 0.0;
            let result = part.residuals_watched(pws, (u, &self.maps), r, limit, &mut reach);
            (result, reach)
        };
        if let ([part], [pws]) = (self.parts.as_slice(), ws.parts.as_mut_slice()) {
            let one = run(part, pws, r);
            return self.combine(std::slice::from_ref(&one), r, since);
        }
        let rows = self.split_rows(r);
        let results: Vec<_> = self
            .parts
            .par_iter()
            .zip(ws.parts.par_iter_mut())
            .zip(rows)
            .map(|((part, pws), r)| run(part, pws, r))
            .collect();
        self.combine(&results, r, since)
    }

    /// The point's outcome from each experiment's (whether it ran to the
    /// end, and its reach): abandoned if any experiment was, else the first
    /// failure in experiment order, else J; counted.
    fn combine(
        &self,
        results: &[(Result<bool, SimulationError>, f64)],
        r: &[f64],
        since: Instant,
    ) -> Watched {
        let failed = results.iter().filter(|(x, _)| x.is_err()).count();
        self.count_runs(results.len(), failed, since);
        let reach = results.iter().fold(0.0_f64, |m, (_, x)| m.max(*x));
        let abandoned = results.iter().any(|(x, _)| matches!(x, Ok(false)));
        if abandoned {
            self.count_abandoned(1);
            return Watched {
                outcome: None,
                reach,
            };
        }
        let failure = results.iter().find_map(|(x, _)| x.as_ref().err());
        Watched {
            outcome: Some(match failure {
                Some(e) => Err(EvalError::Problem(e.clone())),
                None => finite_cost(r),
            }),
            reach,
        }
    }
}

impl Part<'_> {
    /// [`Part::residuals`] with the running sum of squares checked every
    /// few samples: `Ok(false)` when it passed `limit` and the simulation
    /// stopped there (`r` is then not filled). `reach`: the largest sum a
    /// check saw.
    fn residuals_watched(
        &self,
        ws: &mut PartWorkspace,
        (u, maps): (&[f64], &[crate::identification::box_map::BoxMap]),
        r: &mut [f64],
        limit: f64,
        reach: &mut f64,
    ) -> Result<bool, SimulationError> {
        self.all_params(u, maps, &mut ws.params);
        let PartWorkspace {
            sim,
            response,
            params,
            past,
            line,
            block,
            ..
        } = ws;
        past.iter_mut().for_each(Vec::clear);
        let mut running = Running {
            next: self.data.first,
            sum: 0.0,
        };
        let every = check_every(self.data.measured.n_samples);
        let complete =
            self.data
                .sim
                .run_watched(params, sim, response, every, &mut |samples, motion| {
                    running.take(self, params, motion, samples, (past, line, block));
                    *reach = reach.max(running.sum);
                    *reach > limit
                })?;
        if complete {
            self.fill_residuals(response, r);
        }
        Ok(complete)
    }
}

/// A running sum of squared residuals, and the first sample not yet in it.
struct Running {
    next: usize,
    sum: f64,
}

impl Running {
    /// Adds the residuals of the samples up to `samples` (exclusive) of the
    /// run's `motion` (before calibration) at `params`. Does not allocate
    /// once the buffers have grown to a check's samples.
    fn take(
        &mut self,
        part: &Part<'_>,
        params: &[f64],
        motion: &Response,
        samples: usize,
        (past, line, block): (&mut [Vec<f64>], &mut Vec<f64>, &mut Vec<f64>),
    ) {
        let from = self.next;
        if samples <= from {
            return;
        }
        for (c, sensor) in part.data.sim.model().sensors.iter().enumerate() {
            let (plain, gain, offset) = (
                sensor.is_plain(),
                sensor.gain.eval(params),
                sensor.offset.eval(params),
            );
            // The reading as `calibration` makes it, the residual as
            // `Part::fill_residuals`.
            let w = part.sqrt_weights[c];
            let residual = |(m, y): (&f64, &f64)| {
                let g = if plain { *m } else { gain * *m + offset };
                w * (g - y)
            };
            let g = &motion.sensor(c)[from..samples];
            let y = &part.data.measured.sensor(c)[from..samples];
            let filter = &part.whitening[c];
            if filter.order() == 0 {
                for v in g.iter().zip(y).map(residual) {
                    self.sum += v * v;
                }
            } else {
                block.clear();
                block.extend(g.iter().zip(y).map(residual));
                filter.apply_after(&mut past[c], block, line);
                for v in block.iter() {
                    self.sum += v * v;
                }
            }
        }
        self.next = samples;
    }
}
