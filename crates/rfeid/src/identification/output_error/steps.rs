//! The steps per sample the experiments take: the chosen ones, or the fewer
//! ones a search may take (`crate::simulation::steps`, "Searches").
use super::OutputError;
use crate::simulation::StepChoice;

impl<'m> OutputError<'m> {
    /// Experiment p simulates with `steps` steps per sample from now on (the
    /// criterion changes with them: use between searches, never within one).
    pub fn set_experiment_steps(&mut self, p: usize, steps: StepChoice) {
        self.parts[p].data.sim.set_steps(steps);
    }

    /// Experiment p takes its chosen steps from now on.
    pub fn use_chosen_steps(&mut self, p: usize) {
        self.parts[p].data.sim.use_chosen_steps();
    }

    /// Every experiment takes the steps a search may take from now on
    /// ([`Simulator::use_search_steps`]); [`OutputError::set_experiment_steps`]
    /// or [`OutputError::at_chosen_steps`] go back to the chosen ones.
    ///
    /// [`Simulator::use_search_steps`]: crate::simulation::Simulator::use_search_steps
    pub fn use_search_steps(&mut self) {
        for part in &mut self.parts {
            part.data.sim.use_search_steps();
        }
    }

    /// Whether an experiment takes fewer steps than were chosen for it
    /// ([`crate::simulation::Simulator::searching`]).
    pub fn searching(&self) -> bool {
        self.parts.iter().any(|p| p.data.sim.searching())
    }

    /// Whether an experiment's step choice lets a search take fewer steps
    /// ([`StepChoice::search`]).
    pub fn has_search_steps(&self) -> bool {
        self.parts
            .iter()
            .any(|p| p.data.sim.steps().search.is_some())
    }

    /// This criterion with every experiment at its chosen steps (a clone
    /// counted into the same tally and cancelled with it).
    pub fn at_chosen_steps(&self) -> OutputError<'m> {
        let mut chosen = self.clone();
        for part in &mut chosen.parts {
            part.data.sim.use_chosen_steps();
        }
        chosen
    }
}
