//! The [`Simulator`]: one model with its structure, integrator settings and
//! step choice, its constructor from explicit settings and its accessors.
//! The constructors that choose the steps ([`Simulator::new`],
//! [`Simulator::choose`]) are in `steps`, the runs in `simulate`, the
//! integration loop in `run`.
use super::integrator::{Integrator, Kernel};
use super::response::Response;
use super::step_choice::StepChoice;
use super::structure::Structure;
use super::system::System;
use super::SimulationError;
use crate::model::Model;

/// Simulates one model at any parameter point.
#[derive(Debug, Clone)]
pub struct Simulator<'m> {
    pub(super) model: &'m Model,
    pub(super) kernel: Kernel,
    pub(super) structure: Structure,
    pub(super) integrator: Integrator,
    pub(super) steps: StepChoice,
    /// Instants where the excitation has a kink or a jump, sorted, within
    /// the record: steps are split there.
    pub(super) breakpoints: Vec<f64>,
}

impl<'m> Simulator<'m> {
    /// A simulator with explicit integrator settings (fixed steps, no
    /// error estimate).
    pub fn with_integrator(model: &'m Model, integrator: Integrator) -> Self {
        let integrator = Integrator {
            substeps: integrator.substeps.max(1),
            ..integrator
        };
        let end = model
            .sampling
            .time(model.sampling.n_samples().saturating_sub(1));
        let mut breakpoints: Vec<f64> = model
            .excitations
            .iter()
            .flat_map(|e| &e.signal.terms)
            .flat_map(|term| term.shape.breakpoints())
            .filter(|t| *t > 0.0 && *t < end)
            .collect();
        breakpoints.sort_by(f64::total_cmp);
        breakpoints.dedup();
        Simulator {
            model,
            kernel: Kernel::Auto,
            structure: Structure::new(model),
            breakpoints,
            integrator,
            steps: StepChoice {
                substeps: integrator.substeps,
                automatic: false,
                tolerance: model.sampling.tolerance,
                estimated_error: None,
                runs: 0,
                search: None,
            },
        }
    }

    /// Uses `kernel` from now on (see [`Kernel`]).
    pub fn set_kernel(&mut self, kernel: Kernel) {
        self.kernel = kernel;
    }

    /// The kernel setting.
    pub fn kernel(&self) -> Kernel {
        self.kernel
    }

    /// How the steps per sample were chosen, and their estimated error.
    pub fn steps(&self) -> StepChoice {
        self.steps
    }

    /// Takes `steps.substeps` steps per sample from now on, recording `steps`.
    pub fn set_steps(&mut self, steps: StepChoice) {
        self.integrator.substeps = steps.substeps.max(1);
        self.steps = StepChoice {
            substeps: self.integrator.substeps,
            ..steps
        };
    }

    /// Takes the steps a search may take ([`StepChoice::search`]) from now
    /// on, if there are fewer such steps; [`Simulator::steps`] still
    /// records the choice, and [`Simulator::use_chosen_steps`] goes back to
    /// it.
    pub fn use_search_steps(&mut self) {
        if let Some(s) = self.steps.search {
            self.integrator.substeps = s.substeps.max(1);
        }
    }

    /// Takes the chosen steps ([`Simulator::steps`]) from now on.
    pub fn use_chosen_steps(&mut self) {
        self.integrator.substeps = self.steps.substeps;
    }

    /// Whether it takes fewer steps than [`Simulator::steps`] chose, for a
    /// search ([`Simulator::use_search_steps`]).
    pub fn searching(&self) -> bool {
        self.integrator.substeps != self.steps.substeps
    }

    /// The model.
    pub fn model(&self) -> &'m Model {
        self.model
    }

    /// The assembled structure (B, excitation and sensor maps).
    pub fn structure(&self) -> &Structure {
        &self.structure
    }

    /// The integrator settings.
    pub fn integrator(&self) -> Integrator {
        self.integrator
    }

    /// The equations of motion at parameter values `params`.
    pub fn system(&self, params: &[f64]) -> Result<System<'_>, SimulationError> {
        System::new(self.model, &self.structure, params)
    }

    /// A response buffer of the right shape.
    pub fn response_buffer(&self) -> Response {
        Response::zeros(self.model.sensors.len(), self.model.sampling.n_samples())
    }
}
