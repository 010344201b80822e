//! The Jacobian taken block by block from the simulation into its
//! triangular factor (`OutputError::residuals_factor`, issue 24 "Memory")
//! against the whole Jacobian: the same residuals bit for bit, the same
//! factor to rounding (with whitening filters that reach across blocks, a
//! first sample inside the record, and a campaign), and the same
//! Levenberg–Marquardt search and identification.
use nalgebra::DMatrix;
use rfeid::identification::blocked_qr::BlockedQr;
use rfeid::identification::lm::{LevenbergMarquardt, LmSettings};
use rfeid::identification::noise::Whitener;
use rfeid::identification::output_error::{ExperimentData, OutputError};
use rfeid::identification::pipeline::{identify, Settings, Silent};
use rfeid::identification::problem::LeastSquares;
use rfeid::io::model_file::load_model;
use rfeid::measurement::add_noise;
use rfeid::model::Model;
use rfeid::simulation::{Response, Simulator, Workspace};
use std::path::Path;

fn knee_column(duration: f64) -> Model {
    let mut m = load_model(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/knee-column/model.toml"),
    )
    .expect("example loads");
    m.sampling.duration = duration;
    m
}

fn noisy(model: &Model, seed: u64) -> Response {
    let sim = Simulator::new(model);
    let mut out = sim.response_buffer();
    sim.run(&model.nominal(), &mut Workspace::default(), &mut out)
        .expect("simulates");
    add_noise(&mut out, 0.01, seed);
    out
}

fn max_rel(a: &[f64], b: &[f64]) -> f64 {
    let scale = a.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs() / scale)
        .fold(0.0, f64::max)
}

/// The factor by blocks against the whole Jacobian's, at `u`.
fn compare(problem: &OutputError<'_>, u: &[f64]) {
    let (n, r) = (problem.n_residuals(), problem.n_params());
    let mut ws = problem.workspace();
    let (mut res, mut jac) = (vec![0.0; n], DMatrix::zeros(n, r));
    problem
        .residuals_jacobian(&mut ws, u, &mut res, &mut jac)
        .unwrap();
    let whole = BlockedQr::from_rows(&jac, &res, 256);
    let mut plain = vec![0.0; n];
    problem.residuals(&mut ws, u, &mut plain).unwrap();

    let mut ws = problem.workspace();
    let mut by_blocks = vec![0.0; n];
    let mut qr = BlockedQr::new(r);
    problem
        .residuals_factor(&mut ws, u, &mut by_blocks, &mut qr)
        .unwrap();
    assert!(by_blocks == plain, "residuals differ");
    assert_eq!(qr.rows(), n);
    let fisher = |q: &BlockedQr| (q.r().transpose() * q.r()).as_slice().to_vec();
    let e_fisher = max_rel(&fisher(&whole), &fisher(&qr));
    let e_grad = max_rel(&whole.gradient(), &qr.gradient());
    let e_rest = (whole.ssr_rest() - qr.ssr_rest()).abs() / whole.ssr_rest();
    println!("JᵀJ {e_fisher:.1e}, Jᵀr {e_grad:.1e}, SSR left {e_rest:.1e}");
    assert!(e_fisher < 1e-12 && e_grad < 1e-9 && e_rest < 1e-9);
}

/// One record of 3000 samples in one block, and in blocks of 500, 7 and 1
/// sample (the whitening's history then crosses every block), AR(3)
/// filters on two of the three sensors, the first 137 samples left out.
#[test]
fn factor_by_blocks_is_the_whole_jacobians() {
    let m = knee_column(0.3);
    let mut problem = OutputError::new(Simulator::new(&m), noisy(&m, 1), 137);
    problem.set_whitening(&[
        Whitener::new(&[-0.9, 0.3, -0.05]),
        Whitener::NONE,
        Whitener::new(&[0.5, 0.2, 0.1]),
    ]);
    let u: Vec<f64> = (0..problem.n_params())
        .map(|j| 0.3 + 0.4 * j as f64 / 15.0)
        .collect();
    for block in [4096, 500, 7, 1] {
        problem.set_block_samples(block);
        compare(&problem, &u);
    }
}

/// A campaign of two experiments (the second shorter, weighted, whitened):
/// each experiment's rows go into the one factor.
#[test]
fn a_campaigns_experiments_share_one_factor() {
    let (a, b) = (knee_column(0.3), knee_column(0.2));
    let experiment = |name: &str, m, seed, first, weight| ExperimentData {
        name: name.into(),
        sim: Simulator::new(m),
        measured: noisy(m, seed),
        first,
        weight,
    };
    let experiments = vec![
        experiment("a", &a, 2, 0, 1.0),
        experiment("b", &b, 3, 10, 2.5),
    ];
    let mut problem = OutputError::campaign(experiments);
    problem.set_block_samples(333);
    let none = Whitener::NONE;
    problem.set_whitening(&[
        none.clone(),
        none.clone(),
        none.clone(),
        Whitener::new(&[-0.5, 0.1]),
        none,
        Whitener::new(&[0.3]),
    ]);
    compare(&problem, &vec![0.5; problem.n_params()]);
}

/// Levenberg–Marquardt on the factor by blocks takes the same path as on
/// the whole Jacobian: the same iterations and stop, the same estimate to
/// rounding, and a Jacobian entry of the result (its factor R) that gives
/// the same JᵀJ.
#[test]
fn levenberg_marquardt_by_blocks_takes_the_same_path() {
    let m = knee_column(0.3);
    let mut problem = OutputError::new(Simulator::new(&m), noisy(&m, 4), 0);
    let u0 = vec![0.3; problem.n_params()];
    let lm = LevenbergMarquardt::new(LmSettings::default());
    let whole = lm.minimize(&problem, &u0).expect("converges");
    problem.set_jacobian_memory(0);
    problem.set_block_samples(700);
    assert!(problem.jacobian_by_blocks());
    let blocks = lm.minimize(&problem, &u0).expect("converges");
    println!(
        "whole: {} iterations, J {:.10e}; by blocks: {} iterations, J {:.10e}",
        whole.iterations, whole.cost, blocks.iterations, blocks.cost
    );
    assert_eq!(whole.iterations, blocks.iterations);
    assert_eq!(whole.stop_reason, blocks.stop_reason);
    assert!((whole.cost - blocks.cost).abs() <= 1e-12 * whole.cost);
    let du = whole
        .u
        .iter()
        .zip(&blocks.u)
        .fold(0.0_f64, |a, (x, y)| a.max((x - y).abs()));
    assert!(du < 1e-9, "estimates differ by {du:e}");
    assert_eq!(blocks.jacobian.shape(), (16, 16));
    let fw = whole.jacobian.tr_mul(&whole.jacobian);
    let fb = blocks.jacobian.tr_mul(&blocks.jacobian);
    assert!(max_rel(fw.as_slice(), fb.as_slice()) < 1e-6);
}

/// The whole identification with every Jacobian taken by blocks gives the
/// estimates and standard errors of the one with whole Jacobians.
#[test]
fn identification_by_blocks_gives_the_same_estimates_and_errors() {
    let m = knee_column(0.3);
    let run = |memory| {
        let settings = Settings {
            plan_points: 32,
            starts: 1,
            jacobian_memory: memory,
            ..Settings::default()
        };
        identify(
            OutputError::new(Simulator::new(&m), noisy(&m, 5), 0),
            &settings,
            &Silent,
        )
        .expect("identifies")
    };
    let (whole, blocks) = (run(None), run(Some(0)));
    assert_eq!(whole.iterations, blocks.iterations);
    for (a, b) in whole.parameters.iter().zip(&blocks.parameters) {
        let (sa, sb) = (a.std_error.unwrap(), b.std_error.unwrap());
        println!(
            "{}: {:.9e} ± {sa:.4e} / {:.9e} ± {sb:.4e}",
            a.name, a.estimate, b.estimate
        );
        assert!((a.estimate - b.estimate).abs() < 1e-6 * sa, "{}", a.name);
        assert!((sa - sb).abs() < 1e-9 * sa, "{}", a.name);
    }
}
