//! The search's progress on standard error.
use crate::cli::SearchArgs;
use crate::ui::Ui;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use rfeid::identification::pipeline::Progress;

/// Progress on stderr: a bar over the plan, then one line per iteration.
pub struct Bars {
    /// The plan's bar.
    pub bar: ProgressBar,
    quiet: bool,
}

impl Bars {
    /// The display for a search with `a`'s plan (hidden with `--quiet`).
    pub fn new(a: &SearchArgs, ui: &Ui) -> Self {
        let target = if ui.quiet {
            ProgressDrawTarget::hidden()
        } else {
            ProgressDrawTarget::stderr()
        };
        let bar = ProgressBar::with_draw_target(Some(a.plan as u64), target);
        bar.set_style(
            ProgressStyle::with_template(
                "{msg} [{bar:40}] {pos}/{len} points, {elapsed} (eta {eta})",
            )
            .expect("valid template")
            .progress_chars("=> "),
        );
        Bars {
            bar,
            quiet: ui.quiet,
        }
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
}
