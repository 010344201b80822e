//! Sensor calibration (SPEC §5): a reading is `gain · motion + offset`,
//! where either may be a parameter. Applied to the simulated motion after
//! the integration, with its exact derivatives: for a sample `y = a g + b`,
//! `∂y/∂x_j = a ∂g/∂x_j + g [x_j = a] + [x_j = b]` (the rows of H₁ of
//! eq. 27–28).
use super::response::Response;
use crate::model::Model;

/// Turns the motions in `out` (and their sensitivities `sens` to the
/// parameters `wrt`, laid out as in [`super::Sensitivities`]) into
/// readings. A no-op for sensors with gain 1 and offset 0.
pub(super) fn apply(
    model: &Model,
    params: &[f64],
    wrt: &[usize],
    out: &mut Response,
    mut sens: Option<&mut Vec<f64>>,
) {
    let n = out.n_samples;
    let p = wrt.len();
    for (c, sensor) in model.sensors.iter().enumerate() {
        if sensor.is_plain() {
            continue;
        }
        let gain = sensor.gain.eval(params);
        let offset = sensor.offset.eval(params);
        let gain_col = sensor
            .gain
            .param()
            .and_then(|i| wrt.iter().position(|&w| w == i));
        let offset_col = sensor
            .offset
            .param()
            .and_then(|i| wrt.iter().position(|&w| w == i));
        let signal = &mut out.values[c * n..(c + 1) * n];
        for (k, y) in signal.iter_mut().enumerate() {
            if let Some(s) = sens.as_deref_mut() {
                let row = &mut s[(c * n + k) * p..(c * n + k + 1) * p];
                for v in row.iter_mut() {
                    *v *= gain;
                }
                if let Some(j) = gain_col {
                    row[j] += *y;
                }
                if let Some(j) = offset_col {
                    row[j] += 1.0;
                }
            }
            *y = gain * *y + offset;
        }
    }
}
