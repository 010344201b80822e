//! The map between a parameter's box and the normalised coordinate
//! `u ∈ [0, 1]` of the plan and the local search (eq. 17 and its
//! logarithmic form; see [`Scale`]).
//!
//! ```text
//! linear:  x = min + u (max − min),      dx/du = max − min
//! log:     x = min (max/min)^u,          dx/du = x ln(max/min)
//! ```
//!
//! The Jacobian in u is the Jacobian in x times `dx/du` (chain rule), and
//! the Cramér–Rao bounds divide it out again, so standard errors are in
//! physical units whatever the scale. The ends map exactly: u = 0 gives
//! `min` and u = 1 gives `max`, bit for bit, and x stays inside the box.
use crate::model::Scale;

/// One parameter's box and scale.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BoxMap {
    lo: f64,
    hi: f64,
    scale: Scale,
    /// ln(min) (log scale only).
    ln_lo: f64,
    /// ln(max/min) (log scale only).
    ln_ratio: f64,
}

impl BoxMap {
    /// The map of `[lo, hi]` (lo < hi; for [`Scale::Log`], lo > 0, which the
    /// model file guarantees).
    pub fn new(lo: f64, hi: f64, scale: Scale) -> Self {
        let (ln_lo, ln_ratio) = match scale {
            Scale::Log => (lo.ln(), (hi / lo).ln()),
            Scale::Linear => (0.0, 0.0),
        };
        BoxMap {
            lo,
            hi,
            scale,
            ln_lo,
            ln_ratio,
        }
    }

    /// The scale.
    pub fn scale(&self) -> Scale {
        self.scale
    }

    /// `max − min`.
    pub fn width(&self) -> f64 {
        self.hi - self.lo
    }

    /// The physical value at u.
    pub fn to_physical(&self, u: f64) -> f64 {
        if u <= 0.0 {
            return self.lo;
        }
        if u >= 1.0 {
            return self.hi;
        }
        let x = match self.scale {
            Scale::Linear => self.lo + u * (self.hi - self.lo),
            Scale::Log => (self.ln_lo + u * self.ln_ratio).exp(),
        };
        x.clamp(self.lo, self.hi)
    }

    /// The normalised coordinate of the physical value x.
    pub fn to_normalised(&self, x: f64) -> f64 {
        match self.scale {
            Scale::Linear => (x - self.lo) / (self.hi - self.lo),
            Scale::Log => (x / self.lo).ln() / self.ln_ratio,
        }
    }

    /// `dx/du` at u.
    pub fn derivative(&self, u: f64) -> f64 {
        match self.scale {
            Scale::Linear => self.hi - self.lo,
            Scale::Log => self.to_physical(u) * self.ln_ratio,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ends_map_exactly_and_the_middle_of_a_log_box_is_the_geometric_mean() {
        let m = BoxMap::new(3e4, 3e7, Scale::Log);
        assert_eq!(m.to_physical(0.0), 3e4);
        assert_eq!(m.to_physical(1.0), 3e7);
        let mid = m.to_physical(0.5);
        assert!((mid / (3e4_f64 * 3e7).sqrt() - 1.0).abs() < 1e-14);
        assert!((m.to_physical(1.0 / 3.0) / 3e5 - 1.0).abs() < 1e-14);
        let l = BoxMap::new(-2.0, 6.0, Scale::Linear);
        assert_eq!(l.to_physical(0.25), 0.0);
        assert_eq!(l.derivative(0.9), 8.0);
    }

    #[test]
    fn the_derivative_matches_central_differences() {
        let m = BoxMap::new(1e-3, 1e3, Scale::Log);
        for u in [0.1, 0.37, 0.5, 0.93] {
            let h = 1e-6;
            let fd = (m.to_physical(u + h) - m.to_physical(u - h)) / (2.0 * h);
            assert!((m.derivative(u) / fd - 1.0).abs() < 1e-8, "u = {u}");
        }
    }
}
