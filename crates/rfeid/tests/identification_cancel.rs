//! Cancelling an identification from another thread: every simulation of
//! the criterion checks the flag first, so a run stops within one
//! simulation and ends with `IdentifyError::Cancelled`, whatever stage it
//! was in; a run never cancelled is the run of the shared options.
use rfeid::identification::cancel::Cancel;
use rfeid::identification::options::{prepare, SearchOptions};
use rfeid::identification::pipeline::{identify, IdentifyError, Progress, Silent};
use rfeid::io::model_file::load_model;
use rfeid::model::Model;
use rfeid::simulation::{Response, Simulator, Workspace};
use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::{Duration, Instant};

fn knee_column() -> Model {
    load_model(&Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/knee-column/model.toml"))
        .expect("example loads")
}

fn data(model: &Model) -> Response {
    let sim = Simulator::new(model);
    let mut out = sim.response_buffer();
    sim.run(&model.nominal(), &mut Workspace::default(), &mut out)
        .expect("simulates");
    out
}

#[test]
fn a_flag_set_before_the_run_cancels_it_at_once() {
    let model = knee_column();
    let cancel = Cancel::new();
    let p = prepare(&model, data(&model), &SearchOptions::default(), &cancel).expect("prepares");
    cancel.set();
    let t = Instant::now();
    let e = identify(p.problem, &p.settings, &Silent).expect_err("cancelled");
    assert!(matches!(e, IdentifyError::Cancelled), "{e}");
    assert!(t.elapsed() < Duration::from_secs(1));
}

/// Sets the flag once `after` plan points or `after_iterations` local
/// search iterations are done.
struct CancelAt<'c> {
    cancel: &'c Cancel,
    points: AtomicUsize,
    after: usize,
    iterations_after: Option<usize>,
}

impl Progress for CancelAt<'_> {
    fn plan_point(&self) {
        if self.points.fetch_add(1, Ordering::Relaxed) + 1 == self.after {
            self.cancel.set();
        }
    }
    fn iteration(&self, iteration: usize, _cost: f64) {
        if self.iterations_after == Some(iteration) {
            self.cancel.set();
        }
    }
}

#[test]
fn a_flag_set_during_the_plan_or_the_local_search_stops_the_run() {
    let model = knee_column();
    let measured = data(&model);
    // During a plan of 10⁵ points (minutes uncancelled), and in the first
    // local search's second iteration.
    for (plan, after, iterations_after) in [(100_000, 50, None), (20, usize::MAX, Some(2))] {
        let cancel = Cancel::new();
        let options = SearchOptions {
            plan,
            ..SearchOptions::default()
        };
        let p = prepare(&model, measured.clone(), &options, &cancel).expect("prepares");
        let watch = CancelAt {
            cancel: &cancel,
            points: AtomicUsize::new(0),
            after,
            iterations_after,
        };
        let t = Instant::now();
        let e = identify(p.problem, &p.settings, &watch).expect_err("cancelled");
        assert!(matches!(e, IdentifyError::Cancelled), "{e}");
        assert!(
            t.elapsed() < Duration::from_secs(5),
            "plan {plan}: took {:?}",
            t.elapsed()
        );
    }
}

#[test]
fn an_uncancelled_run_of_the_shared_options_identifies() {
    let model = knee_column();
    let options = SearchOptions {
        plan: 30,
        ..SearchOptions::default()
    };
    let p = prepare(&model, data(&model), &options, &Cancel::new()).expect("prepares");
    assert!(p.constant.is_empty() && p.constant_warning().is_none());
    let r = identify(p.problem, &p.settings, &Silent).expect("identifies");
    for q in &r.parameters {
        assert!(
            (q.estimate - q.nominal).abs() < 1e-3 * q.nominal,
            "{}",
            q.name
        );
    }
}
