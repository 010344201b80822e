//! Many sensitivity columns in parallel (issue 12).
//!
//! The columns of the sensitivity equation (eq. 27–28) are independent of
//! one another given the state: each goes through the same operations
//! whichever columns share its run (`tangent`, `sparse_tangent`). So the
//! parameters are split into groups, in order, and each group is integrated
//! with its own copy of the state on the current rayon pool. A group holds
//! at most [`COLUMN_GROUP`] columns, and there are at least as many groups
//! as threads when the columns allow ([`group_size`]): each group costs one
//! extra integration of the state, a small part of its columns, and keeps
//! a thread busy. Since no column depends on its group, the results do not
//! depend on the number of threads, bit for bit
//! (`tests/sensitivity_threads.rs`).
use super::response::Response;
use super::simulator::Simulator;
use super::structure::ComponentRow;
use super::workspace::GroupBuffers;
use super::SimulationError;
use crate::model::Law;
use rayon::prelude::*;

/// The most parameters integrated in one run.
pub const COLUMN_GROUP: usize = 16;

/// Parameters per group for `r` parameters on `threads` threads, each run
/// carrying `spare` columns after them (the split column of a model with
/// contacts, `Tangent::shift`): one group per thread, its parameters and
/// spare columns filling multiples of four (the kernels' SIMD width), from
/// 4 to [`COLUMN_GROUP`] columns.
pub fn group_size(r: usize, threads: usize, spare: usize) -> usize {
    (r.div_ceil(threads.max(1)) + spare)
        .next_multiple_of(4)
        .clamp(4, COLUMN_GROUP)
        - spare
}

/// The columns a run of `sim` carries after its parameters': the split
/// column when the model has a contact (`Tangent::shift`).
pub(crate) fn spare_columns(sim: &Simulator<'_>) -> usize {
    let contact = |c: &ComponentRow| matches!(c.law, Law::Contact(_));
    usize::from(sim.structure().components.iter().any(contact))
}

impl Simulator<'_> {
    /// The response at `params` into `out` and the sensitivities to `wrt`
    /// into `values` (observation × parameter, row-major, already sized),
    /// in groups of `size` columns in parallel.
    pub(crate) fn integrate_groups(
        &self,
        params: &[f64],
        (wrt, size): (&[usize], usize),
        groups: &mut Vec<GroupBuffers>,
        out: &mut Response,
        values: &mut [f64],
    ) -> Result<(), SimulationError> {
        let rows = self.model().sensors.len() * self.model().sampling.n_samples();
        let count = wrt.len().div_ceil(size);
        groups.resize_with(count, GroupBuffers::default);
        groups
            .par_iter_mut()
            .zip(wrt.par_chunks(size))
            .try_for_each(|(g, cols)| {
                let out = g.out.get_or_insert_with(|| self.response_buffer());
                g.sens.clear();
                g.sens.resize(rows * cols.len(), 0.0);
                self.integrate_columns(params, cols, &mut g.ws, out, &mut g.sens)
            })?;
        let r = wrt.len();
        for (i, g) in groups.iter().enumerate() {
            let (c0, w) = (i * size, g.sens.len() / rows.max(1));
            for (dst, src) in values.chunks_exact_mut(r).zip(g.sens.chunks_exact(w)) {
                dst[c0..c0 + w].copy_from_slice(src);
            }
        }
        if let Some(first) = groups.first().and_then(|g| g.out.as_ref()) {
            out.clone_from(first);
        }
        Ok(())
    }
}
