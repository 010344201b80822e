//! One experiment's Jacobian handed to its triangular factor block by block
//! ([`BlockedQr`]), straight from a run by blocks
//! ([`crate::simulation::Block`]): the sensitivities of a long record
//! (sensors × samples × parameters, eq. 27–28) are never held whole.
//!
//! A block's rows are the rows [`Part::residuals_jacobian`] writes for its
//! samples, weighted and whitened by the same arithmetic: the whitening
//! filter `A(q)` reaches back `p` samples, so each sensor keeps its last
//! `p` unfiltered rows and filters them ahead of the block's
//! ([`crate::identification::noise::ar::Whitener::apply_after`]). The residuals into `r` are those of
//! [`Part::residuals`] bit for bit.
use super::part::{Part, PartWorkspace};
use super::OutputError;
use crate::identification::blocked_qr::BlockedQr;
use crate::identification::box_map::BoxMap;
use crate::identification::cancel::Cancel;
use crate::simulation::{Block, SimulationError};
use nalgebra::DMatrix;

/// Samples per block of a run by blocks, unless set
/// ([`super::OutputError::set_block_samples`]): small beside a long record, long
/// beside the cost of starting a block (the static equilibrium, the
/// kernel's set-up).
pub(super) const BLOCK_SAMPLES: usize = 4096;

impl OutputError<'_> {
    /// Bytes the whole Jacobian (residuals × parameters) may take: a larger
    /// one is never held whole, but handed to its triangular factor block
    /// by block, straight from the simulation
    /// ([`crate::identification::problem::LeastSquares::residuals_factor`]).
    /// 0 always takes it by blocks.
    pub fn set_jacobian_memory(&mut self, bytes: usize) {
        self.jacobian_memory = bytes;
    }

    /// Samples per block (≥ 1; 4096 unless set) when the Jacobian is taken
    /// by blocks: the same factor to rounding whatever the length.
    pub fn set_block_samples(&mut self, samples: usize) {
        self.block_samples = samples.max(1);
    }

    /// The bytes the whole Jacobian may take
    /// ([`OutputError::set_jacobian_memory`]).
    pub fn jacobian_memory(&self) -> usize {
        self.jacobian_memory
    }
}

impl Part<'_> {
    /// Residuals into `r` (this part's rows) and the Jacobian's rows into
    /// `qr`, in `n_cols` columns (the criterion's), block by block.
    pub(super) fn residuals_factor(
        &self,
        ws: &mut PartWorkspace,
        (u, maps): (&[f64], &[BoxMap]),
        r: &mut [f64],
        qr: &mut BlockedQr,
        (block, cancel): (usize, &Cancel),
    ) -> Result<(), SimulationError> {
        self.all_params(u, maps, &mut ws.params);
        for (d, &c) in ws.dx_du.iter_mut().zip(&self.cols) {
            *d = maps[c].derivative(u[c]);
        }
        let mut rows = Rows::new(self, qr.n_cols());
        let dx_du = &ws.dx_du;
        self.data.sim.run_with_sensitivities_by_blocks(
            &ws.params,
            &self.wrt,
            &mut ws.sim,
            block,
            &mut |b| {
                if cancel.is_set() {
                    return Err(SimulationError::Cancelled);
                }
                rows.take(self, b, dx_du, r, qr);
                Ok(())
            },
        )?;
        Ok(())
    }
}

/// The rows of one block and what the whitening carries between blocks.
struct Rows {
    /// The block's Jacobian rows (sensor by sensor) and residuals.
    jac: DMatrix<f64>,
    res: Vec<f64>,
    /// Per sensor, the last unfiltered residuals (at most the filter's
    /// order), and per sensor and column of the part, the same of the
    /// Jacobian.
    past_res: Vec<Vec<f64>>,
    past_jac: Vec<Vec<Vec<f64>>>,
    /// A filter's input: the past values, then the block's.
    line: Vec<f64>,
}

impl Rows {
    fn new(part: &Part<'_>, n_cols: usize) -> Self {
        let sensors = part.whitening.len();
        Rows {
            jac: DMatrix::zeros(0, n_cols),
            res: Vec::new(),
            past_res: vec![Vec::new(); sensors],
            past_jac: vec![vec![Vec::new(); part.cols.len()]; sensors],
            line: Vec::new(),
        }
    }

    /// Turns block `b` into rows of `qr`, writing its residuals into `r`.
    fn take(
        &mut self,
        part: &Part<'_>,
        b: Block<'_>,
        dx_du: &[f64],
        r: &mut [f64],
        qr: &mut BlockedQr,
    ) {
        let first = part.data.first;
        let len = b.response.n_samples;
        let k0 = b.first.max(first);
        if k0 >= b.first + len {
            return;
        }
        let (m, used, p) = (b.first + len - k0, part.samples_used(), part.wrt.len());
        let sensors = b.response.n_sensors;
        if self.jac.nrows() != sensors * m {
            self.jac = DMatrix::zeros(sensors * m, qr.n_cols());
            self.res.resize(sensors * m, 0.0);
        } else if part.cols.len() < qr.n_cols() {
            // A campaign's other experiments' columns: zero in these rows.
            self.jac.fill(0.0);
        }
        for c in 0..sensors {
            let w = part.sqrt_weights[c];
            let (g, y) = (b.response.sensor(c), part.data.measured.sensor(c));
            for i in 0..m {
                let (k, row) = (k0 + i, c * m + i);
                let raw = w * (g[k - b.first] - y[k]);
                r[c * used + k - first] = raw;
                self.res[row] = raw;
                let src = &b.sensitivities[(c * len + k - b.first) * p..][..p];
                for (j, &col) in part.cols.iter().enumerate() {
                    self.jac[(row, col)] = w * src[j] * dx_du[j];
                }
            }
            let filter = &part.whitening[c];
            if filter.order() == 0 {
                continue;
            }
            let rows = &mut self.res[c * m..(c + 1) * m];
            filter.apply_after(&mut self.past_res[c], rows, &mut self.line);
            // The whitened residuals are those of the whole record.
            r[c * used + k0 - first..][..m].copy_from_slice(rows);
            let n_rows = self.jac.nrows();
            let data = self.jac.as_mut_slice();
            for (j, &col) in part.cols.iter().enumerate() {
                let rows = &mut data[col * n_rows + c * m..col * n_rows + (c + 1) * m];
                filter.apply_after(&mut self.past_jac[c][j], rows, &mut self.line);
            }
        }
        qr.add_rows(&mut self.jac, &mut self.res);
    }
}
