//! Which components are springs, and the Gram matrix of their rows of B
//! in the mass-scaled coordinates, whose null space is the free space.
use crate::model::Law;
use crate::simulation::system::System;

/// Whether a component's law is a spring at the parameter values `p`.
pub(super) fn has_spring(law: &Law, p: &[f64]) -> bool {
    law.joint().is_spring(p)
}

/// `G = Σ_i b̃_i b̃_iᵀ` over the spring rows, `b̃_i = L⁻¹ b_i / |L⁻¹ b_i|`
/// (`sqrt_m` the diagonal of L), row-major n × n.
pub(super) fn spring_gram(sys: &System<'_>, sqrt_m: &[f64]) -> Vec<f64> {
    let n = sys.n;
    let mut g = vec![0.0; n * n];
    for comp in &sys.structure.components {
        if !has_spring(&comp.law, &sys.params) {
            continue;
        }
        let mut row = comp.row.dense(n);
        for (r, s) in row.iter_mut().zip(sqrt_m) {
            *r /= s;
        }
        let norm2: f64 = row.iter().map(|v| v * v).sum();
        if !(norm2 > 0.0) {
            continue;
        }
        let nz: Vec<usize> = (0..n).filter(|&i| row[i] != 0.0).collect();
        for &i in &nz {
            for &j in &nz {
                g[i * n + j] += row[i] * row[j] / norm2;
            }
        }
    }
    g
}
