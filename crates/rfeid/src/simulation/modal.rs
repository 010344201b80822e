//! Modal analysis of the model linearised at rest, or at the static
//! equilibrium under gravity.
//!
//! With `M = L Lᵀ` (L diagonal here, since M is), the undamped problem
//! `K_t φ = ω² M φ` becomes the symmetric `(L⁻¹ K_t L⁻ᵀ) x = ω² x`,
//! `φ = L⁻ᵀ x` (mass-normalised). Damping ratios are the modal projections
//! `ζ = φᵀ C φ / (2ω)`: exact for proportional damping, an approximation
//! otherwise (it neglects the coupling of modes through C).
//!
//! A power-law spring `a·sign(δ)|δ|^m` with m > 1 has zero slope at δ = 0:
//! linearised at rest it contributes no stiffness. The modes it alone would
//! restrain appear as zero-stiffness modes, which are reported, not an error.
//!
//! A free direction (no spring at all along it, [`super::free`]; a feed
//! axis driven through a damper or friction) is a rigid-body mode of zero
//! frequency at any linearisation point. Those modes are reported first,
//! each with its free direction in words and its shape along it; the other
//! zero-stiffness modes follow, their shapes M-orthogonal to the free ones.
use super::equilibrium::static_equilibrium;
use super::free::{free_directions, FreeSet};
use super::integrator::integrator;
use super::laws::power_law;
use super::simulator::Simulator;
use super::system::System;
use super::SimulationError;
use crate::model::Model;
use nalgebra::{DMatrix, SymmetricEigen};

/// One mode.
#[derive(Debug, Clone, serde::Serialize)]
pub struct Mode {
    /// Undamped natural frequency, Hz (0 for a zero-stiffness mode).
    pub frequency_hz: f64,
    /// Modal damping ratio ζ (None for a zero-stiffness mode).
    pub damping_ratio: Option<f64>,
    /// True when the linearised stiffness of this mode is zero (to rounding).
    pub zero_stiffness: bool,
    /// Mass-normalised shape, one entry per generalized coordinate.
    pub shape: Vec<f64>,
    /// For a free (rigid-body) mode, its direction in words (`carriage:
    /// free along x`); None for any other mode.
    pub free: Option<String>,
}

/// The result of a modal analysis.
#[derive(Debug, Clone, serde::Serialize)]
pub struct ModalAnalysis {
    /// Modes by increasing frequency.
    pub modes: Vec<Mode>,
    /// Whether the linearisation is at the static equilibrium under gravity.
    pub at_equilibrium: bool,
    /// Power-law components with zero slope at the linearisation point, as
    /// `element/component`.
    pub zero_slope_components: Vec<String>,
    /// The free directions in words ([`super::free`]): motions no spring
    /// restrains, each a mode of zero frequency.
    pub free_directions: Vec<String>,
}

/// Linearises at rest (or at equilibrium under gravity) and computes the modes.
pub fn modal_analysis(
    sim: &Simulator<'_>,
    params: &[f64],
) -> Result<ModalAnalysis, SimulationError> {
    let model = sim.model();
    let sys = &sim.system(params)?;
    let n = sys.n;
    let q = if model.starts_at_equilibrium() {
        static_equilibrium(sys, &[])?.q
    } else {
        vec![0.0; n]
    };
    let c = DMatrix::from_row_slice(n, n, &sys.damping_matrix(&q));
    let linv: Vec<f64> = sys.minv.iter().map(|m| m.sqrt()).collect();
    let eig = SymmetricEigen::new(mass_scaled_tangent(sys, &q));
    let lam_max = eig.eigenvalues.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&i, &j| eig.eigenvalues[i].total_cmp(&eig.eigenvalues[j]));
    let (zero, moving): (Vec<usize>, Vec<usize>) = order
        .into_iter()
        .partition(|&j| eig.eigenvalues[j] <= 1e-10 * lam_max);
    let free = free_directions(sys);
    let zero_shapes: Vec<Vec<f64>> = zero
        .iter()
        .map(|&j| eig.eigenvectors.column(j).iter().copied().collect())
        .collect();
    let mut modes = zero_modes(model, &free, zero_shapes, &linv);
    modes.extend(moving.into_iter().map(|j| {
        let omega = eig.eigenvalues[j].max(0.0).sqrt();
        let shape: Vec<f64> = (0..n).map(|i| linv[i] * eig.eigenvectors[(i, j)]).collect();
        let phi = nalgebra::DVector::from_column_slice(&shape);
        Mode {
            frequency_hz: omega / (2.0 * std::f64::consts::PI),
            damping_ratio: Some((phi.transpose() * &c * &phi)[(0, 0)] / (2.0 * omega)),
            zero_stiffness: false,
            shape,
            free: None,
        }
    }));
    Ok(ModalAnalysis {
        modes,
        at_equilibrium: model.starts_at_equilibrium(),
        zero_slope_components: zero_slope_components(sim, sys, &q),
        free_directions: free.descriptions(model),
    })
}

/// The natural frequencies (Hz) of the model linearised at rest (or at the
/// equilibrium under gravity) at `params`, as [`modal_analysis`] gives them
/// but from the eigenvalues alone, with how many of the zero ones are free
/// directions: all a check against the Nyquist frequency needs, at a
/// fraction of the cost.
pub fn rest_frequencies(
    sim: &Simulator<'_>,
    params: &[f64],
) -> Result<(Vec<f64>, usize), SimulationError> {
    let sys = &sim.system(params)?;
    let q = match sim.model().starts_at_equilibrium() {
        true => static_equilibrium(sys, &[])?.q,
        false => vec![0.0; sys.n],
    };
    let lam = mass_scaled_tangent(sys, &q).symmetric_eigenvalues();
    let lam_max = lam.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    let zero = lam.iter().filter(|&&v| v <= 1e-10 * lam_max).count();
    let frequencies = lam
        .iter()
        .map(|&v| match v <= 1e-10 * lam_max {
            true => 0.0,
            false => v.sqrt() / (2.0 * std::f64::consts::PI),
        })
        .collect();
    Ok((frequencies, free_directions(sys).len().min(zero)))
}

/// The zero-stiffness modes from the eigenvectors `zero` (mass-scaled
/// coordinates) of the zero eigenvalues: first one per free direction,
/// along it, then the rest of their span M-orthogonal to those. If the
/// free directions do not fit in that span (rounding at the threshold),
/// the eigenvectors as they are.
fn zero_modes(model: &Model, free: &FreeSet, zero: Vec<Vec<f64>>, linv: &[f64]) -> Vec<Mode> {
    let mode = |shape: Vec<f64>, free: Option<String>| Mode {
        frequency_hz: 0.0,
        damping_ratio: None,
        zero_stiffness: true,
        shape,
        free,
    };
    let rest = free.complement(&zero);
    if free.len() + rest.len() != zero.len() {
        let unscale = |x: Vec<f64>| x.iter().zip(linv).map(|(x, l)| l * x).collect();
        return zero.into_iter().map(|x| mode(unscale(x), None)).collect();
    }
    let mut modes: Vec<Mode> = free
        .directions
        .iter()
        .map(|d| {
            // Mass-normalised: φᵀ M φ = 1, with M = diag(1 / linv²).
            let norm = d
                .shape
                .iter()
                .zip(linv)
                .map(|(v, l)| (v / l).powi(2))
                .sum::<f64>()
                .sqrt();
            let shape = d.shape.iter().map(|v| v / norm).collect();
            mode(shape, Some(d.describe(model)))
        })
        .collect();
    modes.extend(
        rest.into_iter()
            .map(|x| mode(x.iter().zip(linv).map(|(x, l)| l * x).collect(), None)),
    );
    modes
}

/// Power-law components with zero slope at `q`, as `element/component`.
fn zero_slope_components(sim: &Simulator<'_>, sys: &System<'_>, q: &[f64]) -> Vec<String> {
    let model = sim.model();
    sim.structure()
        .components
        .iter()
        .zip(&sys.power_components())
        .filter_map(|(comp, pc)| {
            let (a, m) = (*pc)?;
            let (_, slope) = power_law(a, m, comp.row.dot(q));
            (slope == 0.0).then(|| {
                format!(
                    "{}/{}",
                    model.elements[comp.element].name,
                    crate::model::COMPONENT_NAMES[comp.dof]
                )
            })
        })
        .collect()
}

/// `L⁻¹ K_t(q) L⁻ᵀ` with `M = L Lᵀ`: its eigenvalues are the squared
/// undamped natural frequencies ω² of the model linearised at `q`.
fn mass_scaled_tangent(sys: &System<'_>, q: &[f64]) -> DMatrix<f64> {
    mass_scaled(sys, &sys.tangent_stiffness(q))
}

/// `L⁻¹ K L⁻ᵀ` of a stiffness `kt` (dense n×n, row-major), symmetrised.
fn mass_scaled(sys: &System<'_>, kt: &[f64]) -> DMatrix<f64> {
    let n = sys.n;
    let linv: Vec<f64> = sys.minv.iter().map(|m| m.sqrt()).collect();
    let a = DMatrix::from_fn(n, n, |i, j| linv[i] * kt[i * n + j] * linv[j]);
    (&a + a.transpose()) * 0.5
}

/// The highest undamped natural frequency, Hz, of the model linearised at
/// the coordinates `q` (any state, not only rest: a power-law spring
/// stiffens as it deforms, eq. 2–6).
pub fn highest_frequency_at(sys: &System<'_>, q: &[f64]) -> f64 {
    // The top of the spectrum only (Lanczos): a 300-coordinate model's
    // dense eigenvalues cost several times as much.
    highest_frequency_of(sys, &sys.tangent_stiffness(q))
}

/// The highest undamped natural frequency, Hz, of the stiffness `kt`
/// (dense n×n, row-major) on the model's masses.
pub fn highest_frequency_of(sys: &System<'_>, kt: &[f64]) -> f64 {
    let lam = super::lanczos::largest_eigenvalue(&mass_scaled(sys, kt)).max(0.0);
    lam.sqrt() / (2.0 * std::f64::consts::PI)
}

/// The highest natural frequency of the model linearised at rest (or at
/// equilibrium) at `params`, Hz; `None` if the modal analysis fails.
pub fn fastest_mode_hz(model: &Model, params: &[f64]) -> Option<f64> {
    let sim = Simulator::with_integrator(model, integrator(1));
    modal_analysis(&sim, params)
        .ok()?
        .modes
        .iter()
        .map(|m| m.frequency_hz)
        .filter(|f| f.is_finite())
        .reduce(f64::max)
}
