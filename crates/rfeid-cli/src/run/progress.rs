//! The search's progress on standard error.
use crate::ui::Ui;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use rfeid::identification::pipeline::Progress;

/// Progress on stderr: a bar over the plan, then one line per iteration,
/// then a bar over the profiles (if asked).
pub struct Bars {
    /// The plan's bar.
    pub bar: ProgressBar,
    /// The profiles' bar (parameters done).
    profiles: ProgressBar,
    quiet: bool,
}

impl Bars {
    /// The display for a search with `a`'s plan (hidden with `--quiet`).
    pub fn new(plan: usize, ui: &Ui) -> Self {
        let bar = ProgressBar::with_draw_target(Some(plan as u64), bar_target(ui));
        bar.set_style(
            ProgressStyle::with_template(
                "{msg} [{bar:40}] {pos}/{len} points, {elapsed} (eta {eta})",
            )
            .expect("valid template")
            .progress_chars("=> "),
        );
        let profiles = ProgressBar::with_draw_target(Some(0), bar_target(ui));
        profiles.set_style(
            ProgressStyle::with_template(
                "{msg} [{bar:40}] {pos}/{len} parameters, {elapsed} (eta {eta})",
            )
            .expect("valid template")
            .progress_chars("=> "),
        );
        Bars {
            bar,
            profiles,
            quiet: ui.quiet,
        }
    }

    /// Clears the bars at the end of the run.
    pub fn finish(&self) {
        self.bar.finish_and_clear();
        self.profiles.finish_and_clear();
    }
}

/// Standard error, or nothing with `--quiet`.
fn bar_target(ui: &Ui) -> ProgressDrawTarget {
    match ui.quiet {
        true => ProgressDrawTarget::hidden(),
        false => ProgressDrawTarget::stderr(),
    }
}

impl Progress for Bars {
    fn plan_started(&self, points: usize) {
        self.bar.set_length(points as u64);
        self.bar.set_message("LP_τ plan");
    }
    fn plan_point(&self) {
        self.bar.inc(1);
    }
    fn search_started(&self, k: usize, of: usize, cost: f64) {
        self.bar.finish_and_clear();
        if !self.quiet {
            eprintln!("local search {}/{of} from the plan's J = {cost:.6e}", k + 1);
        }
    }
    fn iteration(&self, iteration: usize, cost: f64) {
        if !self.quiet {
            eprintln!("  iteration {iteration:3}  J = {cost:.6e}");
        }
    }
    fn profiles_started(&self, parameters: usize) {
        self.profiles.set_length(parameters as u64);
        self.profiles.set_message("profile likelihoods");
        self.profiles.reset_elapsed();
        self.profiles.tick();
    }
    fn profile_done(&self, _name: &str) {
        self.profiles.inc(1);
    }
}
