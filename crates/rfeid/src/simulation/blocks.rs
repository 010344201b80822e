//! A run with sensitivities handed out one block of samples at a time, so
//! that the sensitivities of a long record (sensors × samples × parameters)
//! are never held whole: the identification turns each block into rows of
//! the Jacobian's triangular factor and lets it go.
//!
//! Each group of columns (`columns`) runs a block from the state and
//! sensitivities where its previous block ended, so a block is computed by
//! the same operations as in one run over the whole record: the blocks,
//! put end to end, are [`Simulator::run_with_sensitivities`]'s response and
//! sensitivities bit for bit (`tests` below).
use super::calibration;
use super::columns::{group_size, spare_columns};
use super::response::Response;
use super::run::{SampleState, SensitivityState, Span};
use super::simulator::Simulator;
use super::workspace::{GroupBuffers, Workspace};
use super::SimulationError;
use rayon::prelude::*;

/// One block of a run by blocks.
#[derive(Debug, Clone, Copy)]
pub struct Block<'a> {
    /// The record's index of the block's first sample.
    pub first: usize,
    /// The readings of the block's samples, sensor by sensor.
    pub response: &'a Response,
    /// Their sensitivities: one row of `wrt.len()` values per sensor and
    /// sample, sensor by sensor, as [`super::Sensitivities::values`] over
    /// the block.
    pub sensitivities: &'a [f64],
}

/// Where a group's next block starts: the state and sensitivities at the
/// last sample of its previous block.
type Resume = Option<(SampleState, SensitivityState)>;

impl Simulator<'_> {
    /// [`Simulator::run_with_sensitivities`] handed to `sink` in blocks of
    /// `block` samples (the last one shorter), in record order; the
    /// columns run in parallel groups as there. Stops at the first error,
    /// the sink's included.
    pub fn run_with_sensitivities_by_blocks(
        &self,
        params: &[f64],
        wrt: &[usize],
        ws: &mut Workspace,
        block: usize,
        sink: &mut dyn FnMut(Block<'_>) -> Result<(), SimulationError>,
    ) -> Result<(), SimulationError> {
        let threads = rayon::current_num_threads();
        let size = group_size(wrt.len(), threads, spare_columns(self));
        let chunks: Vec<&[usize]> = match wrt.is_empty() {
            true => vec![&[]],
            false => wrt.chunks(size).collect(),
        };
        let mut groups = std::mem::take(&mut ws.groups);
        groups.resize_with(chunks.len(), GroupBuffers::default);
        let mut resume: Vec<Resume> = vec![None; chunks.len()];
        let (mut response, mut values) = (Response::zeros(0, 0), Vec::new());
        let n = self.model().sampling.n_samples();
        let mut first = 0;
        let mut result = Ok(());
        while first < n && result.is_ok() {
            let len = block.max(1).min(n - first);
            let skip = usize::from(first > 0);
            result = groups
                .par_iter_mut()
                .zip(resume.par_iter_mut())
                .zip(chunks.par_iter())
                .try_for_each(|((g, at), cols)| self.group_block(params, cols, g, at, len + skip))
                .and_then(|()| {
                    gather(&groups, (len, skip), &mut response);
                    gather_sens(
                        &groups,
                        &chunks,
                        (size, wrt.len()),
                        (len, skip),
                        &mut values,
                    );
                    sink(Block {
                        first,
                        response: &response,
                        sensitivities: &values,
                    })
                });
            first += len;
        }
        ws.groups = groups;
        result
    }

    /// Runs `samples` samples of one group from where it stopped (`at`;
    /// `None`: the record's start), and leaves in `at` where it stops.
    fn group_block(
        &self,
        params: &[f64],
        cols: &[usize],
        g: &mut GroupBuffers,
        at: &mut Resume,
        samples: usize,
    ) -> Result<(), SimulationError> {
        let resume = at.take();
        let last = resume.as_ref().map_or(0, |(s, _)| s.sample) + samples - 1;
        let mut span = Span {
            resume,
            samples: Some(samples),
            ..Span::default()
        };
        let out = g.out.get_or_insert_with(|| Response::zeros(0, 0));
        g.sens.clear();
        g.sens
            .resize(self.model().sensors.len() * samples * cols.len(), 0.0);
        self.integrate(params, cols, &mut g.ws, out, Some(&mut g.sens), &mut span)?;
        calibration::apply(self.model(), params, cols, out, Some(&mut g.sens));
        let state = SampleState {
            sample: last,
            y: g.ws.y.clone(),
            z: g.ws.z.y.clone(),
        };
        let sens = SensitivityState {
            sy: g.ws.sy.clone(),
            z_sy: g.ws.z.sy.clone(),
        };
        *at = Some((state, sens));
        Ok(())
    }
}

/// The block's readings, from the first group's run, without its first
/// `skip` samples (the previous block's last).
fn gather(groups: &[GroupBuffers], (len, skip): (usize, usize), response: &mut Response) {
    let run = groups[0].out.as_ref().expect("every group ran");
    response.n_samples = len;
    response.n_sensors = run.n_sensors;
    response.values.clear();
    for c in 0..run.n_sensors {
        let from = c * (len + skip) + skip;
        response
            .values
            .extend_from_slice(&run.values[from..from + len]);
    }
}

/// The block's sensitivities, each group's columns into their place in
/// rows of `r`, without the first `skip` samples.
fn gather_sens(
    groups: &[GroupBuffers],
    chunks: &[&[usize]],
    (size, r): (usize, usize),
    (len, skip): (usize, usize),
    values: &mut Vec<f64>,
) {
    let sensors = groups[0].out.as_ref().map_or(0, |o| o.n_sensors);
    values.clear();
    values.resize(sensors * len * r, 0.0);
    for (i, (g, cols)) in groups.iter().zip(chunks).enumerate() {
        let (c0, w) = (i * size, cols.len());
        for c in 0..sensors {
            for k in 0..len {
                let src = (c * (len + skip) + skip + k) * w;
                let dst = (c * len + k) * r + c0;
                values[dst..dst + w].copy_from_slice(&g.sens[src..src + w]);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::model_file::load_model;
    use crate::model::Model;
    use crate::simulation::Sensitivities;
    use std::path::Path;

    fn example(name: &str) -> Model {
        let path = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../examples")
            .join(name)
            .join("model.toml");
        load_model(&path).expect("example loads")
    }

    /// The blocks of `block` samples put end to end.
    fn by_blocks(
        sim: &Simulator<'_>,
        p: &[f64],
        wrt: &[usize],
        block: usize,
    ) -> (Vec<Vec<f64>>, Vec<f64>) {
        let (s, n, r) = (
            sim.model().sensors.len(),
            sim.model().sampling.n_samples(),
            wrt.len(),
        );
        let mut readings = vec![Vec::new(); s];
        let mut sens = vec![0.0; s * n * r];
        let mut expected_first = 0;
        sim.run_with_sensitivities_by_blocks(p, wrt, &mut Workspace::default(), block, &mut |b| {
            assert_eq!(b.first, expected_first);
            let len = b.response.n_samples;
            expected_first += len;
            for (c, out) in readings.iter_mut().enumerate() {
                out.extend_from_slice(b.response.sensor(c));
                for k in 0..len {
                    let (src, dst) = ((c * len + k) * r, (c * n + b.first + k) * r);
                    sens[dst..dst + r].copy_from_slice(&b.sensitivities[src..src + r]);
                }
            }
            Ok(())
        })
        .expect("runs");
        assert_eq!(expected_first, n);
        (readings, sens)
    }

    fn check(model: &Model, blocks: &[usize], threads: &[usize]) {
        let sim = Simulator::new(model);
        let p = model.nominal();
        let wrt = model.identified();
        let mut whole = sim.response_buffer();
        let mut sens = Sensitivities {
            wrt: Vec::new(),
            values: Vec::new(),
        };
        sim.run_with_sensitivities(&p, &wrt, &mut Workspace::default(), &mut whole, &mut sens)
            .expect("runs");
        for &threads in threads {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            for &block in blocks {
                let (readings, values) = pool.install(|| by_blocks(&sim, &p, &wrt, block));
                for (c, got) in readings.iter().enumerate() {
                    assert_eq!(
                        got.as_slice(),
                        whole.sensor(c),
                        "sensor {c}, blocks of {block}"
                    );
                }
                assert!(
                    values == sens.values,
                    "sensitivities, blocks of {block}, {threads} threads"
                );
            }
        }
    }

    /// Knee–column (gravity, power laws whose zero crossings split steps,
    /// 16 columns in groups): the blocks are the whole run bit for bit,
    /// for blocks of 1, 7 and 1000 samples and a block longer than the
    /// record, on one thread and on three (other groups).
    #[test]
    fn blocks_end_to_end_are_the_whole_run_bit_for_bit() {
        check(&example("knee-column"), &[1, 7, 1000, 10_000], &[1, 3]);
    }

    /// The same with Bouc–Wen internal states and their sensitivities.
    #[test]
    fn blocks_carry_the_internal_states_and_their_sensitivities() {
        let mut m = example("bouc-wen");
        m.sampling.duration = 0.5;
        check(&m, &[1, 100], &[2]);
    }
}
