//! A signal at fixed parameter values, evaluated at every stage of a run.
use super::{knot_after, Interpolation, Shape, Signal};

/// A signal at fixed parameter values, for evaluation at every stage of a
/// run: the amplitudes evaluated once, each linear table's knots per unit
/// time kept (its knot is found by a product rather than a division), and
/// with [`FixedSignal::at_side_kept`], the segment of each linear table last
/// looked up kept by the caller, so that the stages of a step, which fall
/// between the same two samples, interpolate without a search. Both
/// evaluations equal [`Signal::at_side`] bit for bit.
#[derive(Debug, Clone)]
pub struct FixedSignal<'s> {
    terms: Vec<FixedTerm<'s>>,
}

/// One term `A_j · shape_j` of a [`FixedSignal`].
#[derive(Debug, Clone)]
struct FixedTerm<'s> {
    amplitude: f64,
    shape: &'s Shape,
    /// How the shape is evaluated.
    kind: Kind,
}

/// The shapes a [`FixedTerm`] evaluates itself, and the others.
#[derive(Debug, Clone, Copy)]
enum Kind {
    /// A linearly interpolated table, with its knots per unit time.
    LinearTable(f64),
    /// A constant from t = 0.
    Constant,
    /// Any other shape, evaluated by [`Shape::at_side`].
    Other,
}

/// The segment of a linear table that held the last instant looked up
/// (see [`FixedSignal::at_side_kept`]): `[t0, t1)` between two consecutive
/// knots, both away from the table's ends, with the value `v0` at t0 and
/// the rise `dv` to t1. There the table is `v0 + (t − t0)/(t1 − t0) · dv`
/// from either side of t, the formula and order of operations of the full
/// lookup. The default holds no instant.
#[derive(Debug, Clone, Copy)]
pub struct Segment {
    t0: f64,
    t1: f64,
    v0: f64,
    dv: f64,
}

/// No segment: no instant lies in it.
const NO_SEGMENT: Segment = Segment {
    t0: f64::NAN,
    t1: f64::NAN,
    v0: 0.0,
    dv: 0.0,
};

impl Default for Segment {
    fn default() -> Self {
        NO_SEGMENT
    }
}

impl Segment {
    /// Whether t lies in `[t0, t1)`.
    #[inline(always)]
    fn holds(&self, t: f64) -> bool {
        self.t0 <= t && t < self.t1
    }

    /// The table at t in the segment.
    #[inline(always)]
    fn at(&self, t: f64) -> f64 {
        self.v0 + (t - self.t0) / (self.t1 - self.t0) * self.dv
    }

    /// The segment of the strictly increasing table `(times, values)` that
    /// holds t, or [`NO_SEGMENT`] when t is near or past an end: within the
    /// first or last interval, or where the lookup's test for the ends
    /// (relative to the instants' magnitude) could apply.
    fn holding(times: &[f64], values: &[f64], t: f64, per_time: f64) -> Segment {
        let n = times.len();
        if n < 4 || values.len() != n || !(times[0] <= t && t <= times[n - 1]) {
            return NO_SEGMENT;
        }
        let (first, last) = (times[0], times[n - 1]);
        let j = knot_after(times, t, Some(per_time));
        if j < 2 || j + 2 > n {
            return NO_SEGMENT;
        }
        let (t0, t1) = (times[j - 1], times[j]);
        // Every instant of [t0, t1) is then farther from either end than
        // the lookup's 8ε relative tolerance (|t| ≤ max(|first|, |last|)).
        let far = 16.0 * f64::EPSILON * first.abs().max(last.abs());
        if t0 - first > far && last - t1 > far && t0 <= t && t < t1 {
            let (v0, dv) = (values[j - 1], values[j] - values[j - 1]);
            Segment { t0, t1, v0, dv }
        } else {
            NO_SEGMENT
        }
    }
}

impl<'s> FixedSignal<'s> {
    /// `signal` at the parameter values `p`.
    pub fn new(signal: &'s Signal, p: &[f64]) -> Self {
        let kind = |shape: &Shape| match shape {
            Shape::Table {
                times,
                interpolation: Interpolation::Linear,
                ..
            } if times.len() >= 2 => {
                Kind::LinearTable((times.len() - 1) as f64 / (times[times.len() - 1] - times[0]))
            }
            Shape::Constant => Kind::Constant,
            _ => Kind::Other,
        };
        let terms = (signal.terms.iter())
            .map(|term| FixedTerm {
                amplitude: term.amplitude.eval(p),
                shape: &term.shape,
                kind: kind(&term.shape),
            })
            .collect();
        FixedSignal { terms }
    }

    /// The number of terms: the length of the segments kept for
    /// [`FixedSignal::at_side_kept`].
    pub fn terms(&self) -> usize {
        self.terms.len()
    }

    /// P(t) as the limit from before or after t ([`Signal::at_side`]).
    pub fn at_side(&self, t: f64, before: bool) -> f64 {
        (self.terms.iter())
            .map(|term| term.amplitude * term.shape_at_side(t, before, &mut Segment::default()))
            .sum()
    }

    /// Term j's shape alone (without its amplitude) at t, from before or
    /// after t, with its segment `kept` as [`FixedSignal::at_side_kept`]
    /// keeps it: the same value as the shape's own
    /// ([`crate::model::Shape::at_side`]).
    #[inline]
    pub fn shape_at_side_kept(&self, j: usize, t: f64, before: bool, kept: &mut Segment) -> f64 {
        self.terms[j].shape_at_side(t, before, kept)
    }

    /// [`FixedSignal::at_side`] reusing, for each linear table, the segment
    /// `kept` holds for its term (one per term, in order; any values, as
    /// the [`Default`]) when it holds t, and keeping the segment looked up
    /// otherwise: a run's instants, in increasing order, find their
    /// segment without a search. The same value either way.
    #[inline]
    pub fn at_side_kept(&self, t: f64, before: bool, kept: &mut [Segment]) -> f64 {
        assert_eq!(kept.len(), self.terms.len(), "one segment per term");
        if let ([term], [kept]) = (&self.terms[..], &mut kept[..]) {
            // The sum of one term, −0 + x, is x.
            return term.amplitude * term.shape_at_side(t, before, kept);
        }
        (self.terms.iter().zip(kept))
            .map(|(term, kept)| term.amplitude * term.shape_at_side(t, before, kept))
            .sum()
    }
}

impl FixedTerm<'_> {
    /// The term's shape at t, from before or after t, with its segment
    /// `kept` (see [`FixedSignal::at_side_kept`]).
    #[inline]
    fn shape_at_side(&self, t: f64, before: bool, kept: &mut Segment) -> f64 {
        let per_time = match self.kind {
            Kind::LinearTable(per_time) => per_time,
            // As `Shape::at_side`: 1 from t = 0 on, 0 before.
            Kind::Constant => return f64::from(u8::from(if before { t > 0.0 } else { t >= 0.0 })),
            Kind::Other => return self.shape.at_side(t, before),
        };
        if kept.holds(t) {
            return kept.at(t);
        }
        self.look_up(t, before, per_time, kept)
    }

    /// A linear table's value at t by the full lookup, keeping the segment
    /// that holds t for the next instants.
    #[cold]
    #[inline(never)]
    fn look_up(&self, t: f64, before: bool, per_time: f64, kept: &mut Segment) -> f64 {
        if let Shape::Table { times, values, .. } = self.shape {
            *kept = Segment::holding(times, values, t, per_time);
        }
        // Inside the segment found, the full look-up's value, without a
        // second search.
        match kept.holds(t) {
            true => kept.at(t),
            false => self.shape.table_side(t, before, Some(per_time)),
        }
    }
}
