//! The runs of a [`Simulator`]: the response, the response with its
//! sensitivities (in parallel groups of columns when there are many), and
//! runs over part of the record or watched sample by sample.
use super::columns::{group_size, spare_columns};
use super::response::{Response, Sensitivities};
use super::run::{Span, Watch};
use super::simulator::Simulator;
use super::workspace::Workspace;
use super::SimulationError;
#[cfg(doc)]
use crate::model::Model;

impl<'m> Simulator<'m> {
    /// Simulates at `params` (all parameters, SI) into `out`.
    pub fn run(
        &self,
        params: &[f64],
        ws: &mut Workspace,
        out: &mut Response,
    ) -> Result<(), SimulationError> {
        self.integrate(params, &[], ws, out, None, &mut Span::default())?;
        super::calibration::apply(self.model, params, &[], out, None);
        Ok(())
    }

    /// Simulates at `params` and computes the sensitivities of every sample to
    /// the parameters `wrt` (indices into [`Model::parameters`]).
    pub fn run_with_sensitivities(
        &self,
        params: &[f64],
        wrt: &[usize],
        ws: &mut Workspace,
        out: &mut Response,
        sens: &mut Sensitivities,
    ) -> Result<(), SimulationError> {
        sens.wrt.clear();
        sens.wrt.extend_from_slice(wrt);
        sens.values.clear();
        // Sized from the model, not from `out`, which may be a reused buffer
        // of another shape (`integrate` resizes it).
        let rows = self.model.sensors.len() * self.model.sampling.n_samples();
        sens.values.resize(rows * wrt.len(), 0.0);
        let threads = rayon::current_num_threads();
        let size = group_size(wrt.len(), threads, spare_columns(self));
        if wrt.len() > size {
            let mut groups = std::mem::take(&mut ws.groups);
            let columns = (wrt, size);
            let result = self.integrate_groups(params, columns, &mut groups, out, &mut sens.values);
            ws.groups = groups;
            result?;
        } else {
            self.integrate(
                params,
                wrt,
                ws,
                out,
                Some(&mut sens.values),
                &mut Span::default(),
            )?;
        }
        super::calibration::apply(self.model, params, wrt, out, Some(&mut sens.values));
        Ok(())
    }

    /// [`Simulator::run`], watched: after every `every` samples short of
    /// the record's end, `watch(samples, motions)` is asked whether to go
    /// on, with the number of samples recorded and the sensor motions so
    /// far (before calibration: `motions.sensor(c)[..samples]`). When it
    /// says stop (`true`), the run ends there with `Ok(false)`, and `out`
    /// holds the motions so far, uncalibrated; `Ok(true)`: the whole
    /// record, as [`Simulator::run`] gives it, bit for bit.
    pub fn run_watched(
        &self,
        params: &[f64],
        ws: &mut Workspace,
        out: &mut Response,
        every: usize,
        watch: &mut Watch<'_>,
    ) -> Result<bool, SimulationError> {
        let mut span = Span {
            watch: Some(watch),
            every: every.max(1),
            next_check: every.max(1),
            ..Span::default()
        };
        ws.stopped = false;
        let run = self.integrate(params, &[], ws, out, None, &mut span);
        if span.stopped {
            ws.stopped = false;
            return Ok(false);
        }
        run?;
        super::calibration::apply(self.model, params, &[], out, None);
        Ok(true)
    }

    /// Simulates at `params` over the part of the record `span` gives,
    /// calling its observer at each sample: the response there, as
    /// [`Simulator::run`] gives it over the whole record.
    pub fn run_span(
        &self,
        params: &[f64],
        ws: &mut Workspace,
        out: &mut Response,
        span: &mut Span<'_>,
    ) -> Result<(), SimulationError> {
        self.integrate(params, &[], ws, out, None, span)?;
        super::calibration::apply(self.model, params, &[], out, None);
        Ok(())
    }
}
