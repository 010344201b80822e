//! The step-error check of a long record on windows of it (see `steps`):
//! the run at s steps per sample keeps its state at the start of each span
//! ([`check_spans`]); the [`CHECKED_WINDOWS`] spans where its response
//! varies fastest ([`roughness`]) are run again at 2s from those states and
//! compared with it.
//!
//! The windows are launched while the run goes on: when a span ends, the
//! spans so far are ranked with the scales so far, and a span that ranks
//! among the first is started at once on a free thread (one window at a
//! time, so that a window that later drops out costs only a thread that
//! was idle). The record's last span, which can be ranked only at its end,
//! has its window started as soon as the run enters it, so that when it is
//! among the roughest (a chirp's end) its window ends about one span after
//! the run instead of two. Starting the window of the span after a leading
//! one as well, before its own rank is known, was tried and measured no
//! faster. Once the run is done the spans are ranked again, exactly, and
//! the windows among the final ones not started yet are started at once
//! (if the second thread has decided by then that windows apply), beside
//! one still running. Which windows are compared is fixed by the
//! final ranking alone, so the estimate is the same whatever the threads
//! did.
//!
//! Whether windows can show the record's error at all
//! (`windows_suffice`) is decided on the second thread while the run
//! starts; where they cannot, that thread runs the whole record at 2s, as
//! for a short record. On a 50-body machine tool (3000 samples, a chirp
//! whose last span is the roughest) `rfeid simulate`'s whole process went
//! from 1.46 to 1.22–1.28 times the run alone.
use super::integrator::integrator;
use super::response::Response;
use super::run::{SampleState, SampleView, Span};
use super::simulator::Simulator;
use super::step_error::{
    floored, relative_difference, sensor_scales, windowed_difference, ChosenRun, Watcher,
};
use super::workspace::Workspace;
use super::SimulationError;
use crate::model::SensorKind;
use rayon::prelude::*;
use std::sync::atomic::{AtomicU8, AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::Instant;

/// How many windows a long record is checked on.
const CHECKED_WINDOWS: usize = 2;

/// The record's spans a long record of `n_samples` is cut into for the
/// check (first sample, samples): 1/32 of the record each, but at least 256
/// samples, the last one ending at the record's end.
pub fn check_spans(n_samples: usize) -> Vec<(usize, usize)> {
    let len = (n_samples / 32).max(256).min(n_samples).max(1);
    let mut spans: Vec<(usize, usize)> = (0..n_samples / len).map(|i| (i * len, len)).collect();
    if n_samples % len != 0 {
        spans.push((n_samples - len, len));
    }
    spans
}

/// How fast the response in `span` varies: the largest over the sensors of
/// the RMS of its fourth differences, relative to the sensor's scale. An
/// explicit method's local error grows with a high power of ωh, and the
/// fourth difference weights content at ω by (2 sin(ωh/2))⁴, so the spans
/// where it is largest are where the steps' error is made.
fn roughness(r: &Response, scales: &[f64], (first, len): (usize, usize)) -> f64 {
    (0..r.n_sensors)
        .map(|c| fourth_differences(&r.sensor(c)[first..first + len]).sqrt() / scales[c])
        .fold(0.0, f64::max)
}

/// The mean square of the fourth differences of `x` (over its length).
fn fourth_differences(x: &[f64]) -> f64 {
    let d4 = x
        .windows(5)
        .map(|w| w[0] - 4.0 * w[1] + 6.0 * w[2] - 4.0 * w[3] + w[4]);
    d4.map(|d| d * d).sum::<f64>() / x.len().max(1) as f64
}

/// A window's response at 2s, or why there is none.
type Window = Result<Response, SimulationError>;

/// Windows run so far, with their spans' indices.
type Done = Mutex<Vec<(usize, Window)>>;

/// What the check keeps while the run goes on.
struct Progress<'a> {
    spans: &'a [(usize, usize)],
    kinds: Vec<SensorKind>,
    /// The states at the spans' first samples, as the run passes them.
    starts: Vec<SampleState>,
    /// Per span ended: each sensor's mean-square fourth difference.
    rough: Vec<Vec<f64>>,
    /// Each sensor's sum of squared motion so far.
    squares: Vec<f64>,
    launched: Vec<bool>,
}

impl<'a> Progress<'a> {
    /// Nothing seen yet of a run of `model` cut into `spans`.
    fn new(spans: &'a [(usize, usize)], model: &crate::model::Model) -> Self {
        Progress {
            spans,
            kinds: model.sensors.iter().map(|s| s.kind).collect(),
            starts: Vec::with_capacity(spans.len()),
            rough: Vec::with_capacity(spans.len()),
            squares: vec![0.0; model.sensors.len()],
            launched: vec![false; spans.len()],
        }
    }

    /// Takes a sample of the run: keeps the state at a span's start, and
    /// when a span ends, ranks it; returns the spans that rank among the
    /// first then (none at other samples). The record's last span is also
    /// returned when the run enters it: it can be ranked only at the
    /// record's end, and its window, started then, would be all the check
    /// adds to the run when it is among the roughest.
    fn observe(&mut self, at: &SampleView<'_>) -> Vec<usize> {
        for (c, sq) in self.squares.iter_mut().enumerate() {
            *sq += at.motion(c).last().map_or(0.0, |x| x * x);
        }
        let mut entered = None;
        if (self.spans.get(self.starts.len())).is_some_and(|s| s.0 == at.sample) {
            let (y, z) = (at.y.to_vec(), at.z.to_vec());
            let sample = at.sample;
            self.starts.push(SampleState { sample, y, z });
            entered = Some(self.starts.len() - 1).filter(|&i| i + 1 == self.spans.len());
        }
        let mut start = match self.spans.get(self.rough.len()) {
            Some(&(first, len)) if at.sample == first + len - 1 => {
                let rough = (0..self.squares.len())
                    .map(|c| fourth_differences(&at.motion(c)[first..first + len]))
                    .collect();
                self.rough.push(rough);
                self.leading(at.sample + 1)
            }
            _ => Vec::new(),
        };
        start.extend(entered.filter(|&i| i > 0));
        start
    }

    /// The spans ended so far that rank among the first [`CHECKED_WINDOWS`]
    /// with the scales so far (the floor of `sensor_scales`).
    fn leading(&self, samples: usize) -> Vec<usize> {
        let rms: Vec<f64> = (self.squares.iter())
            .map(|s| (s / samples as f64).sqrt())
            .collect();
        let scale = floored(&rms, &self.kinds);
        let score = |i: usize| -> f64 {
            (self.rough[i].iter().zip(&scale))
                .map(|(r, s)| r.sqrt() / s)
                .fold(0.0, f64::max)
        };
        roughest(&(0..self.rough.len()).map(score).collect::<Vec<_>>())
    }
}

/// Whether a window can show the error a run makes, so that a long record
/// may be checked on windows: every motion restrained by a spring (an error
/// made along a free direction, say a feed axis held by friction alone,
/// is never restored and adds up over the record) unless no force can act
/// along it ([`super::free::FreeSet::inert`]), no friction or
/// hysteresis (their stick and reversal events make errors that persist
/// past a window), and no kink or jump in the excitation within the record
/// (an impulse's edges, a chirp's end, a table's knots: there the steps
/// are split and make no error, but the response's fourth differences,
/// which rank the spans, are large). A linear table on the sample grid
/// splits no step, but on the Silverbox (a measured input) the windows
/// estimate 3× the whole record's difference (2.9e-7 against 9.7e-8 at one
/// step per sample, a true 9.8e-8), and at the identification's start
/// that crossed its tolerance of 1e-6: two steps per sample, the search
/// twice as costly. Measured before these rules: on the
/// feed-axis example the windows said 8.8e-8 at one step per sample for a
/// true 3.7e-7; on the lathe with an impulse and a chirp ending mid-record
/// they ranked the impulse's span first and said 6.3e-9 for a true 1.45e-8.
fn windows_suffice(sim: &Simulator<'_>, params: &[f64]) -> bool {
    let events = (sim.structure().components.iter()).any(|c| c.law.joint().switches());
    !events
        && sim.breakpoints.is_empty()
        && sim.system(params).is_ok_and(|sys| {
            let free = super::free::free_directions(&sys);
            free.is_empty() || free.inert(&sys)
        })
}

/// Whether a long record may be checked on windows: not known yet, yes, or
/// no (the whole record is run at 2s instead); decided on a second thread
/// while the run starts (`windows_suffice`).
const UNKNOWN: u8 = 0;
const WINDOWS: u8 = 1;
const WHOLE: u8 = 2;

/// The run at `substeps` steps per sample with its estimated error, for a
/// record of at least [`super::steps::SHORTEST_WINDOWED`] samples (see the
/// module documentation). Whether windows can show its error
/// (`windows_suffice`, which builds the model's equations and looks for
/// free directions: 9 ms on a 50-body model) is decided on a second thread
/// while the run starts; if not, that thread runs the whole record at 2s.
/// When the run ends, the windows of the final ranking not yet started are
/// started at once, beside any still running.
pub(super) fn windowed_check<'w>(
    sim: &Simulator<'_>,
    params: &[f64],
    mut watch: Option<&mut Watcher<'w>>,
) -> Result<(f64, ChosenRun), SimulationError> {
    let model = sim.model();
    let finer = integrator(2 * sim.integrator().substeps);
    let finer = Simulator::with_integrator(model, finer);
    let n_samples = model.sampling.n_samples();
    let spans = check_spans(n_samples);
    let mut out = sim.response_buffer();
    let mut progress = Progress::new(&spans, model);
    let (done, busy): (Done, AtomicUsize) = (Mutex::new(Vec::new()), AtomicUsize::new(1));
    let (mode, whole) = (AtomicU8::new(UNKNOWN), Mutex::new(None));
    let (mut run, mut elapsed, mut equilibrium) = (Ok(()), Default::default(), None);
    // The final ranking (with the whole run's scales), once the run is done.
    let mut ranked = None;
    rayon::scope(|scope| {
        let (finer, done, busy, mode, whole) = (&finer, &done, &busy, &mode, &whole);
        scope.spawn(move |_| decide(sim, finer, params, (mode, busy, whole)));
        let launch = |p: &mut Progress<'_>, i: usize, eq: Option<Vec<f64>>| {
            p.launched[i] = true;
            busy.fetch_add(1, Ordering::AcqRel);
            let (start, len) = (p.starts[i].clone(), p.spans[i].1);
            scope.spawn(move |_| {
                let w = run_window(finer, params, &eq, start, len);
                done.lock().expect("a window panicked").push((i, w));
                busy.fetch_sub(1, Ordering::AcqRel);
            });
        };
        let mut observer = |at: &SampleView<'_>| {
            if let Some(w) = watch.as_mut() {
                w(at);
            }
            let p = &mut progress;
            for i in p.observe(at) {
                let last = i + 1 == p.spans.len();
                let free = busy.load(Ordering::Acquire) == 0;
                if p.launched[i] || mode.load(Ordering::Acquire) != WINDOWS || !(free || last) {
                    continue;
                }
                launch(p, i, Some(at.origin.to_vec()).filter(|o| !o.is_empty()));
            }
        };
        let mut span = Span {
            observer: Some(&mut observer),
            ..Span::default()
        };
        let t0 = Instant::now();
        run = sim.run_span(params, &mut Workspace::default(), &mut out, &mut span);
        elapsed = t0.elapsed();
        equilibrium = span.equilibrium;
        if run.is_err() {
            return;
        }
        let scales = sensor_scales(model, &out);
        let chosen = final_ranking(&out, &scales, &spans);
        if mode.load(Ordering::Acquire) == WINDOWS {
            for &i in &chosen {
                if !progress.launched[i] {
                    launch(&mut progress, i, equilibrium.clone());
                }
            }
        }
        ranked = Some((scales, chosen));
    });
    run?;
    if mode.into_inner() == WHOLE {
        let fine = whole.into_inner().expect("the whole check panicked");
        let fine = fine.expect("the whole check ran")?;
        return Ok((relative_difference(model, &out, &fine), (out, elapsed)));
    }
    let done = done.into_inner().expect("a window panicked");
    let ranked = ranked.expect("the run ended");
    let e = compare_windows(&finer, params, (&out, ranked), &progress, done, equilibrium)?;
    Ok((e, (out, elapsed)))
}

/// The second thread's part at the start of [`windowed_check`]: decides
/// whether windows can show the error (`mode`, releasing `busy` if so), and
/// if not runs the whole record at 2s (`finer`) into `whole`.
fn decide(
    sim: &Simulator<'_>,
    finer: &Simulator<'_>,
    params: &[f64],
    (mode, busy, whole): (&AtomicU8, &AtomicUsize, &Mutex<Option<Window>>),
) {
    if windows_suffice(sim, params) {
        mode.store(WINDOWS, Ordering::Release);
        busy.fetch_sub(1, Ordering::AcqRel);
    } else {
        mode.store(WHOLE, Ordering::Release);
        let mut fine = finer.response_buffer();
        let r = finer.run(params, &mut Workspace::default(), &mut fine);
        *whole.lock().expect("the whole check panicked") = Some(r.map(|()| fine));
    }
}

/// The estimate from the windows of the final ranking `chosen`, compared
/// with the run's response `out` (its sensors' `scales`): those already
/// `done`, the others run now from the states `progress` kept (see the
/// module documentation).
fn compare_windows(
    finer: &Simulator<'_>,
    params: &[f64],
    (out, (scales, chosen)): (&Response, (Vec<f64>, Vec<usize>)),
    progress: &Progress<'_>,
    done: Vec<(usize, Window)>,
    equilibrium: Option<Vec<f64>>,
) -> Result<f64, SimulationError> {
    let (spans, starts) = (progress.spans, &progress.starts);
    let model = finer.model();
    let n_samples = model.sampling.n_samples();
    // A window shows the error its span makes only once that error has
    // settled (the modes it excites have decayed many times over): while
    // it still grows across a window, the windows are lengthened, and
    // past a quarter of the record the whole record is run instead.
    let mut len = spans[0].1;
    let mut done = done;
    let mut ready: Vec<Option<Window>> = (chosen.iter())
        .map(|&i| {
            let at = done.iter().position(|(j, _)| *j == i);
            at.map(|at| done.swap_remove(at).1)
        })
        .collect();
    while len <= n_samples / 4 {
        let missing: Vec<(SampleState, usize)> = (chosen.iter().zip(&ready))
            .filter(|(_, w)| w.is_none())
            .map(|(&i, _)| (starts[i].clone(), len.min(n_samples - spans[i].0)))
            .collect();
        let mut more = run_windows(finer, params, &equilibrium, missing).into_iter();
        // The first failure in record order, whichever windows ran early:
        // the error does not depend on the threads.
        let fine: Vec<(usize, Response)> = (chosen.iter().zip(ready.iter_mut()))
            .map(|(&i, w)| {
                let w = w.take().or_else(|| more.next());
                Ok((spans[i].0, w.expect("one window per span chosen")?))
            })
            .collect::<Result<_, SimulationError>>()?;
        if !still_growing(out, &scales, &fine) {
            return Ok(windowed_difference(model, out, &fine));
        }
        len *= 2;
    }
    let mut fine = finer.response_buffer();
    let mut whole = Span {
        equilibrium,
        ..Span::default()
    };
    finer.run_span(params, &mut Workspace::default(), &mut fine, &mut whole)?;
    Ok(relative_difference(model, out, &fine))
}

/// The [`CHECKED_WINDOWS`] spans where the run's response `out` varies
/// fastest ([`roughness`] with the whole record's `scales`), in record
/// order.
fn final_ranking(out: &Response, scales: &[f64], spans: &[(usize, usize)]) -> Vec<usize> {
    let rough: Vec<f64> = spans.iter().map(|s| roughness(out, scales, *s)).collect();
    let mut order = roughest(&rough);
    order.sort_unstable();
    order
}

/// The indices of the [`CHECKED_WINDOWS`] largest `scores`, largest first
/// (the earlier of equal ones first).
fn roughest(scores: &[f64]) -> Vec<usize> {
    let mut order: Vec<usize> = (0..scores.len()).collect();
    order.sort_by(|&a, &b| scores[b].total_cmp(&scores[a]).then(a.cmp(&b)));
    order.truncate(CHECKED_WINDOWS);
    order
}

/// Runs `sim` at `params` over the `windows` (a starting state and a number
/// of samples each) in parallel, from the static `equilibrium` if any: each
/// window's response or error, in the order given.
fn run_windows(
    sim: &Simulator<'_>,
    params: &[f64],
    equilibrium: &Option<Vec<f64>>,
    windows: Vec<(SampleState, usize)>,
) -> Vec<Window> {
    windows
        .into_par_iter()
        .map(|(start, len)| run_window(sim, params, equilibrium, start, len))
        .collect()
}

/// Runs `sim` at `params` for `len` samples from `start`, from the static
/// `equilibrium` if any.
fn run_window(
    sim: &Simulator<'_>,
    params: &[f64],
    equilibrium: &Option<Vec<f64>>,
    start: SampleState,
    len: usize,
) -> Window {
    let mut window = Span {
        equilibrium: equilibrium.clone(),
        start: Some(start),
        samples: Some(len),
        ..Span::default()
    };
    let mut w = Response::zeros(sim.model().sensors.len(), 0);
    sim.run_span(params, &mut Workspace::default(), &mut w, &mut window)?;
    Ok(w)
}

/// Whether the difference of `a` from the finer windows `fine` still grows
/// across them: for the sensor that differs most (relative to its scale,
/// `scales`), the second halves'
/// squared difference is more than four times the first halves', beyond
/// what the response's own variation there explains (the ratio of the
/// halves' [`roughness`], squared). An error growing linearly gives seven;
/// a settled one about one.
fn still_growing(a: &Response, scales: &[f64], fine: &[(usize, Response)]) -> bool {
    // Per sensor: (early, late) squared difference and squared roughness.
    let mut halves = vec![[0.0; 4]; a.n_sensors];
    for (first, w) in fine {
        let mid = w.n_samples / 2;
        for (c, h) in halves.iter_mut().enumerate() {
            let coarse = &a.sensor(c)[*first..*first + w.n_samples];
            for (k, (x, y)) in coarse.iter().zip(w.sensor(c)).enumerate() {
                h[usize::from(k >= mid)] += (x - y) * (x - y);
            }
            let (early, late) = coarse.split_at(mid);
            h[2] += fourth_differences(early) * early.len() as f64;
            h[3] += fourth_differences(late) * late.len() as f64;
        }
    }
    let relative = |c: usize| (halves[c][0] + halves[c][1]) / (scales[c] * scales[c]);
    let worst = (0..halves.len())
        .max_by(|&x, &y| relative(x).total_cmp(&relative(y)))
        .map(|c| halves[c]);
    worst.is_some_and(|h| h[1] * h[2] > 4.0 * h[0] * h[3])
}
