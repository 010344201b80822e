//! Cramér–Rao bounds on the estimates (eq. 26–29) and identifiability
//! warnings.
//!
//! ```text
//! D²(x̂) ≥ [H₁ᵀ(x̂) H₁(x̂)]⁻¹ s²                                  (eq. 26)
//! H₁ = [f_1 … f_r],   f_i = ∂g/∂x_i (all N simulated samples)   (eq. 27, 28)
//! s² = SSR / (N − r − 1)                                       (eq. 29)
//! ```
//!
//! The standard error of estimate i is `√(D²)_ii`, the correlation matrix
//! `D²_ij / √(D²_ii D²_jj)`. With residuals `r = y − g`, `∂r/∂x = −H₁`: the sign
//! does not matter, so the Jacobian of a least-squares problem can be passed
//! as it is ([`cramer_rao_normalised`] takes the one in normalised
//! coordinates, e.g. [`crate::identification::lm::LmResult::jacobian`]).
//! For a weighted criterion, pass the weighted Jacobian and weighted SSR.
//!
//! # Numerics
//!
//! Physical parameters differ by many orders of magnitude (a_n ~ 10¹⁵ N/m²,
//! h ~ 10⁴ N·s/m), so H₁ᵀH₁ is never formed in physical units. Each column
//! of H₁ is scaled to unit norm, `H₁ = H_s C`, `C = diag(‖f_i‖)`; `H_s = Q R`
//! and `R = U Σ Vᵀ` give `(H_sᵀH_s)⁻¹ = V Σ⁻² Vᵀ`, and
//! `D² = s² C⁻¹ V Σ⁻² Vᵀ C⁻¹`. The reported [`CramerRao::condition_number`]
//! is that of the scaled Fisher matrix `H_sᵀH_s` (`(σ_max/σ_min)²`), which
//! measures how well the parameters can be told apart whatever their units;
//! [`CramerRao::condition_number_raw`] is that of `H₁ᵀH₁` in SI units, which
//! mostly reflects the units and is only indicative above ~10¹⁶.
//!
//! # Caveat
//!
//! These are lower bounds on the variance of *unbiased* estimators, exact for
//! a model linear in x; they assume the model is correct and the measurement
//! errors are white Gaussian noise of equal variance (eq. 12, 14). Estimates
//! of a nonlinear model are usually biased (paper §3), and correlated errors
//! (e.g. an unmodelled resonance) make the true uncertainty larger.
use nalgebra::DMatrix;
use serde::Serialize;

use super::blocked_qr::BlockedQr;
use super::settings::{in_unit_interval, positive, SettingsError};

/// Thresholds of the identifiability analysis, validated when set.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct UncertaintySettings {
    correlation_threshold: f64,
    singular_tolerance: f64,
    condition_warning: f64,
}

impl Default for UncertaintySettings {
    /// `correlation_threshold` 0.99; `singular_tolerance` 1e-12 (on
    /// `σ_min/σ_max` of the scaled H₁, i.e. a scaled Fisher condition number
    /// ≥ 10²⁴ is singular); `condition_warning` 1e10 (scaled Fisher
    /// condition number above which a warning is given).
    fn default() -> Self {
        UncertaintySettings {
            correlation_threshold: 0.99,
            singular_tolerance: 1e-12,
            condition_warning: 1e10,
        }
    }
}

impl UncertaintySettings {
    /// |correlation| above which a pair is reported, in (0, 1).
    pub fn with_correlation_threshold(mut self, value: f64) -> Result<Self, SettingsError> {
        self.correlation_threshold = in_unit_interval("correlation_threshold", value)?;
        Ok(self)
    }
    /// Relative singular value `σ_min/σ_max` of the column-scaled H₁ at or
    /// below which the Fisher matrix counts as singular, in (0, 1).
    pub fn with_singular_tolerance(mut self, value: f64) -> Result<Self, SettingsError> {
        self.singular_tolerance = in_unit_interval("singular_tolerance", value)?;
        Ok(self)
    }
    /// Scaled condition number above which [`IdentifiabilityWarning::IllConditioned`]
    /// is given (> 1).
    pub fn with_condition_warning(mut self, value: f64) -> Result<Self, SettingsError> {
        let value = positive("condition_warning", value)?;
        if value <= 1.0 {
            return Err(SettingsError {
                name: "condition_warning",
                value,
                requirement: "> 1",
            });
        }
        self.condition_warning = value;
        Ok(self)
    }
    /// |correlation| threshold.
    pub fn correlation_threshold(&self) -> f64 {
        self.correlation_threshold
    }
    /// Singularity tolerance.
    pub fn singular_tolerance(&self) -> f64 {
        self.singular_tolerance
    }
    /// Condition-number warning threshold.
    pub fn condition_warning(&self) -> f64 {
        self.condition_warning
    }
}

/// A sign that some parameters are poorly identifiable from the data.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum IdentifiabilityWarning {
    /// The standard error of parameter `index` exceeds the width of its box
    /// (eq. 17): the data hardly constrain it.
    StdErrorExceedsBox {
        /// Parameter index.
        index: usize,
        /// Its standard error.
        std_error: f64,
        /// `x_max − x_min`.
        box_width: f64,
    },
    /// Parameters `first` and `second` are correlated beyond the threshold:
    /// the data determine mostly a combination of them.
    StrongCorrelation {
        /// Lower parameter index.
        first: usize,
        /// Higher parameter index.
        second: usize,
        /// Their correlation coefficient.
        correlation: f64,
        /// The combination the data fix best: `x_first − slope · x_second`
        /// with `slope = cov(first, second) / var(second)`, the regression of
        /// the first on the second (its variance is the first's times
        /// `1 − ρ²`).
        slope: f64,
        /// The standard error of that combination, in the first
        /// parameter's unit.
        combination_std_error: f64,
    },
    /// The column-scaled Fisher matrix is ill-conditioned.
    IllConditioned {
        /// Its condition number.
        condition_number: f64,
    },
}

/// The Cramér–Rao analysis could not be done.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum UncertaintyError {
    /// The Jacobian has no columns.
    #[error("no parameters to analyse")]
    NoParameters,
    /// `N − r − 1 ≤ 0` in eq. 29.
    #[error("{n_observations} observations are too few for {n_parameters} parameters (eq. 29 needs N - r - 1 > 0)")]
    TooFewObservations {
        /// N.
        n_observations: usize,
        /// r.
        n_parameters: usize,
    },
    /// The sum of squared residuals is negative or not finite.
    #[error("invalid sum of squared residuals {ssr}")]
    InvalidSsr {
        /// The given SSR.
        ssr: f64,
    },
    /// A Jacobian entry is NaN or infinite.
    #[error("the Jacobian entry ({row}, {column}) is not finite")]
    NonFiniteJacobian {
        /// Row (observation).
        row: usize,
        /// Column (parameter).
        column: usize,
    },
    /// The number of box widths differs from the number of parameters.
    #[error("{got} box widths given for {expected} parameters")]
    BoxCountMismatch {
        /// Number of parameters.
        expected: usize,
        /// Number of widths given.
        got: usize,
    },
    /// A box width is not finite and positive.
    #[error("box width {width} of parameter {index} is not finite and positive")]
    InvalidBoxWidth {
        /// Parameter index.
        index: usize,
        /// The width.
        width: f64,
    },
    /// The Fisher matrix H₁ᵀH₁ is singular: the listed parameters cannot be
    /// told apart (zero columns of H₁, or the largest components of the
    /// null-space directions).
    #[error("the Fisher matrix is singular (scaled condition number {condition_number:e}): parameters {parameters:?} cannot be told apart from the data")]
    Singular {
        /// Indices of the parameters involved.
        parameters: Vec<usize>,
        /// Scaled condition number (infinite for a zero column).
        condition_number: f64,
    },
}

/// Cramér–Rao bounds and identifiability diagnostics (eq. 26–29).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CramerRao {
    /// N, the number of scalar observations (rows of H₁).
    pub n_observations: usize,
    /// r, the number of parameters.
    pub n_parameters: usize,
    /// s² = SSR / (N − r − 1) (eq. 29).
    pub s2: f64,
    /// Lower bound of the covariance of x̂, `(H₁ᵀH₁)⁻¹ s²` (eq. 26), in the
    /// parameters' units.
    #[serde(serialize_with = "serialize_matrix")]
    pub covariance: DMatrix<f64>,
    /// Standard errors `√D²_ii`.
    pub std_errors: Vec<f64>,
    /// Correlation matrix (unit diagonal).
    #[serde(serialize_with = "serialize_matrix")]
    pub correlation: DMatrix<f64>,
    /// Condition number of the column-scaled Fisher matrix `H_sᵀH_s`.
    pub condition_number: f64,
    /// Condition number of `H₁ᵀH₁` in the parameters' units (indicative).
    pub condition_number_raw: f64,
    /// Identifiability warnings.
    pub warnings: Vec<IdentifiabilityWarning>,
    /// When `covariance` takes each sensor's own noise level
    /// ([`crate::identification::sensor_levels`]): eq. 26's covariance with
    /// the one s², `(H₁ᵀH₁)⁻¹ s²`, whose shape the criterion's curvature
    /// has (a profile's path follows it). `None`: `covariance` is that.
    #[serde(skip)]
    pub pooled: Option<DMatrix<f64>>,
}

fn serialize_matrix<S: serde::Serializer>(m: &DMatrix<f64>, s: S) -> Result<S::Ok, S::Error> {
    use serde::ser::SerializeSeq;
    let mut seq = s.serialize_seq(Some(m.nrows()))?;
    for row in m.row_iter() {
        seq.serialize_element(&row.iter().copied().collect::<Vec<f64>>())?;
    }
    seq.end()
}

/// Cramér–Rao analysis (eq. 26–29) from the Jacobian `h1` (N × r) of the
/// simulated observations with respect to the physical parameters x, the sum
/// of squared residuals `ssr` at x̂, and optionally the parameters' box widths
/// `x_max − x_min` (eq. 17) for the standard-error-versus-box warning.
pub fn cramer_rao(
    h1: &DMatrix<f64>,
    ssr: f64,
    box_widths: Option<&[f64]>,
    settings: &UncertaintySettings,
) -> Result<CramerRao, UncertaintyError> {
    let ones = vec![1.0; h1.ncols()];
    analyse(h1, &ones, ssr, box_widths, settings)
}

/// [`cramer_rao`] from the Jacobian `∂r/∂u` in normalised coordinates
/// (`x = x_min + u (x_max − x_min)`, so `∂/∂x_j = ∂/∂u_j / width_j`); the
/// result is in physical units. The column scaling of the analysis absorbs
/// the widths exactly, so this is as accurate as passing H₁ itself.
pub fn cramer_rao_normalised(
    jac_u: &DMatrix<f64>,
    ssr: f64,
    box_widths: &[f64],
    settings: &UncertaintySettings,
) -> Result<CramerRao, UncertaintyError> {
    check_widths(jac_u.ncols(), Some(box_widths))?;
    let factors: Vec<f64> = box_widths.iter().map(|w| 1.0 / w).collect();
    analyse(jac_u, &factors, ssr, Some(box_widths), settings)
}

/// [`cramer_rao`] from the Jacobian `∂r/∂u` in any normalised coordinate
/// whose chain-rule factors `dx_j/du_j` at the estimate are `dx_du` (see
/// [`crate::identification::box_map`]); the result is in physical units.
/// `box_widths` (`x_max − x_min`) serve the standard-error-versus-box
/// warning only. With `dx_du = box_widths` this is
/// [`cramer_rao_normalised`].
pub fn cramer_rao_mapped(
    jac_u: &DMatrix<f64>,
    ssr: f64,
    dx_du: &[f64],
    box_widths: &[f64],
    settings: &UncertaintySettings,
) -> Result<CramerRao, UncertaintyError> {
    check_widths(jac_u.ncols(), Some(box_widths))?;
    check_widths(jac_u.ncols(), Some(dx_du))?;
    let factors: Vec<f64> = dx_du.iter().map(|d| 1.0 / d).collect();
    analyse(jac_u, &factors, ssr, Some(box_widths), settings)
}

pub(crate) fn check_widths(r: usize, box_widths: Option<&[f64]>) -> Result<(), UncertaintyError> {
    let Some(widths) = box_widths else {
        return Ok(());
    };
    if widths.len() != r {
        return Err(UncertaintyError::BoxCountMismatch {
            expected: r,
            got: widths.len(),
        });
    }
    if let Some((index, &width)) = widths
        .iter()
        .enumerate()
        .find(|(_, w)| !(w.is_finite() && **w > 0.0))
    {
        return Err(UncertaintyError::InvalidBoxWidth { index, width });
    }
    Ok(())
}

/// The analysis on `h` whose column j, multiplied by `factors[j]`, is
/// `∂g/∂x_j`.
fn analyse(
    h: &DMatrix<f64>,
    factors: &[f64],
    ssr: f64,
    box_widths: Option<&[f64]>,
    settings: &UncertaintySettings,
) -> Result<CramerRao, UncertaintyError> {
    let (n_obs, r) = h.shape();
    check_inputs(h, n_obs, ssr)?;
    check_widths(r, box_widths)?;
    // Column scaling H = H_s C.
    let norms: Vec<f64> = h.column_iter().map(|c| c.norm()).collect();
    check_no_zero_column(&norms)?;
    let mut hs = h.clone();
    for (j, mut col) in hs.column_iter_mut().enumerate() {
        col /= norms[j];
    }
    let rs = hs.qr().unpack_r();
    from_scaled_factor(rs, &norms, n_obs, factors, ssr, box_widths, settings)
}

/// [`cramer_rao_mapped`] from the triangular factor of `∂r/∂u` accumulated
/// by row blocks ([`BlockedQr`]), for problems whose Jacobian is too large
/// to hold: `H₁ᵀH₁` depends on H₁ only through R (`H₁ = Q R`), and the
/// column norms of H₁ are those of R. Agrees with [`cramer_rao_mapped`] on
/// the whole Jacobian to rounding.
pub fn cramer_rao_blocked(
    qr: &BlockedQr,
    ssr: f64,
    dx_du: &[f64],
    box_widths: &[f64],
    settings: &UncertaintySettings,
) -> Result<CramerRao, UncertaintyError> {
    let r = qr.n_cols();
    check_widths(r, Some(box_widths))?;
    check_widths(r, Some(dx_du))?;
    let n_obs = qr.rows();
    check_inputs(qr.r(), n_obs, ssr)?;
    let norms = qr.column_norms();
    check_no_zero_column(&norms)?;
    let mut rs = qr.r().clone();
    for (j, mut col) in rs.column_iter_mut().enumerate() {
        col /= norms[j];
    }
    let factors: Vec<f64> = dx_du.iter().map(|d| 1.0 / d).collect();
    from_scaled_factor(rs, &norms, n_obs, &factors, ssr, Some(box_widths), settings)
}

/// What the bounds need of a Jacobian `m` (or its triangular factor) with
/// `n_obs` rows in all: parameters, more observations than r + 1 (eq. 29),
/// a finite SSR ≥ 0 and finite entries.
fn check_inputs(m: &DMatrix<f64>, n_obs: usize, ssr: f64) -> Result<(), UncertaintyError> {
    let r = m.ncols();
    if r == 0 {
        return Err(UncertaintyError::NoParameters);
    }
    if n_obs <= r + 1 {
        return Err(UncertaintyError::TooFewObservations {
            n_observations: n_obs,
            n_parameters: r,
        });
    }
    if !(ssr.is_finite() && ssr >= 0.0) {
        return Err(UncertaintyError::InvalidSsr { ssr });
    }
    for (column, col) in m.column_iter().enumerate() {
        if let Some(row) = col.iter().position(|v| !v.is_finite()) {
            return Err(UncertaintyError::NonFiniteJacobian { row, column });
        }
    }
    Ok(())
}

/// A parameter whose Jacobian column is zero cannot be identified.
pub(crate) fn check_no_zero_column(norms: &[f64]) -> Result<(), UncertaintyError> {
    let zero: Vec<usize> = (0..norms.len()).filter(|&j| norms[j] == 0.0).collect();
    if zero.is_empty() {
        Ok(())
    } else {
        Err(UncertaintyError::Singular {
            parameters: zero,
            condition_number: f64::INFINITY,
        })
    }
}

/// The analysis from `rs`, the triangular factor of the column-scaled
/// Jacobian `H_s = H C⁻¹` with `C = diag(norms)`.
pub(crate) fn from_scaled_factor(
    rs: DMatrix<f64>,
    norms: &[f64],
    n_obs: usize,
    factors: &[f64],
    ssr: f64,
    box_widths: Option<&[f64]>,
    settings: &UncertaintySettings,
) -> Result<CramerRao, UncertaintyError> {
    let r = rs.ncols();
    let svd = rs.clone().svd(false, true);
    let sigma = &svd.singular_values;
    let v = svd.v_t.as_ref().expect("V was requested").transpose();
    let (s_max, s_min) = (sigma[0], sigma[r - 1]);
    let condition_number = (s_max / s_min).powi(2);
    let regular = s_min > settings.singular_tolerance * s_max;
    if !regular {
        return Err(UncertaintyError::Singular {
            parameters: null_space_parameters(&v, sigma, settings.singular_tolerance * s_max),
            condition_number,
        });
    }
    // (H_sᵀH_s)⁻¹ = V Σ⁻² Vᵀ.
    let mut v_scaled = v.clone();
    for (k, mut col) in v_scaled.column_iter_mut().enumerate() {
        col /= sigma[k] * sigma[k];
    }
    let cov_s = &v_scaled * v.transpose();
    let s2 = ssr / (n_obs - r - 1) as f64;
    // Physical column norms c_j = ‖h_j‖ |factor_j|.
    let c: Vec<f64> = norms
        .iter()
        .zip(factors)
        .map(|(n, f)| n * f.abs())
        .collect();
    let covariance = DMatrix::from_fn(r, r, |i, j| s2 * cov_s[(i, j)] / (c[i] * c[j]));
    // A variance beyond f64's range may have a standard error within it.
    let se = |i: usize| match covariance[(i, i)].sqrt() {
        se if se.is_finite() => se,
        _ => s2.sqrt() * cov_s[(i, i)].sqrt() / c[i],
    };
    let std_errors: Vec<f64> = (0..r).map(se).collect();
    let correlation = DMatrix::from_fn(r, r, |i, j| {
        if i == j {
            1.0
        } else {
            cov_s[(i, j)] / (cov_s[(i, i)] * cov_s[(j, j)]).sqrt()
        }
    });
    // Raw condition number: singular values of R C.
    let mut rc = rs;
    for (j, mut col) in rc.column_iter_mut().enumerate() {
        col *= c[j];
    }
    let raw = rc.singular_values();
    let condition_number_raw = (raw.max() / raw.min()).powi(2);
    let warnings = warnings(
        &std_errors,
        &covariance,
        &correlation,
        condition_number,
        box_widths,
        settings,
    );
    Ok(CramerRao {
        n_observations: n_obs,
        n_parameters: r,
        s2,
        covariance,
        std_errors,
        correlation,
        condition_number,
        condition_number_raw,
        warnings,
        pooled: None,
    })
}

/// Parameters with a component ≥ 0.1 (1 % of the weight) in a right singular
/// vector whose singular value is ≤ `threshold`, sorted.
fn null_space_parameters(
    v: &DMatrix<f64>,
    sigma: &nalgebra::DVector<f64>,
    threshold: f64,
) -> Vec<usize> {
    let mut parameters: Vec<usize> = (0..sigma.len())
        .filter(|&k| sigma[k] <= threshold)
        .flat_map(|k| {
            let col = v.column(k);
            (0..col.len()).filter(move |&j| col[j].abs() >= 0.1)
        })
        .collect();
    parameters.sort_unstable();
    parameters.dedup();
    parameters
}

/// The identifiability warnings of a covariance and its correlations.
pub(super) fn warnings(
    std_errors: &[f64],
    covariance: &DMatrix<f64>,
    correlation: &DMatrix<f64>,
    condition_number: f64,
    box_widths: Option<&[f64]>,
    settings: &UncertaintySettings,
) -> Vec<IdentifiabilityWarning> {
    let mut warnings = Vec::new();
    if let Some(widths) = box_widths {
        for (index, (&std_error, &box_width)) in std_errors.iter().zip(widths).enumerate() {
            if std_error > box_width {
                warnings.push(IdentifiabilityWarning::StdErrorExceedsBox {
                    index,
                    std_error,
                    box_width,
                });
            }
        }
    }
    let r = std_errors.len();
    for first in 0..r {
        for second in first + 1..r {
            let correlation = correlation[(first, second)];
            if correlation.abs() > settings.correlation_threshold {
                let var = covariance[(first, first)] * (1.0 - correlation * correlation);
                warnings.push(IdentifiabilityWarning::StrongCorrelation {
                    first,
                    second,
                    correlation,
                    slope: covariance[(first, second)] / covariance[(second, second)],
                    combination_std_error: var.max(0.0).sqrt(),
                });
            }
        }
    }
    if condition_number > settings.condition_warning {
        warnings.push(IdentifiabilityWarning::IllConditioned { condition_number });
    }
    warnings
}
