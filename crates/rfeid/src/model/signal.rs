//! Excitation signals P(t) (SPEC §1): a sum of terms `A_j · shape_j(t)`, so
//! that each amplitude A_j may be a parameter with a simple derivative.
use super::Value;
use std::f64::consts::PI;

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
    /// Samples linearly interpolated; 0 outside the table.
    Table {
        /// Strictly increasing instants, s.
        times: Vec<f64>,
        /// Values at those instants.
        values: Vec<f64>,
    },
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
            Shape::Table { times, values } => interpolate(times, values, t),
        }
    }
}

/// Linear interpolation in a strictly increasing table, 0 outside it.
fn interpolate(times: &[f64], values: &[f64], t: f64) -> f64 {
    let n = times.len();
    if n == 0 || t < times[0] || t > times[n - 1] {
        return 0.0;
    }
    let j = times.partition_point(|&x| x <= t);
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
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_interpolates_linearly_and_is_zero_outside() {
        let s = Shape::Table {
            times: vec![0.0, 1.0, 3.0],
            values: vec![0.0, 2.0, -2.0],
        };
        assert_eq!(s.at(-0.1), 0.0);
        assert_eq!(s.at(0.5), 1.0);
        assert_eq!(s.at(1.0), 2.0);
        assert_eq!(s.at(2.0), 0.0);
        assert_eq!(s.at(3.0), -2.0);
        assert_eq!(s.at(3.5), 0.0);
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
