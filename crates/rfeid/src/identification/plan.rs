//! LP_τ plans (eq. 18–19): Sobol points in the normalised box `[0, 1]^r`.
//!
//! The paper computes plan point i, coordinate j, from Sobol and Levitan's
//! constants `S_j^(l)` (eq. 19): a digit-by-digit XOR of the binary digits of
//! i with direction numbers. We use the same construction in its usual form,
//!
//! ```text
//! x_ij = ⊕_{l : bit l−1 of i is 1} v_j^(l),        v_j^(l) = m_j^(l) / 2^l
//! ```
//!
//! (⊕ the bitwise XOR of binary fractions), with the direction numbers of
//! Joe & Kuo, file `new-joe-kuo-6.21201` (D(6) criterion), as SPEC §2 fixes.
//! Points are in natural (index) order, not the Gray-code order of fast
//! generators, and point 0 (the origin) is skipped, so plan point i is Sobol
//! point i for i = 1 … N_p. Point i is therefore the same whatever N_p is and
//! a plan can be extended without recomputing its first points (paper §3):
//! see [`LpTau::plan_range`].
//!
//! The direction numbers come from the `sobol` crate's copy of the Joe–Kuo
//! tables (`JoeKuoD6::standard()`, the first 1000 dimensions of
//! `new-joe-kuo-6.21201`); the recurrence that extends them to 53 bits is the
//! crate's `Sobol::init_direction_vals`. Coordinates are exact binary
//! fractions with at most 53 significant bits, so they are exact `f64`s.
use sobol::params::JoeKuoD6;
use sobol::Sobol;

/// Largest dimension r an LP_τ plan supports (the Joe–Kuo table shipped with
/// the `sobol` crate's `JoeKuoD6::standard()`).
pub const MAX_DIMENSIONS: usize = 1000;

/// Number of bits of the direction numbers; Sobol indices must be < 2^53.
const BITS: usize = 53;

/// Largest Sobol index a plan may contain (2^53 − 1).
pub const MAX_INDEX: u64 = (1u64 << BITS) - 1;

/// A plan could not be built or evaluated.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum PlanError {
    /// A plan of zero points was asked for.
    #[error("a plan needs at least one point (N_p = 0)")]
    NoPoints,
    /// A plan in zero dimensions was asked for.
    #[error("a plan needs at least one dimension (r = 0)")]
    NoDimensions,
    /// More dimensions than the direction numbers support.
    #[error("{requested} dimensions requested, the direction numbers support at most {max}")]
    TooManyDimensions {
        /// Requested dimension r.
        requested: usize,
        /// [`MAX_DIMENSIONS`].
        max: usize,
    },
    /// The last requested Sobol index exceeds [`MAX_INDEX`], or the first
    /// index is 0 (the skipped origin).
    #[error("Sobol indices {first}..{first}+{count} are outside 1..=2^53-1")]
    IndexOutOfRange {
        /// First requested index.
        first: u64,
        /// Number of requested points.
        count: usize,
    },
    /// An appended plan does not continue this one (other dimension, or its
    /// first Sobol index is not the next one).
    #[error("the appended plan (dimension {dims}, first index {first}) does not continue this one (next index {expected})")]
    NotContiguous {
        /// Dimension of the appended plan.
        dims: usize,
        /// First Sobol index of the appended plan.
        first: u64,
        /// The Sobol index that would continue this plan.
        expected: u64,
    },
    /// The plan's dimension differs from the problem's number of parameters.
    #[error("the plan has {plan} dimensions, the problem has {problem} parameters")]
    DimensionMismatch {
        /// Dimension of the plan.
        plan: usize,
        /// Number of parameters of the problem.
        problem: usize,
    },
}

/// Generator of LP_τ (Sobol) points in natural order (eq. 18–19).
#[derive(Debug, Clone)]
pub struct LpTau {
    dims: usize,
    /// `directions[j][l]` = v_j^(l+1) as a 64-bit left-aligned binary fraction.
    directions: Vec<Vec<u64>>,
}

impl LpTau {
    /// A generator for dimension `dims` (1 ≤ dims ≤ [`MAX_DIMENSIONS`]).
    pub fn new(dims: usize) -> Result<Self, PlanError> {
        if dims == 0 {
            return Err(PlanError::NoDimensions);
        }
        if dims > MAX_DIMENSIONS {
            return Err(PlanError::TooManyDimensions {
                requested: dims,
                max: MAX_DIMENSIONS,
            });
        }
        let params = JoeKuoD6::standard();
        debug_assert!(params.max_dims >= MAX_DIMENSIONS);
        let directions = Sobol::<f64>::init_direction_vals::<u32>(dims, BITS, &params);
        Ok(LpTau { dims, directions })
    }

    /// The dimension r of the points.
    pub fn dims(&self) -> usize {
        self.dims
    }

    /// Writes Sobol point `index` (natural order; 0 is the origin) into
    /// `out` (length [`LpTau::dims`]), eq. 19.
    ///
    /// # Panics
    /// If `out.len() != self.dims()` or `index > MAX_INDEX`.
    pub fn point_into(&self, index: u64, out: &mut [f64]) {
        assert_eq!(
            out.len(),
            self.dims,
            "output length must equal the dimension"
        );
        assert!(index <= MAX_INDEX, "Sobol index beyond 2^53 - 1");
        // 2^-64: the direction numbers are left-aligned in 64 bits.
        const SCALE: f64 = 1.0 / 18_446_744_073_709_551_616.0;
        for (x, dirs) in out.iter_mut().zip(&self.directions) {
            let mut bits = index;
            let mut acc = 0u64;
            let mut l = 0;
            while bits != 0 {
                if bits & 1 == 1 {
                    acc ^= dirs[l];
                }
                bits >>= 1;
                l += 1;
            }
            // `acc` has at most 53 significant bits: the conversion is exact.
            *x = acc as f64 * SCALE;
        }
    }

    /// Plan points 1 … `n_points` (eq. 18–19; the origin is skipped).
    pub fn plan(&self, n_points: usize) -> Result<Plan, PlanError> {
        self.plan_range(1, n_points)
    }

    /// `count` plan points starting at Sobol index `first` ≥ 1: the extension
    /// of a plan of `first − 1` points by `count` more (paper §3).
    pub fn plan_range(&self, first: u64, count: usize) -> Result<Plan, PlanError> {
        if count == 0 {
            return Err(PlanError::NoPoints);
        }
        let last = first.checked_add(count as u64 - 1);
        if first == 0 || last.is_none_or(|l| l > MAX_INDEX) {
            return Err(PlanError::IndexOutOfRange { first, count });
        }
        let mut coords = vec![0.0; count * self.dims];
        for (k, chunk) in coords.chunks_exact_mut(self.dims).enumerate() {
            self.point_into(first + k as u64, chunk);
        }
        Ok(Plan {
            dims: self.dims,
            first_index: first,
            coords,
        })
    }
}

/// The LP_τ plan of `n_points` points in `dims` dimensions: Sobol points
/// 1 … N_p (eq. 18–19), each in `[0, 1)^dims`.
pub fn lp_tau_plan(dims: usize, n_points: usize) -> Result<Plan, PlanError> {
    LpTau::new(dims)?.plan(n_points)
}

/// A set of plan points in the normalised box, stored row by row.
#[derive(Debug, Clone, PartialEq)]
pub struct Plan {
    dims: usize,
    first_index: u64,
    coords: Vec<f64>,
}

impl Plan {
    /// Number of points N_p.
    pub fn len(&self) -> usize {
        self.coords.len() / self.dims
    }

    /// `true` if the plan has no points (never, for a plan built by
    /// [`LpTau`]).
    pub fn is_empty(&self) -> bool {
        self.coords.is_empty()
    }

    /// Dimension r of each point.
    pub fn dims(&self) -> usize {
        self.dims
    }

    /// Point `k` (0-based position in this plan).
    pub fn point(&self, k: usize) -> &[f64] {
        &self.coords[k * self.dims..(k + 1) * self.dims]
    }

    /// Sobol index (i of eq. 18–19) of point `k` of this plan.
    pub fn sobol_index(&self, k: usize) -> u64 {
        self.first_index + k as u64
    }

    /// The points in order.
    pub fn iter(&self) -> std::slice::ChunksExact<'_, f64> {
        self.coords.chunks_exact(self.dims)
    }

    /// The Sobol index that would follow this plan's last point.
    pub fn next_index(&self) -> u64 {
        self.first_index + self.len() as u64
    }

    /// Appends `other`, which must continue this plan (same dimension, first
    /// index [`Plan::next_index`]): extending N_p without recomputing the
    /// first points (paper §3).
    pub fn append(&mut self, other: &Plan) -> Result<(), PlanError> {
        if other.dims != self.dims || other.first_index != self.next_index() {
            return Err(PlanError::NotContiguous {
                dims: other.dims,
                first: other.first_index,
                expected: self.next_index(),
            });
        }
        self.coords.extend_from_slice(&other.coords);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `JoeKuoD6::standard()` must be the first 1000 dimensions of
    /// `new-joe-kuo-6.21201`, the table SPEC §2 names.
    #[test]
    fn standard_table_is_a_prefix_of_21201() {
        let standard = JoeKuoD6::standard();
        let extended = JoeKuoD6::extended();
        assert_eq!(standard.max_dims, MAX_DIMENSIONS);
        assert_eq!(extended.max_dims, 21201);
        for (a, b) in standard.dim_params.iter().zip(&extended.dim_params) {
            assert_eq!((a.d, a.a, &a.m), (b.d, b.a, &b.m));
        }
    }
}
