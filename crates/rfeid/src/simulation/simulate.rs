//! The runs of a [`Simulator`]: the response, the response with its
//! sensitivities (in parallel groups of columns when there are many), and
//! the generalized coordinates along the response.
use super::columns::group_size;
use super::response::{Response, Sensitivities};
use super::simulator::Simulator;
use super::structure::Row;
use super::workspace::Workspace;
use super::SimulationError;
#[cfg(doc)]
use crate::model::Model;
use crate::model::SensorKind;

impl<'m> Simulator<'m> {
    /// Simulates at `params` (all parameters, SI) into `out`.
    pub fn run(
        &self,
        params: &[f64],
        ws: &mut Workspace,
        out: &mut Response,
    ) -> Result<(), SimulationError> {
        self.integrate(params, &[], ws, out, None)?;
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
        let size = group_size(wrt.len(), rayon::current_num_threads());
        if wrt.len() > size {
            let mut groups = std::mem::take(&mut ws.groups);
            let columns = (wrt, size);
            let result = self.integrate_groups(params, columns, &mut groups, out, &mut sens.values);
            ws.groups = groups;
            result?;
        } else {
            self.integrate(params, wrt, ws, out, Some(&mut sens.values))?;
        }
        super::calibration::apply(self.model, params, wrt, out, Some(&mut sens.values));
        Ok(())
    }

    /// The generalized coordinates along the response at `params`, for
    /// analyses of the trajectory (not for the hot path): `values[i *
    /// n_samples + k]` is `q_i(t_k) − q_i(0)`, the initial state being rest
    /// or the static equilibrium under gravity. The same steps as
    /// [`Simulator::run`], with one displacement reading per coordinate.
    pub fn coordinates(
        &self,
        params: &[f64],
        ws: &mut Workspace,
    ) -> Result<Response, SimulationError> {
        let n = self.structure.n;
        let mut probe = self.clone();
        probe.structure.sensors = (0..n)
            .map(|i| {
                let mut h = [0.0; 6];
                h[i % 6] = 1.0;
                let row = Row {
                    blocks: vec![(i - i % 6, h)],
                };
                (SensorKind::Displacement, row)
            })
            .collect();
        let mut out = Response::zeros(n, self.model.sampling.n_samples());
        probe.integrate(params, &[], ws, &mut out, None)?;
        Ok(out)
    }
}
