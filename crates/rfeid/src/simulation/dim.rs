//! The number of coordinates n, known at compile time or at run time.
//!
//! The kernels read n through [`Dim::n`]. Compiled with [`Fixed`], n is a
//! constant: the short loops over coordinates unroll, the state fits in
//! registers and the bounds checks fold away. [`Dynamic`] serves every other
//! size with the same code, so both give the same operations in the same
//! order and therefore the same results.

/// Where n comes from.
pub(crate) trait Dim: Copy {
    /// Whether the element-by-element kernels are compiled in. They serve
    /// large models, so only [`Dynamic`] has them; the dispatch (`run`)
    /// sends every system on them there. A trade: with n fixed they took 7 %
    /// fewer instructions on a 4-body model that runs element by element,
    /// for a fifth more of the library's build time.
    const SPARSE: bool;

    /// n, given the run-time value (which a fixed size must equal).
    fn n(runtime: usize) -> usize;

    /// How many leading coordinates the kernels integrate, given the
    /// system's reach (`System::active`, ≤ n): all n with [`Fixed`], whose
    /// loops then keep their constant bounds, the reach with [`Reach`] and
    /// [`Dynamic`].
    fn reach(active: usize, n: usize) -> usize;
}

/// n known at compile time.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Fixed<const N: usize>;

/// n known at compile time, of which only the leading `System::active`
/// coordinates move: one body restrained and driven along x alone (the
/// Silverbox) integrates 2 of its 12 states. A separate kernel, so that
/// [`Fixed`] keeps its constant loop bounds.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Reach<const N: usize>;

/// n known at run time only.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Dynamic;

impl<const N: usize> Dim for Fixed<N> {
    const SPARSE: bool = false;

    #[inline(always)]
    fn n(runtime: usize) -> usize {
        debug_assert_eq!(runtime, N);
        N
    }

    #[inline(always)]
    fn reach(_: usize, _: usize) -> usize {
        N
    }
}

impl<const N: usize> Dim for Reach<N> {
    const SPARSE: bool = false;

    #[inline(always)]
    fn n(runtime: usize) -> usize {
        debug_assert_eq!(runtime, N);
        N
    }

    #[inline(always)]
    fn reach(active: usize, _: usize) -> usize {
        active.min(N)
    }
}

impl Dim for Dynamic {
    const SPARSE: bool = true;

    #[inline(always)]
    fn n(runtime: usize) -> usize {
        runtime
    }

    #[inline(always)]
    fn reach(active: usize, n: usize) -> usize {
        active.min(n)
    }
}
