//! A split step's derivative in the instant of a located contact switch
//! (`contact_events`), integrated through the step's pieces as a column of
//! its own.
//!
//! A step split at a located opening or closing θ* is a map D(θ*) of the
//! step's start state: Runge–Kutta pieces on [0, θ*] and [θ*, 1], each
//! with the contact held on its side. The sensitivities integrated through
//! the pieces at a fixed θ* are its derivative at that split; the located
//! instant moves with the parameters (`dt*/dx`, `contact_instant_rates`),
//! so the computed response's derivative adds `D'(θ*) dθ*/dx`.
//!
//! For the exact flow, D' is the jump condition `(ẏ⁻ − ẏ⁺) h`. The
//! computed pieces differ from it by their local error's derivative in
//! their lengths: small where the law is smooth on both sides, but O(h^1.5)
//! after the closing of a power-law contact `a s^1.5`, whose spring is not
//! twice differentiable there (docs/benchmarks.md). So D' is the pieces'
//! own derivative, by the chain rule through their stages. A piece from
//! θ_a to θ_b of length L, stage times `t_i = t + θ_a h + c_i L`: in θ*,
//! `dL = h ([b = *] − [a = *])` and `dt_i = h ((1 − c_i)[a = *] + c_i [b = *])`,
//! so with `Z_i = dY_i/dθ*`
//!
//! `dk_i = J_i Z_i + ∂F/∂t dt_i`, `Z_i = Z + L Σ_j a_ij (dk_j + k_j dL/L)`,
//!
//! which is the sensitivity recurrence for a column with the explicit term
//! `E_i = (dL/L) k_i + ∂F/∂t dt_i` ([`Stepper::add_shift_terms`]), ∂F/∂t
//! the excitation's rate (`Shape::rate_side`).
use super::dim::Dim;
use super::madd::Madd;
use super::stepper::Stepper;
use super::workspace::Workspace;

impl<M: Madd, D: Dim> Stepper<'_, M, D> {
    /// Adds the split column's explicit term at stage i (time t) of the
    /// current piece to `ws.ks` and `ws.z.ks` ([`Shift`]). Out of line and
    /// cold: only the pieces next to a located switch have one.
    #[cold]
    #[inline(never)]
    pub(super) fn add_shift_terms(&self, ws: &mut Workspace, i: usize, t: f64) {
        let (Some(col), n) = (self.tangent.shift, self.sys.n) else {
            return;
        };
        let (n2, w, nz) = (2 * n, self.width(), ws.z.y.len());
        let (dl, a, b, len) = ws.shift.piece;
        let ci = self.tab.c[i];
        let dt = (1.0 - ci) * a + ci * b;
        let per = dl / len;
        let ks = &mut ws.ks[i * n2 * w..(i + 1) * n2 * w];
        for (row, &k) in ks.chunks_exact_mut(w).zip(&ws.k[i * n2..(i + 1) * n2]) {
            row[col] += per * k;
        }
        let zks = &mut ws.z.ks[i * nz * w..(i + 1) * nz * w];
        for (row, &k) in zks.chunks_exact_mut(w).zip(&ws.z.k[i * nz..(i + 1) * nz]) {
            row[col] += per * k;
        }
        let sys = self.sys;
        if dt == 0.0 || sys.minv_loads.is_empty() {
            return;
        }
        // ∂q̈/∂t = Σ_e M⁻¹P_e ṗ_e(t), at the stage's side of t.
        let rates = &mut ws.shift.forces;
        rates.resize(sys.minv_loads.len(), 0.0);
        sys.force_rates(t, i > 0 && ci == 1.0, rates);
        for (e, loads) in sys.minv_loads.iter().enumerate() {
            let rate = dt * rates[e];
            if rate != 0.0 {
                for (row, &l) in ks[n * w..].chunks_exact_mut(w).zip(loads) {
                    row[col] += rate * l;
                }
            }
        }
    }

    /// At the end of a split step of length h: adds the split column times
    /// `dθ*/dx = (dt*/dx)/h` to every parameter's column, then clears it.
    /// Out of line and cold, as [`Self::add_shift_terms`].
    #[cold]
    #[inline(never)]
    pub(super) fn apply_shift(&self, ws: &mut Workspace, h: f64) {
        let Some(col) = self.tangent.shift else {
            return;
        };
        let w = self.width();
        let rates = &ws.shift.rates;
        let rows = ws.sy.chunks_exact_mut(w).chain(ws.z.sy.chunks_exact_mut(w));
        for row in rows {
            let d = row[col] / h;
            row[col] = 0.0;
            for (r, &dt) in row[..col].iter_mut().zip(rates) {
                if dt.is_finite() {
                    *r += d * dt;
                }
            }
        }
        ws.shift.reset();
    }
}
