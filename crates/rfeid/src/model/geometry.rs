//! Small-motion kinematics of rigid bodies (SPEC §1, eq. 4–5).
use nalgebra::{Matrix3, Matrix6, SMatrix, Vector3};

/// The cross-product matrix `[ρ]×`, with `[ρ]× v = ρ × v`.
pub fn cross_matrix(r: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(0.0, -r.z, r.y, r.z, 0.0, -r.x, -r.y, r.x, 0.0)
}

/// The attachment matrix `S(ρ) = [[I, −[ρ]×], [0, I]]` (eq. 4): the 6-vector
/// `[w; φ]` of a point at body-frame offset ρ is `S(ρ) q_b`, since
/// `w = u + φ × ρ = u − ρ × φ`.
pub fn attachment(rho: &Vector3<f64>) -> Matrix6<f64> {
    let mut s = Matrix6::identity();
    s.fixed_view_mut::<3, 3>(0, 3)
        .copy_from(&(-cross_matrix(rho)));
    s
}

/// `Θ = diag(θ, θ)` for a 3×3 direction-cosine matrix θ (eq. 4).
pub fn block_diag(theta: &Matrix3<f64>) -> Matrix6<f64> {
    let mut m = Matrix6::zeros();
    m.fixed_view_mut::<3, 3>(0, 0).copy_from(theta);
    m.fixed_view_mut::<3, 3>(3, 3).copy_from(theta);
    m
}

/// The row `hᵀ` (length 6) with `hᵀ q_b = n · R (u + φ × ρ)`: the motion of
/// the body-frame point ρ along the global direction n. Its transpose is also
/// the generalized force of a unit force along n applied at ρ.
pub fn point_direction_row(axes: &Matrix3<f64>, rho: &Vector3<f64>, n: &Vector3<f64>) -> [f64; 6] {
    let local = axes.transpose() * n;
    let mut f = SMatrix::<f64, 6, 1>::zeros();
    f.fixed_rows_mut::<3>(0).copy_from(&local);
    let g = attachment(rho).transpose() * f;
    let mut out = [0.0; 6];
    out.copy_from_slice(g.as_slice());
    out
}

/// Why a set of axes is not a right-handed orthonormal frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum AxesDefect {
    /// `|Rᵀ R − I|` exceeds the tolerance.
    NotOrthonormal {
        /// Largest entry of `Rᵀ R − I`.
        deviation: f64,
    },
    /// `det R < 0`.
    LeftHanded,
}

/// Checks that the columns of `r` form a right-handed orthonormal frame to
/// within `tol`.
pub fn check_axes(r: &Matrix3<f64>, tol: f64) -> Result<(), AxesDefect> {
    let dev = (r.transpose() * r - Matrix3::identity()).abs().max();
    if !(dev <= tol) {
        return Err(AxesDefect::NotOrthonormal { deviation: dev });
    }
    if r.determinant() < 0.0 {
        return Err(AxesDefect::LeftHanded);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn attachment_moves_a_point_by_u_plus_phi_cross_rho() {
        let rho = Vector3::new(0.3, -0.2, 0.7);
        let q = nalgebra::Vector6::new(1e-6, -2e-6, 3e-6, 1e-5, 2e-5, -3e-5);
        let w = attachment(&rho) * q;
        let u = Vector3::new(q[0], q[1], q[2]);
        let phi = Vector3::new(q[3], q[4], q[5]);
        let expect = u + phi.cross(&rho);
        for i in 0..3 {
            assert!((w[i] - expect[i]).abs() < 1e-20);
            assert_eq!(w[i + 3], phi[i]);
        }
    }

    #[test]
    fn axes_checks_catch_skew_and_left_handed_frames() {
        assert!(check_axes(&Matrix3::identity(), 1e-6).is_ok());
        let mut skew = Matrix3::identity();
        skew[(0, 1)] = 1e-3;
        assert!(matches!(
            check_axes(&skew, 1e-6),
            Err(AxesDefect::NotOrthonormal { .. })
        ));
        let left = Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, -1.0));
        assert_eq!(check_axes(&left, 1e-6), Err(AxesDefect::LeftHanded));
    }
}
