//! The linearised matrices of a [`System`] at a state of rest: the tangent
//! stiffness (eq. 2–6 differentiated), the damping matrix, and each
//! contact's law there (the static equilibrium, `modal`, the FRF).
use super::laws::contact::ContactAt;
use super::laws::power_law;
use super::structure::Row;
use super::system::{add_outer, System};

impl System<'_> {
    /// The tangent stiffness `K_t = K + Σ f'(δ_i) B_iᵀ B_i` at `q` (dense n×n,
    /// row-major), used for static equilibrium and modal analysis.
    pub fn tangent_stiffness(&self, q: &[f64]) -> Vec<f64> {
        let deformations: Vec<f64> = self.power.iter().map(|pr| pr.row.dot(q)).collect();
        let mut kt = self.tangent_at_deformations(&deformations);
        for (row, at) in self.contacts_at(q) {
            add_outer(&mut kt, self.n, row, at.slope);
        }
        kt
    }

    /// Each contact's row of B and its law at rest at the coordinates `q`
    /// (absolute, not from a static equilibrium).
    pub(crate) fn contacts_at<'s>(
        &'s self,
        q: &'s [f64],
    ) -> impl Iterator<Item = (&'s Row, ContactAt)> + 's {
        self.contacts.iter().map(move |c| {
            let row = &self.structure.components[c.comp].row;
            (row, c.law.at(row.dot(q), 0.0))
        })
    }

    /// The tangent stiffness with each power-law spring at the deformation
    /// given for it (in the order of [`System::power_components`]' power
    /// laws), whatever state that would take: dense n×n, row-major.
    pub fn tangent_at_deformations(&self, deformations: &[f64]) -> Vec<f64> {
        let n = self.n;
        let mut kt = vec![0.0; n * n];
        for i in 0..n {
            for j in 0..n {
                kt[i * n + j] = -self.a_lin[i * 2 * n + j] / self.minv[i];
            }
        }
        for (pr, &delta) in self.power.iter().zip(deformations) {
            let (_, slope) = power_law(pr.a, pr.m, delta);
            if slope == 0.0 {
                continue;
            }
            add_outer(&mut kt, n, &pr.row, slope);
        }
        kt
    }

    /// For each component row, `Some((a, m))` for a power-law spring
    /// `a · sign(δ)|δ|^m`, δ in SI units.
    pub fn power_components(&self) -> Vec<Option<(f64, f64)>> {
        self.structure
            .components
            .iter()
            .map(|c| c.law.power_spring(&self.params).map(|p| (p.coef, p.m)))
            .collect()
    }

    /// The damping matrix C (dense n×n, row-major) at rest at the
    /// coordinates `q`: the dampers', and each closed contact's.
    pub fn damping_matrix(&self, q: &[f64]) -> Vec<f64> {
        let n = self.n;
        let mut c = vec![0.0; n * n];
        for i in 0..n {
            for j in 0..n {
                c[i * n + j] = -self.a_lin[i * 2 * n + n + j] / self.minv[i];
            }
        }
        for (row, at) in self.contacts_at(q) {
            add_outer(&mut c, n, row, at.damping);
        }
        c
    }
}
