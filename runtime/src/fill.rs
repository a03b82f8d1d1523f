//! The zero that mid-sized results start from.

/// `0.0`, hidden from the optimiser, for generated functions to fill a mid-sized result with
/// before they write its entries in place.
///
/// From a constant zero the compiler fills the result with one `memset`, and above a few hundred
/// bytes that is a call into the C library: mid-kernel, so every vector register live across
/// it is spilled and reloaded, and glibc serves sizes from 2 KiB with `rep stosb`, which is slow
/// to start on AMD Zen. Filled from this zero, which is no byte pattern to the compiler, the
/// fill stays a run of vector stores inside the kernel (`docs/performance-notes.md`). Only up to
/// about 5 KiB, though: a longer fill the compiler does not unroll, and it then fills a temporary
/// and copies it into the result, so generated results over 4 KiB start from a constant zero
/// again (one `memset` straight into the result, one pass over the memory instead of three).
/// Only speed depends on it: a build that sees through [`core::hint::black_box`] fills with the
/// same zeros.
#[inline(always)]
pub fn fill_zero() -> f64 {
    core::hint::black_box(0.0)
}

#[cfg(test)]
mod tests {
    /// The fill is positive zero, bit for bit, as `SMatrix::zeros()` was: a structural zero of a
    /// regressor prints as `0`, and `1/x` of it is `+∞`.
    #[test]
    fn fill_zero_is_positive_zero() {
        assert_eq!(super::fill_zero().to_bits(), 0.0_f64.to_bits());
    }
}
