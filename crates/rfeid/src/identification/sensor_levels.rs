//! The bounds of an equally weighted criterion whose sensors are not
//! equally noisy.
//!
//! Eq. 26 takes one s² (eq. 29) for every residual: it is the covariance
//! of x̂ when every sensor's noise has the same variance (eq. 14's w_c = 1
//! is then the maximum-likelihood weighting). Sensors of different kinds
//! or places rarely are: with the knee–column's three accelerometers,
//! each at 2 % of its own RMS, eq. 26 put the spread of the estimates'
//! errors at 0.5–1.4 times their standard errors, depending on the
//! parameter. The least-squares estimate is still consistent then; its
//! covariance is
//!
//! ```text
//! D² = A⁻¹ (Σ_c s_c² H_cᵀH_c) A⁻¹,   A = H₁ᵀH₁ = Σ_c H_cᵀH_c
//! s_c² = SSR_c · N / (N_c (N − r − 1))
//! ```
//!
//! with H_c the rows of H₁ (eq. 27–28) of sensor c, N_c their number and
//! SSR_c their sum of squared residuals. When every sensor's mean square is
//! the same, s_c² = s² and D² is eq. 26 exactly. The criterion's curvature
//! is still A: a profile of J (eq. 16) rises by s² κ_j χ² where eq. 26 has
//! it rise by s² χ², with κ_j = D²_jj / (s² A⁻¹)_jj the ratio of the two
//! variances ([`CramerRao::variance_ratio`]).
use nalgebra::DMatrix;

use super::uncertainty::{warnings, CramerRao, UncertaintySettings};

impl CramerRao {
    /// κ_j, the variance of estimate j over eq. 26's with the one s²: 1
    /// unless `covariance` takes each sensor's own noise level. A profile
    /// of J rises by s² κ_j χ² over the interval whose variance is
    /// `covariance`'s.
    pub fn variance_ratio(&self, j: usize) -> f64 {
        self.pooled
            .as_ref()
            .map_or(1.0, |p| self.covariance[(j, j)] / p[(j, j)])
    }
}

/// One sensor's rows of the (weighted) Jacobian in the search's
/// coordinates u, as their Gram matrix `J_cᵀJ_c`, and their sum of
/// squared (weighted) residuals.
#[derive(Debug, Clone)]
pub struct SensorRows {
    /// `J_cᵀJ_c` (r × r), in u.
    pub gram: DMatrix<f64>,
    /// SSR_c of the same rows.
    pub ssr: f64,
    /// N_c, the rows.
    pub rows: usize,
}

impl SensorRows {
    /// Each sensor's rows of a whole Jacobian `jac` (in u) and residuals
    /// `res`, the sensors' rows consecutive with `counts` rows each.
    pub fn split(jac: &DMatrix<f64>, res: &[f64], counts: &[usize]) -> Vec<SensorRows> {
        let mut start = 0;
        counts
            .iter()
            .map(|&n| {
                let rows = jac.rows(start, n);
                let ssr = res[start..start + n].iter().map(|v| v * v).sum();
                start += n;
                SensorRows {
                    gram: rows.transpose() * rows,
                    ssr,
                    rows: n,
                }
            })
            .collect()
    }
}

/// `bounds` (eq. 26 with one s²) turned into the covariance of x̂ with
/// each sensor's own noise level (module docs), with its standard errors,
/// correlations and identifiability warnings; `dx_du` are the chain-rule
/// factors of u at the estimate, `box_widths` serve the warnings. Unchanged
/// with fewer than two sensors, or when a sensor's level is not finite.
pub fn with_sensor_levels(
    bounds: CramerRao,
    sensors: &[SensorRows],
    dx_du: &[f64],
    box_widths: &[f64],
    settings: &UncertaintySettings,
) -> CramerRao {
    let (n, r) = (bounds.n_observations, bounds.n_parameters);
    let dof = n as f64 - r as f64 - 1.0;
    if sensors.len() < 2 || dof <= 0.0 || bounds.s2 <= 0.0 {
        return bounds;
    }
    // D_j = √(A⁻¹)_jj in x; the pooled covariance is s² D ρ D.
    let pooled = &bounds.covariance;
    let d: Vec<f64> = bounds
        .std_errors
        .iter()
        .map(|s| s / bounds.s2.sqrt())
        .collect();
    // M̃ = D (Σ_c s_c² H_cᵀH_c) D, with H_c = J_c diag(1/dx_du).
    let scale: Vec<f64> = d.iter().zip(dx_du).map(|(d, f)| d / f).collect();
    let mut meat = DMatrix::zeros(r, r);
    for s in sensors.iter().filter(|s| s.rows > 0) {
        let level = s.ssr * n as f64 / (s.rows as f64 * dof);
        if !level.is_finite() {
            return bounds;
        }
        meat += &s.gram * level;
    }
    let meat = DMatrix::from_fn(r, r, |i, j| meat[(i, j)] * scale[i] * scale[j]);
    let rho = &bounds.correlation;
    let inner = rho * meat * rho;
    let covariance = DMatrix::from_fn(r, r, |i, j| {
        let v = 0.5 * (inner[(i, j)] + inner[(j, i)]);
        v * d[i] * d[j]
    });
    if covariance.iter().any(|v| !v.is_finite()) || (0..r).any(|j| covariance[(j, j)] <= 0.0) {
        return bounds;
    }
    let std_errors: Vec<f64> = (0..r).map(|j| covariance[(j, j)].sqrt()).collect();
    let correlation = DMatrix::from_fn(r, r, |i, j| match i == j {
        true => 1.0,
        false => covariance[(i, j)] / (std_errors[i] * std_errors[j]),
    });
    let warnings = warnings(
        &std_errors,
        &covariance,
        &correlation,
        bounds.condition_number,
        Some(box_widths),
        settings,
    );
    CramerRao {
        pooled: Some(pooled.clone()),
        covariance,
        std_errors,
        correlation,
        warnings,
        ..bounds
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::identification::uncertainty::cramer_rao_mapped;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;
    use rand_distr::{Distribution, Normal};

    /// Two sensors of a straight line `y = x₀ + x₁ t` (sensor 2 sees
    /// `x₀ + 4 x₁ t`), 200 samples each.
    fn line() -> (DMatrix<f64>, Vec<usize>) {
        let n = 200;
        let jac = DMatrix::from_fn(2 * n, 2, |k, j| {
            let t = (k % n) as f64 / n as f64;
            let gain = if k < n { 1.0 } else { 4.0 };
            if j == 0 {
                1.0
            } else {
                gain * t
            }
        });
        (jac, vec![n, n])
    }

    fn pooled(jac: &DMatrix<f64>, res: &[f64], f: &[f64]) -> CramerRao {
        let ssr = res.iter().map(|v| v * v).sum();
        cramer_rao_mapped(jac, ssr, f, &[1e9, 1e9], &UncertaintySettings::default()).unwrap()
    }

    #[test]
    fn equal_levels_give_eq_26() {
        let (jac, counts) = line();
        // Residuals of one mean square on both sensors.
        let res: Vec<f64> = (0..jac.nrows())
            .map(|k| if k % 2 == 0 { 0.1 } else { -0.1 })
            .collect();
        let f = [3.0, 0.5];
        let b = pooled(&jac, &res, &f);
        let sensors = SensorRows::split(&jac, &res, &counts);
        let s = with_sensor_levels(b.clone(), &sensors, &f, &[1e9, 1e9], &Default::default());
        for (a, e) in s.covariance.iter().zip(b.covariance.iter()) {
            assert!((a - e).abs() <= 1e-12 * e.abs().max(1e-30), "{a} {e}");
        }
    }

    /// The sandwich against its closed form, and against the spread of
    /// the least-squares estimates over seeded noise whose level differs
    /// by sensor (σ = 0.01 and 0.1): the z-scores' spread is 1 with the
    /// sensors' levels, and far from it with one s² for the slope.
    #[test]
    fn the_estimates_spread_as_the_sensors_levels_say() {
        let (jac, counts) = line();
        let n = counts[0];
        let f = [1.0, 1.0];
        let normal = Normal::new(0.0, 1.0).unwrap();
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let a_inv = (jac.transpose() * &jac).try_inverse().unwrap();
        let (mut z_levels, mut z_pooled) = (vec![Vec::new(); 2], vec![Vec::new(); 2]);
        let mut kappa = [0.0; 2];
        for rep in 0..2000 {
            let e: Vec<f64> = (0..2 * n)
                .map(|k| normal.sample(&mut rng) * if k < n { 0.01 } else { 0.1 })
                .collect();
            // Truth 0: x̂ = A⁻¹ Jᵀ e, the residuals e − J x̂.
            let x = &a_inv * jac.transpose() * DMatrix::from_column_slice(2 * n, 1, &e);
            let fit = &jac * &x;
            let res: Vec<f64> = e.iter().zip(fit.iter()).map(|(a, b)| a - b).collect();
            let b = pooled(&jac, &res, &f);
            let sensors = SensorRows::split(&jac, &res, &counts);
            let s = with_sensor_levels(b.clone(), &sensors, &f, &[1e9, 1e9], &Default::default());
            if rep == 0 {
                // Closed form with these residuals' levels.
                let dof = (2 * n - 3) as f64;
                let mut meat = DMatrix::zeros(2, 2);
                for c in &sensors {
                    meat += &c.gram * (c.ssr * (2 * n) as f64 / (n as f64 * dof));
                }
                let v = &a_inv * meat * &a_inv;
                for (a, e) in s.covariance.iter().zip(v.iter()) {
                    assert!((a - e).abs() <= 1e-9 * v.norm(), "{a} {e}");
                }
                assert_eq!(s.pooled.as_ref(), Some(&b.covariance));
                kappa = [s.variance_ratio(0), s.variance_ratio(1)];
            }
            for j in 0..2 {
                z_levels[j].push(x[j] / s.std_errors[j]);
                z_pooled[j].push(x[j] / b.std_errors[j]);
            }
        }
        let sd = |z: &[f64]| (z.iter().map(|v| v * v).sum::<f64>() / z.len() as f64).sqrt();
        for z in &z_levels {
            assert!((sd(z) - 1.0).abs() < 0.05, "z spread {}", sd(z));
        }
        // With one s², the z-scores spread by √κ_j: the slope, seen mostly
        // by the noisy sensor, is where one s² errs.
        for (j, z) in z_pooled.iter().enumerate() {
            let expected = kappa[j].sqrt();
            assert!(
                (sd(z) / expected - 1.0).abs() < 0.05,
                "x{j}: {} vs {expected}",
                sd(z)
            );
        }
        assert!(kappa[1] > 1.3, "κ of the slope {}", kappa[1]);
    }
}
