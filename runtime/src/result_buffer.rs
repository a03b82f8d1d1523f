//! A large result kept between calls, so that a generated function writes only the entries
//! that can be nonzero.

use core::ops::Deref;
use nalgebra::SMatrix;

/// A result kept between calls of a generated function's `_into` form
/// (`torque_regressor_into(&t, &qd, &qdd, &mut y)`), as a control loop or an identification
/// keeps its workspace: no fill and no copy per call.
///
/// Most entries of a regressor, and many of `C`, `D⁻¹` and the derivatives, are zero for every
/// state (a body's columns reach only the rows of the joints that carry it). Returned by value,
/// a result is zeroed and then written on every call: a `memset` of 18.7 KB for a quadruped's
/// regressor, a fifth of its time, and for functions generated in chunks a copy of the whole
/// result as well. A `ResultBuffer` remembers which function's pattern of structural zeros it
/// holds, so a call of the same pattern writes only the other entries; a buffer last written by
/// a function of another pattern (another function, another robot, or a by-value result) is
/// zeroed once first. (A hand-written implementation of a robot trait computes the result by
/// value and stores it: the traits' default.) Reading a buffer is reading `T` (it dereferences
/// to it); writing it is only for the generated functions, which is what keeps its zeros true.
#[derive(Clone, Debug)]
pub struct ResultBuffer<T> {
    value: T,
    /// The structural-zero pattern `value` holds: [`ZEROED`], [`UNKNOWN`], or a generated
    /// function's pattern id.
    pattern: u64,
}

/// All entries zero: every pattern holds.
const ZEROED: u64 = 0;
/// Written whole by value: no pattern can be assumed.
const UNKNOWN: u64 = u64::MAX;

/// What a [`ResultBuffer`] holds: a matrix of `f64` or a pair of them (the derivatives).
pub trait BufferedResult: Sized {
    /// The result with every entry zero.
    fn zero() -> Self;
}

impl<const R: usize, const C: usize> BufferedResult for SMatrix<f64, R, C> {
    fn zero() -> Self {
        SMatrix::zeros()
    }
}

impl<A: BufferedResult, B: BufferedResult> BufferedResult for (A, B) {
    fn zero() -> Self {
        (A::zero(), B::zero())
    }
}

impl<T: BufferedResult> ResultBuffer<T> {
    /// A buffer of zeros.
    pub fn new() -> Self {
        ResultBuffer {
            value: T::zero(),
            pattern: ZEROED,
        }
    }

    /// The result of the last call, owned.
    pub fn into_inner(self) -> T {
        self.value
    }

    /// Stores a whole result computed by value (what a robot whose code has no `_into` form of
    /// a function does).
    pub(crate) fn replace(&mut self, value: T) {
        self.value = value;
        self.pattern = UNKNOWN;
    }

    /// The result, for a generated function of structural-zero pattern `pattern` to write its
    /// other entries into: zeroed first unless the buffer holds zeros there already.
    #[inline]
    pub(crate) fn claim(&mut self, pattern: u64) -> &mut T {
        debug_assert!(pattern != ZEROED && pattern != UNKNOWN, "reserved pattern id");
        if self.pattern != pattern && self.pattern != ZEROED {
            self.value = T::zero();
        }
        self.pattern = pattern;
        &mut self.value
    }
}

impl<T: BufferedResult> Default for ResultBuffer<T> {
    fn default() -> Self {
        Self::new()
    }
}

impl<T> Deref for ResultBuffer<T> {
    type Target = T;

    fn deref(&self) -> &T {
        &self.value
    }
}

impl<T> AsRef<T> for ResultBuffer<T> {
    fn as_ref(&self) -> &T {
        &self.value
    }
}

/// What a generated `_into` function starts with: the buffer's result, zeroed unless it already
/// holds `pattern`'s structural zeros. Generated code only (a pattern id is a hash of the
/// entries the function never writes); called with another id it would read stale entries.
#[inline]
pub fn claim<T: BufferedResult>(buffer: &mut ResultBuffer<T>, pattern: u64) -> &mut T {
    buffer.claim(pattern)
}

#[cfg(test)]
mod tests {
    use super::{ResultBuffer, UNKNOWN, ZEROED};
    use nalgebra::SMatrix;

    type M = SMatrix<f64, 2, 2>;

    /// A buffer written by a function of one pattern is zeroed before a function of another
    /// writes it, and kept as it is for the same one.
    #[test]
    fn a_new_pattern_starts_from_zeros() {
        let mut b: ResultBuffer<M> = ResultBuffer::new();
        b.claim(7)[(0, 1)] = 3.0;
        // Same pattern: the stale entry stays (that function would never write it nonzero).
        assert_eq!(b.claim(7)[(0, 1)], 3.0);
        assert_eq!(b.claim(8)[(0, 1)], 0.0);
        b.claim(8)[(1, 0)] = 2.0;
        b.replace(M::repeat(5.0));
        assert_eq!(b.pattern, UNKNOWN);
        assert_eq!(*b.claim(8), M::zeros());
    }

    /// A fresh buffer is zero, which every pattern accepts without a fill.
    #[test]
    fn a_fresh_buffer_is_zero_and_takes_any_pattern() {
        let mut b: ResultBuffer<(M, M)> = ResultBuffer::default();
        assert_eq!(b.pattern, ZEROED);
        b.claim(9).1[(1, 1)] = 4.0;
        assert_eq!(b.1[(1, 1)], 4.0);
        assert_eq!(b.clone().into_inner().0, M::zeros());
    }
}
