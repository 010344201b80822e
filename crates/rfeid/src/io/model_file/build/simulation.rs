//! The `[simulation]` table: duration, sample rate, substeps, tolerance.
use super::ctx::*;
use crate::io::model_file::raw::*;
use crate::model::*;
use crate::units::Dimension;

/// The simulated duration, from the `[simulation]` table.
pub(super) fn simulation_duration(ctx: &Ctx, raw: &RawFile) -> Result<f64> {
    sampling(ctx, raw).map(|s| s.duration)
}

/// The `[simulation]` table, checked: positive duration and rate, 2 to 1e8 samples.
pub(super) fn sampling(ctx: &Ctx, raw: &RawFile) -> Result<Sampling> {
    let entry = "[simulation]";
    let sim = raw.simulation.as_ref().ok_or_else(|| {
        ctx.err(
            None,
            entry,
            "",
            "the model has no [simulation] table (duration, sample_rate)",
        )
    })?;
    let rs = sim.get_ref();
    let duration = ctx.number(
        required(ctx, &rs.duration, sim.span(), entry, "duration")?,
        Dimension::TIME,
        entry,
        "duration",
    )?;
    let rate_raw = required(ctx, &rs.sample_rate, sim.span(), entry, "sample_rate")?;
    let sample_rate = ctx.number(rate_raw, Dimension::FREQUENCY, entry, "sample_rate")?;
    if !(duration > 0.0) {
        return Err(ctx.err(
            rs.duration.as_ref().map(|d| d.span()),
            entry,
            "duration",
            "must be positive",
        ));
    }
    if !(sample_rate > 0.0) {
        return Err(ctx.err(
            Some(rate_raw.span()),
            entry,
            "sample_rate",
            "must be positive",
        ));
    }
    let n = (duration * sample_rate).round();
    if !(2.0..=1e8).contains(&n) {
        return Err(ctx.err(
            Some(sim.span()),
            entry,
            "duration",
            format!("duration × sample_rate gives {n} samples; it must be 2 to 1e8"),
        ));
    }
    let substeps = substeps(ctx, rs, entry)?;
    let tolerance = tolerance(ctx, rs, entry)?;
    Ok(Sampling {
        duration,
        sample_rate,
        substeps,
        tolerance,
    })
}

/// The optional number of substeps per sample: 1 to [`MAX_SUBSTEPS`](crate::simulation::MAX_SUBSTEPS).
fn substeps(ctx: &Ctx, rs: &RawSimulation, entry: &str) -> Result<Option<usize>> {
    match &rs.substeps {
        None => Ok(None),
        Some(s) if (1..=crate::simulation::MAX_SUBSTEPS as i64).contains(s.get_ref()) => {
            Ok(Some(*s.get_ref() as usize))
        }
        Some(s) => Err(ctx.err(
            Some(s.span()),
            entry,
            "substeps",
            "must be a whole number from 1 to 1000",
        )),
    }
}

/// The integrator's tolerance, within [`TOLERANCE_RANGE`](crate::simulation::TOLERANCE_RANGE).
fn tolerance(ctx: &Ctx, rs: &RawSimulation, entry: &str) -> Result<f64> {
    let Some(t) = &rs.tolerance else {
        return Ok(crate::simulation::DEFAULT_TOLERANCE);
    };
    let v = ctx.number(t, Dimension::DIMENSIONLESS, entry, "tolerance")?;
    if !crate::simulation::TOLERANCE_RANGE.contains(&v) {
        return Err(ctx.err(
            Some(t.span()),
            entry,
            "tolerance",
            crate::simulation::steps::tolerance_range_text(),
        ));
    }
    Ok(v)
}
