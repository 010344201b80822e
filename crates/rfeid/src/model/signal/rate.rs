//! The excitation's rate dP/dt, exact for every shape: what a step's
//! derivative in where it is split needs (`simulation::split_shifts`).
use super::{knot_after, near, within, Interpolation, Shape, Signal};
use std::f64::consts::PI;

impl Shape {
    /// The unit-amplitude shape's time derivative at t, as the limit from
    /// before t (`before`) or from after it, as [`Shape::at_side`] takes
    /// its value: zero where the shape is zero, the segment's slope on a
    /// linear table (the segment before a knot from before, after it from
    /// after).
    pub fn rate_side(&self, t: f64, before: bool) -> f64 {
        let inside = |first: f64, last: f64| within(t, (first, last), before);
        match self {
            Shape::Sine { frequency, phase } => {
                2.0 * PI * frequency * (2.0 * PI * frequency * t + phase).cos()
            }
            Shape::Chirp { f0, f1, duration } if inside(0.0, *duration) => {
                let t = t.min(*duration);
                let sweep = (f1 - f0) / duration;
                let angle = 2.0 * PI * (f0 * t + sweep * t * t / 2.0);
                2.0 * PI * (f0 + sweep * t) * angle.cos()
            }
            Shape::Impulse { t0, width } if inside(*t0, t0 + width) => {
                PI / width * (PI * (t - t0) / width).cos()
            }
            Shape::Table {
                times,
                values,
                interpolation,
            } => match (times.first(), times.last()) {
                (Some(&first), Some(&last)) if inside(first, last) => match interpolation {
                    Interpolation::Linear => {
                        let n = times.len();
                        let mut j = knot_after(times, t.clamp(first, last), None);
                        if before && j >= 1 && near(t, times[j - 1]) {
                            j -= 1;
                        } else if !before && j < n && near(t, times[j]) {
                            j += 1;
                        }
                        let j = j.clamp(1, n - 1);
                        (values[j] - values[j - 1]) / (times[j] - times[j - 1])
                    }
                    Interpolation::BandLimited(b) => b.rate(t.clamp(first, last)),
                },
                _ => 0.0,
            },
            _ => 0.0,
        }
    }
}

impl Signal {
    /// dP/dt for parameter values `p`, as the limit from before or after t
    /// ([`Shape::rate_side`]).
    pub fn rate_side(&self, t: f64, p: &[f64], before: bool) -> f64 {
        self.terms
            .iter()
            .map(|term| term.amplitude.eval(p) * term.shape.rate_side(t, before))
            .sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::signal::BandLimited;
    use std::sync::Arc;

    /// Each shape's rate against a central difference of its value, inside
    /// its span; zero outside.
    #[test]
    fn rates_match_central_differences() {
        let times: Vec<f64> = (0..64).map(|k| k as f64 * 0.01).collect();
        let values: Vec<f64> = times.iter().map(|t| (7.0 * t).sin() + 0.3 * t).collect();
        let band = BandLimited::new(&times, &values).expect("an even record");
        let shapes = [
            Shape::Sine {
                frequency: 3.0,
                phase: 0.4,
            },
            Shape::Chirp {
                f0: 1.0,
                f1: 9.0,
                duration: 0.5,
            },
            Shape::Impulse {
                t0: 0.1,
                width: 0.2,
            },
            Shape::Constant,
            Shape::linear_table(times.clone(), values.clone()),
            Shape::Table {
                times,
                values,
                interpolation: Interpolation::BandLimited(Arc::new(band)),
            },
        ];
        for shape in &shapes {
            for t in [0.137, 0.2543, 0.3001, 0.4459] {
                let h = 1e-6;
                let fd = (shape.at(t + h) - shape.at(t - h)) / (2.0 * h);
                let rate = shape.rate_side(t, false);
                assert!(
                    (rate - fd).abs() <= 1e-6 * fd.abs().max(1.0),
                    "{shape:?} at {t}: {rate} vs {fd}"
                );
                assert_eq!(rate, shape.rate_side(t, true), "{shape:?} at {t}");
            }
            if !matches!(shape, Shape::Sine { .. }) {
                assert_eq!(shape.rate_side(-0.5, false), 0.0, "{shape:?}");
            }
        }
        // A linear table's knot: the segment before it, from before.
        let s = Shape::linear_table(vec![0.0, 1.0, 3.0], vec![0.0, 2.0, -2.0]);
        assert_eq!(s.rate_side(1.0, true), 2.0);
        assert_eq!(s.rate_side(1.0, false), -2.0);
    }
}
