//! The building blocks together, on a model with a known answer: noisy data
//! from y = A exp(−k t), an LP_τ plan, Levenberg–Marquardt (and BFGS) from
//! the best plan point, then Cramér–Rao bounds: the estimates must land
//! within 3 standard errors of the truth.
use crate::problems;

use nalgebra::DMatrix;
use problems::{to_physical, EXP_BOX, EXP_TRUE};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};
use rfeid::identification::bfgs::Bfgs;
use rfeid::identification::lm::{LevenbergMarquardt, LmSettings};
use rfeid::identification::plan::lp_tau_plan;
use rfeid::identification::plan_eval::evaluate_plan;
use rfeid::identification::problem::LeastSquares;
use rfeid::identification::uncertainty::{cramer_rao_normalised, UncertaintySettings};

/// Exponential decay with noisy data (200 samples, σ = 0.01).
struct NoisyDecay {
    t: Vec<f64>,
    y: Vec<f64>,
}

impl NoisyDecay {
    fn new(seed: u64) -> Self {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let noise = Normal::new(0.0, 0.01).unwrap();
        let t: Vec<f64> = (0..200).map(|k| 0.015 * k as f64).collect();
        let y = t
            .iter()
            .map(|&t| EXP_TRUE[0] * (-EXP_TRUE[1] * t).exp() + noise.sample(&mut rng))
            .collect();
        NoisyDecay { t, y }
    }
}

#[derive(Debug, Clone, thiserror::Error)]
#[error("never fails")]
struct Never;

impl LeastSquares for NoisyDecay {
    type Workspace = ();
    type Error = Never;
    fn n_params(&self) -> usize {
        2
    }
    fn n_residuals(&self) -> usize {
        self.t.len()
    }
    fn workspace(&self) {}
    fn residuals(&self, _: &mut (), u: &[f64], r: &mut [f64]) -> Result<(), Never> {
        let x = to_physical(u, &EXP_BOX);
        for ((ri, &t), &y) in r.iter_mut().zip(&self.t).zip(&self.y) {
            *ri = y - x[0] * (-x[1] * t).exp();
        }
        Ok(())
    }
    fn residuals_jacobian(
        &self,
        ws: &mut (),
        u: &[f64],
        r: &mut [f64],
        jac: &mut DMatrix<f64>,
    ) -> Result<(), Never> {
        self.residuals(ws, u, r)?;
        let x = to_physical(u, &EXP_BOX);
        for (i, &t) in self.t.iter().enumerate() {
            let e = (-x[1] * t).exp();
            jac[(i, 0)] = -e * (EXP_BOX[0].1 - EXP_BOX[0].0);
            jac[(i, 1)] = x[0] * t * e * (EXP_BOX[1].1 - EXP_BOX[1].0);
        }
        Ok(())
    }
}

#[test]
fn plan_lm_and_cramer_rao_recover_the_parameters() {
    let widths: Vec<f64> = EXP_BOX.iter().map(|(lo, hi)| hi - lo).collect();
    for seed in [1, 2, 3] {
        let problem = NoisyDecay::new(seed);
        let plan = lp_tau_plan(2, 16).unwrap();
        let evaluation = evaluate_plan(&problem, &plan, None).unwrap();
        let (best, _) = evaluation.best().unwrap();
        let lm = LevenbergMarquardt::default()
            .minimize(&problem, plan.point(best))
            .unwrap();
        assert!(lm.stop_reason.is_converged(), "{}", lm.stop_reason);
        assert!(lm.iterations <= 10, "{} iterations", lm.iterations);
        let cr = cramer_rao_normalised(
            &lm.jacobian,
            lm.cost,
            &widths,
            &UncertaintySettings::default(),
        )
        .unwrap();
        // s² estimates the noise variance 1e-4.
        assert!((cr.s2 / 1e-4 - 1.0).abs() < 0.3, "s² = {}", cr.s2);
        let x = to_physical(&lm.u, &EXP_BOX);
        for j in 0..2 {
            let z = (x[j] - EXP_TRUE[j]) / cr.std_errors[j];
            eprintln!(
                "seed {seed}: x{j} = {:.6} ± {:.2e} (true {}, {z:+.2} σ), LM {} iterations",
                x[j], cr.std_errors[j], EXP_TRUE[j], lm.iterations
            );
            assert!(z.abs() < 3.0);
        }
        // BFGS from the same point finds the same minimum as LM polished to
        // its other tolerances (the default LM stops within 0.22 standard
        // errors of it, `LmSettings::with_decrement_tolerance`).
        let polish = LmSettings::default()
            .with_decrement_tolerance(f64::MIN_POSITIVE)
            .unwrap();
        let lm = LevenbergMarquardt::new(polish)
            .minimize(&problem, plan.point(best))
            .unwrap();
        let bfgs = Bfgs::default()
            .minimize(&problem, plan.point(best))
            .unwrap();
        eprintln!(
            "seed {seed}: BFGS {} after {} iterations, {} evaluations",
            bfgs.stop_reason, bfgs.iterations, bfgs.cost_evaluations
        );
        assert!(bfgs.stop_reason.is_converged(), "{}", bfgs.stop_reason);
        assert!(bfgs.iterations <= 30, "{} iterations", bfgs.iterations);
        for j in 0..2 {
            assert!(
                (bfgs.u[j] - lm.u[j]).abs() < 1e-6,
                "{:?} vs {:?}",
                bfgs.u,
                lm.u
            );
        }
        assert!(bfgs.cost <= lm.cost * (1.0 + 1e-9));
    }
}
