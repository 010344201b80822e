//! Scratch memory for runs ([`Workspace`]), and the buffers of the
//! parameter groups integrated in parallel ([`GroupBuffers`], `columns`).
use super::laws::bouc_wen::Branch;
use super::response::Response;
#[cfg(doc)]
use super::sines::StageSines;
use super::split_column::Shift;
use super::system::System;
use crate::model::Segment;

/// Scratch memory for one run; reuse it so that runs do not allocate.
#[derive(Debug, Clone, Default)]
pub struct Workspace {
    pub(crate) y: Vec<f64>,
    pub(super) y_new: Vec<f64>,
    /// Stage states, stages × 2n.
    pub(super) y_stage: Vec<f64>,
    /// Stage derivatives, stages × 2n.
    pub(crate) k: Vec<f64>,
    /// Sensitivities, 2n rows of the tangent's width.
    pub(crate) sy: Vec<f64>,
    pub(super) sy_stage: Vec<f64>,
    /// The sensitivities at the start of a step whose trial step's
    /// sensitivities are computed too (`Stepper::step`).
    pub(super) sy_start: Vec<f64>,
    /// Stage derivatives of the sensitivities, stages × 2n rows.
    pub(crate) ks: Vec<f64>,
    pub(super) scratch: Vec<f64>,
    /// Power-law forces of a stage.
    pub(super) power_forces: Vec<f64>,
    pub(super) forces: Vec<f64>,
    pub(super) forces_time: f64,
    /// The table segments the excitation looked up last, one per term of
    /// each signal in turn (`FixedSignal::at_side_kept`).
    pub(super) segments: Vec<Segment>,
    /// Whether `forces` are the limits from before `forces_time`.
    pub(super) forces_before: bool,
    /// `(sin θ, cos θ)` of each sine term at `phases_time` ([`StageSines`]).
    pub(super) phases: Vec<(f64, f64)>,
    pub(super) phases_time: f64,
    pub(super) crossings: Vec<f64>,
    /// The buffers of the parameter groups run in parallel (`columns`).
    pub(crate) groups: Vec<GroupBuffers>,
    /// The Bouc–Wen internal states and their sensitivities, laid out as
    /// the fields above for z (empty without Bouc–Wen components), kept
    /// apart so that the motion's loops keep their fixed lengths.
    pub(crate) z: InternalStates,
    /// Whether a watch stopped the run (`run::Span::notify`).
    pub(crate) stopped: bool,
    /// Per contact, the side a step or a piece of a split step holds it on
    /// (+1 acting, −1 not; `contact_events`), the side of the piece before
    /// and the side at the step's start; its closure and force with their rates (per unit of
    /// the step) at the trial step's ends, `[s0, ṡ0, s1, ṡ1, f0, ḟ0, f1,
    /// ḟ1]`; and the located openings and closings of the step: (θ,
    /// contact, whether of the force).
    pub(super) contact_sides: Vec<f64>,
    pub(super) contact_sides_before: Vec<f64>,
    pub(super) contact_start_sides: Vec<f64>,
    pub(super) contact_ends: Vec<[f64; 8]>,
    pub(super) contact_marks: Vec<(f64, usize, bool)>,
    /// The derivatives in the parameters of each located opening's or
    /// closing's instant (`contact_events::contact_instant_rates`), marks ×
    /// the tangent's width.
    pub(super) contact_mark_rates: Vec<f64>,
    /// The split column's state in a step (`split_shifts`).
    pub(super) shift: Shift,
}

/// The internal states z of a run (`hysteresis`): the state, its stages
/// and their sensitivities, as the motion's in [`Workspace`].
#[derive(Debug, Clone, Default)]
pub struct InternalStates {
    pub(crate) y: Vec<f64>,
    pub(super) y_new: Vec<f64>,
    pub(super) y_stage: Vec<f64>,
    pub(super) k: Vec<f64>,
    pub(crate) sy: Vec<f64>,
    pub(super) sy_stage: Vec<f64>,
    pub(super) ks: Vec<f64>,
    /// Per component, the branches its law is evaluated
    /// on within a piece of a split step (`stepper`), 0 for the state's own
    /// sign: `[v0, v̇0, v1, v̇1, z0, ż0, z1, ż1]` per component (rates per
    /// unit of the step) from the trial step, then the branches.
    pub(super) ends: Vec<[f64; 8]>,
    pub(super) branch: Vec<Branch>,
    /// The located kinks of the step: (θ, component, whether of z).
    pub(super) marks: Vec<(f64, usize, bool)>,
    /// Per located kink (in `marks`' order), the derivatives of its
    /// instant in the parameters, one row of the tangent's width
    /// (`Stepper::kink_instant_rates`); empty when not computed.
    pub(super) mark_rates: Vec<f64>,
    /// `sy` at the start of a step whose trial step's sensitivities are
    /// computed too.
    pub(super) sy_start: Vec<f64>,
    /// The branches of the piece before (for the jumps at its end).
    pub(super) branch_before: Vec<Branch>,
}

impl Workspace {
    /// Whether the trial step just taken located a Bouc–Wen kink or a
    /// contact's opening or closing, whose instants' derivatives need the
    /// trial step's sensitivities (`Stepper::step`). Out of line: a call in
    /// the step's loop, not code the compiler may mix into its stages.
    #[inline(never)]
    pub(super) fn located_marks(&self) -> bool {
        !(self.z.marks.is_empty() && self.contact_marks.is_empty())
    }

    /// Sizes the buffers for the equations `sys`, a method of `stages` stages,
    /// sensitivity rows `width` long (zero without sensitivities), the
    /// sensitivities' `scratch` and `sine_terms` phases; zero-fills them.
    pub(crate) fn prepare(
        &mut self,
        sys: &System<'_>,
        stages: usize,
        (width, scratch): (usize, usize),
        sine_terms: usize,
    ) {
        let (n2, nz) = (2 * sys.n, sys.internal_states());
        let resize = |v: &mut Vec<f64>, len: usize| {
            v.clear();
            v.resize(len, 0.0);
        };
        resize(&mut self.y, n2);
        resize(&mut self.y_new, n2);
        resize(&mut self.y_stage, stages * n2);
        resize(&mut self.k, stages * n2);
        resize(&mut self.sy, n2 * width);
        resize(&mut self.sy_stage, n2 * width);
        // Only located Bouc–Wen kinks and contact switches need the trial
        // step's sensitivities.
        let trials = nz > 0 || !sys.contacts.is_empty();
        resize(&mut self.sy_start, if trials { n2 * width } else { 0 });
        resize(&mut self.ks, stages * n2 * width);
        resize(&mut self.z.y, nz);
        resize(&mut self.z.y_new, nz);
        resize(&mut self.z.y_stage, stages * nz);
        resize(&mut self.z.k, stages * nz);
        resize(&mut self.z.sy, nz * width);
        resize(&mut self.z.sy_stage, nz * width);
        resize(&mut self.z.sy_start, nz * width);
        self.z.mark_rates.clear();
        resize(&mut self.z.ks, stages * nz * width);
        self.z.ends.clear();
        self.z.ends.resize(nz, [0.0; 8]);
        self.z.branch.clear();
        self.z.branch.resize(nz, Branch::NATURAL);
        self.z.marks.clear();
        self.z.branch_before.clear();
        self.z.branch_before.resize(nz, Branch::NATURAL);
        resize(&mut self.scratch, scratch);
        resize(&mut self.forces, sys.minv_loads.len());
        resize(&mut self.power_forces, sys.scratch_len());
        self.segments.clear();
        self.segments.resize(sys.signal_terms(), Segment::default());
        self.phases.clear();
        self.phases.resize(sine_terms, (0.0, 1.0));
        self.forces_time = f64::NAN;
        self.phases_time = f64::NAN;
        self.crossings.clear();
        resize(&mut self.contact_sides, sys.contacts.len());
        resize(&mut self.contact_sides_before, sys.contacts.len());
        resize(&mut self.contact_start_sides, sys.contacts.len());
        self.contact_ends.clear();
        self.contact_ends.resize(sys.contacts.len(), [0.0; 8]);
        self.contact_marks.clear();
        self.contact_mark_rates.clear();
        self.shift.reset();
    }
}

/// The buffers of one group, kept in the caller's [`Workspace`].
#[derive(Debug, Clone, Default)]
pub struct GroupBuffers {
    pub(super) ws: Workspace,
    pub(super) out: Option<Response>,
    pub(super) sens: Vec<f64>,
}
