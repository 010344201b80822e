//! Excitation signals P(t) (SPEC §1): a sum of terms `A_j · shape_j(t)`, so
//! that each amplitude A_j may be a parameter with a simple derivative.
mod band_limited;
mod fixed;
mod rate;

pub use band_limited::{BandLimited, BandLimitedError};
pub use fixed::{FixedSignal, Segment};

use super::Value;
use std::f64::consts::PI;
use std::sync::Arc;

/// The time history of one term, with unit amplitude.
#[derive(Debug, Clone, PartialEq)]
pub enum Shape {
    /// `sin(2π f t + φ)`.
    Sine {
        /// Frequency, Hz.
        frequency: f64,
        /// Phase, rad.
        phase: f64,
    },
    /// `sin(2π(f0 t + (f1 − f0) t² / (2T)))` for `0 ≤ t ≤ T`, else 0.
    Chirp {
        /// Start frequency, Hz.
        f0: f64,
        /// End frequency, Hz.
        f1: f64,
        /// Sweep time T, s.
        duration: f64,
    },
    /// Half-sine pulse `sin(π(t − t0)/w)` for `t0 ≤ t ≤ t0 + w`, else 0.
    Impulse {
        /// Start, s.
        t0: f64,
        /// Width w, s.
        width: f64,
    },
    /// 1 for `t ≥ 0` (a steady load: a force offset, a weight not modelled
    /// as gravity).
    Constant,
    /// Samples interpolated between them (linearly, or as a band-limited
    /// signal); 0 outside the table. Build it with [`Shape::linear_table`]
    /// or [`Shape::band_limited_table`].
    Table {
        /// Strictly increasing instants, s.
        times: Vec<f64>,
        /// Values at those instants.
        values: Vec<f64>,
        /// How the samples are interpolated.
        interpolation: Interpolation,
    },
}

/// How a `table` signal's samples are interpolated (SPEC §1, the key
/// `interpolation`).
#[derive(Debug, Clone, PartialEq)]
pub enum Interpolation {
    /// Straight lines between samples (the default, `"linear"`): the steps
    /// are split at every sample, where the slope jumps.
    Linear,
    /// The periodic band-limited (sinc) interpolant of evenly spaced samples
    /// (`"band-limited"`): smooth, exact for a record of whole periods of a
    /// signal without content at or above half the sample rate. Shared, as
    /// it holds 4 values per sample.
    BandLimited(Arc<BandLimited>),
}

impl Shape {
    /// A table of samples, linearly interpolated; 0 outside.
    pub fn linear_table(times: Vec<f64>, values: Vec<f64>) -> Shape {
        Shape::Table {
            times,
            values,
            interpolation: Interpolation::Linear,
        }
    }

    /// A table of evenly spaced samples of a band-limited signal,
    /// interpolated by [`BandLimited`]; 0 outside. An error when the
    /// instants are not evenly spaced (or fewer than 2).
    pub fn band_limited_table(
        times: Vec<f64>,
        values: Vec<f64>,
    ) -> Result<Shape, BandLimitedError> {
        let interpolant = BandLimited::new(&times, &values)?;
        Ok(Shape::Table {
            times,
            values,
            interpolation: Interpolation::BandLimited(Arc::new(interpolant)),
        })
    }
}

impl Shape {
    /// The unit-amplitude value at time t.
    pub fn at(&self, t: f64) -> f64 {
        match self {
            Shape::Sine { frequency, phase } => (2.0 * PI * frequency * t + phase).sin(),
            Shape::Chirp { f0, f1, duration } => {
                if (0.0..=*duration).contains(&t) {
                    (2.0 * PI * (f0 * t + (f1 - f0) * t * t / (2.0 * duration))).sin()
                } else {
                    0.0
                }
            }
            Shape::Impulse { t0, width } => {
                if t >= *t0 && t <= t0 + width {
                    (PI * (t - t0) / width).sin()
                } else {
                    0.0
                }
            }
            Shape::Constant => f64::from(u8::from(t >= 0.0)),
            // Zero outside the table's span.
            Shape::Table {
                times,
                values,
                interpolation,
            } => match (times.first(), times.last()) {
                (Some(&first), Some(&last)) if (first..=last).contains(&t) => {
                    table_value(times, values, interpolation, t)
                }
                _ => 0.0,
            },
        }
    }

    /// The value at t as the limit from before t (`before`) or from after
    /// it: the two differ where the shape jumps (the end of a chirp, the
    /// ends of a table). A step that ends at such an instant evaluates it
    /// from before, the next step starts from after. Within a few units in
    /// the last place of a jump, t counts as being at it.
    pub fn at_side(&self, t: f64, before: bool) -> f64 {
        match self {
            Shape::Chirp { duration, .. } => {
                let end = *duration;
                let inside = match before {
                    true => t > 0.0 && (t <= end || near(t, end)),
                    false => t >= 0.0 && t < end && !near(t, end),
                };
                match inside {
                    true => self.at(t.min(end)),
                    false => 0.0,
                }
            }
            Shape::Table { .. } => self.table_side(t, before, None),
            // It starts at t = 0, where a run starts from rest.
            Shape::Constant => match before {
                true => f64::from(u8::from(t > 0.0)),
                false => self.at(t),
            },
            // Continuous: a sine, and a half-sine pulse (zero at both ends).
            Shape::Sine { .. } | Shape::Impulse { .. } => self.at(t),
        }
    }

    /// [`Shape::at_side`] of a table (0 for any other shape), with its
    /// knots per unit time `(n − 1)/(t_last − t_first)` if known (see
    /// [`FixedSignal`]).
    fn table_side(&self, t: f64, before: bool, per_time: Option<f64>) -> f64 {
        let Shape::Table {
            times,
            values,
            interpolation,
        } = self
        else {
            return 0.0;
        };
        let (Some(&first), Some(&last)) = (times.first(), times.last()) else {
            return 0.0;
        };
        let inside = within(t, (first, last), before);
        // Clamped only inside: a table whose ends are not in order (built
        // by hand; a file's are checked) is zero, as `at` gives it.
        match (inside, interpolation) {
            (false, _) => 0.0,
            (true, Interpolation::Linear) => {
                interpolate(times, values, t.clamp(first, last), per_time)
            }
            (true, Interpolation::BandLimited(b)) => b.at(t.clamp(first, last)),
        }
    }

    /// The instants where the shape has a kink or a jump (or a higher
    /// derivative jumps): a step across one loses the method's order, so
    /// steps are split there. Unsorted. A linear table has one at every
    /// sample; a band-limited one is smooth inside, and jumps only at its
    /// ends.
    pub fn breakpoints(&self) -> Vec<f64> {
        match self {
            Shape::Sine { .. } => Vec::new(),
            Shape::Chirp { duration, .. } => vec![0.0, *duration],
            Shape::Impulse { t0, width } => vec![*t0, t0 + width],
            Shape::Constant => vec![0.0],
            Shape::Table {
                times,
                interpolation: Interpolation::Linear,
                ..
            } => times.clone(),
            Shape::Table { times, .. } => match (times.first(), times.last()) {
                (Some(&first), Some(&last)) => vec![first, last],
                _ => Vec::new(),
            },
        }
    }
}

/// Whether t is within a few units in the last place of `b` (an instant
/// at which a shape jumps counts as at it, [`Shape::at_side`]).
fn near(a: f64, b: f64) -> bool {
    (a - b).abs() <= 8.0 * f64::EPSILON * b.abs().max(a.abs())
}

/// Whether t is inside the span `(first, last)` as the limit from before t
/// (`before`) or from after it: a table's span, [`Shape::at_side`].
fn within(t: f64, (first, last): (f64, f64), before: bool) -> bool {
    match before {
        true => t > first && !near(t, first) && (t <= last || near(t, last)),
        false => (t >= first || near(t, first)) && t < last && !near(t, last),
    }
}

/// A table's value at t inside its span.
fn table_value(times: &[f64], values: &[f64], interpolation: &Interpolation, t: f64) -> f64 {
    match interpolation {
        Interpolation::Linear => interpolate(times, values, t, None),
        Interpolation::BandLimited(b) => b.at(t),
    }
}

/// Linear interpolation in a strictly increasing table, 0 outside it;
/// `per_time` as in [`knot_after`].
fn interpolate(times: &[f64], values: &[f64], t: f64, per_time: Option<f64>) -> f64 {
    let n = times.len();
    if n == 0 || t < times[0] || t > times[n - 1] {
        return 0.0;
    }
    let j = knot_after(times, t, per_time);
    if j == 0 {
        return values[0];
    }
    if j >= n {
        return values[n - 1];
    }
    let (t0, t1) = (times[j - 1], times[j]);
    let w = (t - t0) / (t1 - t0);
    values[j - 1] + w * (values[j] - values[j - 1])
}

/// The first index j with `times[j] > t` (as `partition_point`), in O(1)
/// on an evenly spaced table (a record of samples, such as a measured force
/// of 10⁵ samples, looked up at every stage of every step): j is guessed
/// from the first instant and the knots per unit time (`per_time`, computed
/// here if not given) and checked against its neighbours, else found by
/// bisection. The same j either way, so the same force.
fn knot_after(times: &[f64], t: f64, per_time: Option<f64>) -> usize {
    let n = times.len();
    if n >= 2 {
        let (first, last) = (times[0], times[n - 1]);
        let per_time = per_time.unwrap_or_else(|| (n - 1) as f64 / (last - first));
        let guess = (t - first) * per_time;
        if guess >= 0.0 && guess < n as f64 {
            // Truncation is the floor here, without a call to libm.
            let i = guess as usize;
            // j = i + 1 when the spacing is even; rounding may move it by one.
            for j in [i + 1, i, i + 2] {
                if (1..=n).contains(&j) && times[j - 1] <= t && (j == n || times[j] > t) {
                    return j;
                }
            }
        }
    }
    times.partition_point(|&x| x <= t)
}

/// One term of a signal: amplitude times shape.
#[derive(Debug, Clone, PartialEq)]
pub struct Term {
    /// Amplitude A (N), possibly a parameter.
    pub amplitude: Value,
    /// Unit-amplitude time history.
    pub shape: Shape,
}

/// P(t) = Σ_j A_j · shape_j(t).
#[derive(Debug, Clone, PartialEq)]
pub struct Signal {
    /// The kind as written in the file (`sine`, `multisine`, …), for reports.
    pub kind: &'static str,
    /// The terms.
    pub terms: Vec<Term>,
}

impl Signal {
    /// P(t) for parameter values `p`.
    pub fn at(&self, t: f64, p: &[f64]) -> f64 {
        self.terms
            .iter()
            .map(|term| term.amplitude.eval(p) * term.shape.at(t))
            .sum()
    }

    /// P(t) as the limit from before or after t ([`Shape::at_side`]).
    pub fn at_side(&self, t: f64, p: &[f64], before: bool) -> f64 {
        self.terms
            .iter()
            .map(|term| term.amplitude.eval(p) * term.shape.at_side(t, before))
            .sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_interpolates_linearly_and_is_zero_outside() {
        let s = Shape::linear_table(vec![0.0, 1.0, 3.0], vec![0.0, 2.0, -2.0]);
        assert_eq!(s.at(-0.1), 0.0);
        assert_eq!(s.at(0.5), 1.0);
        assert_eq!(s.at(1.0), 2.0);
        assert_eq!(s.at(2.0), 0.0);
        assert_eq!(s.at(3.0), -2.0);
        assert_eq!(s.at(3.5), 0.0);
    }

    #[test]
    fn a_constant_is_one_from_t_0_on() {
        let c = Shape::Constant;
        assert_eq!((c.at(-1e-9), c.at(0.0), c.at(2.5)), (0.0, 1.0, 1.0));
        assert_eq!((c.at_side(0.0, true), c.at_side(0.0, false)), (0.0, 1.0));
        assert_eq!(c.at_side(1.0, true), 1.0);
        assert_eq!(c.breakpoints(), vec![0.0]);
    }

    #[test]
    fn the_knot_lookup_is_bisection_on_even_and_uneven_tables() {
        let rate = 610.3515625;
        let even: Vec<f64> = (0..1000).map(|k| k as f64 / rate).collect();
        let uneven: Vec<f64> = (0..1000).map(|k| (k as f64).powf(1.5) * 1e-3).collect();
        for times in [even, uneven, vec![0.0, 1.0], vec![0.0, 1.0, 3.0]] {
            let last = *times.last().unwrap();
            let probes = (0..=4000)
                .map(|i| last * i as f64 / 4000.0)
                .chain(times.iter().copied())
                .chain(times.iter().map(|t| t * (1.0 + 1e-15)))
                .chain(times.iter().map(|t| t * (1.0 - 1e-15)));
            for t in probes.filter(|t| (0.0..=last).contains(t)) {
                assert_eq!(
                    knot_after(&times, t, None),
                    times.partition_point(|&x| x <= t),
                    "t = {t}"
                );
            }
        }
    }

    /// A signal at fixed parameters gives the same forces, bit for bit, as
    /// the signal evaluated with them, from both sides, at and between the
    /// knots of even and uneven tables, with the knot guessed by a product
    /// and the last segment reused: the instants in increasing order (as
    /// a run asks), then in a scrambled order, so that the kept segment is
    /// as often wrong as right.
    #[test]
    fn a_fixed_signal_equals_the_signal_bit_for_bit() {
        let rate = 610.3515625;
        let even: Vec<f64> = (0..500).map(|k| k as f64 / rate).collect();
        let uneven: Vec<f64> = (0..500).map(|k| (k as f64).powf(1.5) * 1e-3).collect();
        let values: Vec<f64> = (0..500).map(|k| (k as f64 * 0.37).sin()).collect();
        let term = |amplitude: Value, shape: Shape| Term { amplitude, shape };
        let signal = Signal {
            kind: "test",
            terms: vec![
                term(
                    Value::Param(0),
                    Shape::linear_table(even.clone(), values.clone()),
                ),
                term(
                    Value::Fixed(-0.3),
                    Shape::linear_table(uneven.clone(), values),
                ),
                term(Value::Param(1), Shape::Constant),
                term(
                    Value::Fixed(2.0),
                    Shape::Chirp {
                        f0: 1.0,
                        f1: 40.0,
                        duration: 0.5,
                    },
                ),
            ],
        };
        let p = [1.7, -4.1];
        let fixed = FixedSignal::new(&signal, &p);
        let mut kept = vec![Segment::default(); fixed.terms()];
        let last = uneven[499].max(even[499]);
        let probes: Vec<f64> = (0..=20_000)
            .map(|i| last * i as f64 / 20_000.0 - 0.01)
            .chain(even.iter().chain(&uneven).copied())
            .chain(even.iter().map(|t| t * (1.0 + 1e-15)))
            .chain(even.iter().map(|t| t * (1.0 - 1e-15)))
            .collect();
        // 7919 is prime and does not divide the number of probes.
        let scrambled = (0..probes.len()).map(|i| probes[i * 7919 % probes.len()]);
        assert_ne!(probes.len() % 7919, 0);
        for t in probes.iter().copied().chain(scrambled) {
            for before in [true, false] {
                let a = signal.at_side(t, &p, before);
                let b = fixed.at_side(t, before);
                let c = fixed.at_side_kept(t, before, &mut kept);
                assert_eq!(a.to_bits(), b.to_bits(), "t = {t}, before {before}");
                assert_eq!(a.to_bits(), c.to_bits(), "t = {t}, before {before}, kept");
            }
        }
    }

    #[test]
    fn jumps_have_a_value_from_each_side() {
        let c = Shape::Chirp {
            f0: 10.0,
            f1: 100.0,
            duration: 0.5,
        };
        assert_eq!(c.at_side(0.5, true), c.at(0.5));
        assert_ne!(c.at(0.5), 0.0);
        assert_eq!(c.at_side(0.5, false), 0.0);
        // An instant off by rounding counts as the jump.
        let off = 0.5 + f64::EPSILON;
        assert_eq!(c.at_side(off, true), c.at(0.5));
        let t = Shape::linear_table(vec![0.1, 0.2], vec![3.0, 5.0]);
        assert_eq!(t.at_side(0.1, true), 0.0);
        assert_eq!(t.at_side(0.1, false), 3.0);
        assert_eq!(t.at_side(0.2, true), 5.0);
        assert_eq!(t.at_side(0.2, false), 0.0);
        assert_eq!(t.at_side(0.15, true), t.at(0.15));
        assert_eq!(t.at_side(0.15, false), t.at(0.15));
    }

    #[test]
    fn a_band_limited_table_is_smooth_inside_and_ends_like_a_linear_one() {
        // Five whole periods of 5 Hz at 64 Hz: a periodic band-limited record.
        let times: Vec<f64> = (0..64).map(|k| 0.1 + k as f64 / 64.0).collect();
        let values: Vec<f64> = times
            .iter()
            .map(|t| 1.0 + (2.0 * PI * 5.0 * t).sin())
            .collect();
        let linear = Shape::linear_table(times.clone(), values.clone());
        let s = Shape::band_limited_table(times.clone(), values.clone()).unwrap();
        let (first, last) = (times[0], times[63]);
        assert_eq!(s.breakpoints(), vec![first, last]);
        assert_eq!(linear.breakpoints(), times);
        for shape in [&s, &linear] {
            assert_eq!(shape.at(first - 1e-9), 0.0);
            assert_eq!(shape.at(last + 1e-9), 0.0);
            assert_eq!(shape.at_side(first, true), 0.0);
            assert_eq!(shape.at_side(last, false), 0.0);
            assert!((shape.at_side(first, false) - values[0]).abs() <= 1e-12);
            assert!((shape.at_side(last, true) - values[63]).abs() <= 1e-12);
        }
        // Between samples it follows the sine, not the chord.
        let t = 0.1 + 10.5 / 64.0;
        let exact = 1.0 + (2.0 * PI * 5.0 * t).sin();
        assert!((s.at(t) - exact).abs() < 1e-12);
        assert!((linear.at(t) - exact).abs() > 1e-4);
        assert_eq!(s.at_side(t, true), s.at(t));
        let uneven = Shape::band_limited_table(vec![0.0, 1.0, 3.0], vec![1.0; 3]);
        assert!(matches!(
            uneven,
            Err(BandLimitedError::Uneven { index: 1, .. })
        ));
    }

    #[test]
    fn chirp_and_impulse_vanish_outside_their_windows() {
        let c = Shape::Chirp {
            f0: 10.0,
            f1: 100.0,
            duration: 0.5,
        };
        assert_eq!(c.at(0.6), 0.0);
        let i = Shape::Impulse {
            t0: 0.1,
            width: 0.01,
        };
        assert_eq!(i.at(0.05), 0.0);
        assert!((i.at(0.105) - 1.0).abs() < 1e-12);
    }
}
