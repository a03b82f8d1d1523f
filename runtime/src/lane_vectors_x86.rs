//! [`EightLanes`] in AVX2 (two 256-bit registers) and AVX-512 (one 512-bit register), and
//! [`FourLanes`] in one 256-bit register, for builds that choose the processor's features at run
//! time. Only [`dispatch_eight`] creates a value of
//! either type (through the multiply-add strategies [`Fused`] and [`Fused512`], which it creates
//! after checking the processor), and no other way to make one exists: so every operation below
//! runs on a processor that has its instructions. Each operation is one intrinsic per register,
//! inlined into the kernel that `dispatch_eight` compiles with those features.
//!
//! [`dispatch_eight`]: crate::dispatch::dispatch_eight
//! [`Fused`]: crate::dispatch::Fused
//! [`Fused512`]: crate::dispatch::Fused512

use crate::dispatch::{Fused, Fused512};
use crate::lane_kernels::LaneVector;
use crate::lane_vectors::{EightLanes, FourLanes};
use core::arch::x86_64::*;
use core::mem::transmute;
use core::ops::{Add, Div, Mul, Neg, Sub};

/// Eight lanes as two AVX registers.
#[derive(Clone, Copy, Debug)]
pub struct Avx2Eight([__m256d; 2]);

/// Eight lanes as one AVX-512 register.
#[derive(Clone, Copy, Debug)]
pub struct Avx512Eight(__m512d);

/// Four lanes as one AVX register.
#[derive(Clone, Copy, Debug)]
pub struct Avx2Four(__m256d);

impl Avx2Eight {
    /// # Safety
    /// The processor must have AVX2 and FMA.
    #[inline(always)]
    pub(crate) unsafe fn new(lanes: [f64; 8]) -> Self {
        // SAFETY: `[f64; 8]` and `[__m256d; 2]` are both 64 bytes of eight `f64`s.
        Avx2Eight(unsafe { transmute::<[f64; 8], [__m256d; 2]>(lanes) })
    }
}

impl Avx2Four {
    /// # Safety
    /// The processor must have AVX2 and FMA.
    #[inline(always)]
    pub(crate) unsafe fn new(lanes: [f64; 4]) -> Self {
        // SAFETY: `[f64; 4]` and `__m256d` are both 32 bytes of four `f64`s.
        Avx2Four(unsafe { transmute::<[f64; 4], __m256d>(lanes) })
    }
}

impl Avx512Eight {
    /// # Safety
    /// The processor must have AVX-512F.
    #[inline(always)]
    pub(crate) unsafe fn new(lanes: [f64; 8]) -> Self {
        // SAFETY: `[f64; 8]` and `__m512d` are both 64 bytes of eight `f64`s.
        Avx512Eight(unsafe { transmute::<[f64; 8], __m512d>(lanes) })
    }
}

/// The operators and multiply-adds of `$t`, each one intrinsic per register written out in place
/// (no closure or helper between them and the intrinsic: a kernel inlines thousands of these, and
/// every extra layer of functions costs compile time). `$on` spells the call on every register.
/// SAFETY of every `unsafe` block: a value of the type exists only where the processor has its
/// instructions (see the module).
macro_rules! lane_vector {
    ($t:ident: $trait:ident, $width:literal, $on:ident, $neg:expr,
     add $add:ident, sub $sub:ident, mul $mul:ident, div $div:ident,
     fmadd $fmadd:ident, fmsub $fmsub:ident, fnmadd $fnmadd:ident, fnmsub $fnmsub:ident) => {
        binary_operator!($t, $on, Add, add, $add);
        binary_operator!($t, $on, Sub, sub, $sub);
        binary_operator!($t, $on, Mul, mul, $mul);
        binary_operator!($t, $on, Div, div, $div);
        impl Neg for $t {
            type Output = Self;
            #[inline(always)]
            fn neg(self) -> Self {
                // The sign bit flipped, as `wide` negates (−0 for +0).
                unsafe { $neg(self) }
            }
        }
        impl $trait for $t {
            multiply_add!($t, $on, mul_add, $fmadd);
            multiply_add!($t, $on, mul_sub, $fmsub);
            multiply_add!($t, $on, mul_neg_add, $fnmadd);
            multiply_add!($t, $on, mul_neg_sub, $fnmsub);
            #[inline(always)]
            fn to_array(self) -> [f64; $width] {
                // SAFETY: both are `$width` `f64`s.
                unsafe { transmute::<$t, [f64; $width]>(self) }
            }
        }
    };
}

/// `impl $op for $t` by the intrinsic `$f` on every register (SAFETY as in `lane_vector!`).
macro_rules! binary_operator {
    ($t:ident, $on:ident, $op:ident, $method:ident, $f:ident) => {
        impl $op for $t {
            type Output = Self;
            #[inline(always)]
            fn $method(self, b: Self) -> Self {
                unsafe { $on!($t, $f, self, b) }
            }
        }
    };
}

/// A multiply-add method of a lane vector by the intrinsic `$f` on every register (SAFETY as in
/// `lane_vector!`).
macro_rules! multiply_add {
    ($t:ident, $on:ident, $method:ident, $f:ident) => {
        #[inline(always)]
        fn $method(self, m: Self, c: Self) -> Self {
            unsafe { $on!($t, $f, self, m, c) }
        }
    };
}

/// `f` on both registers of two-register values.
macro_rules! on_two {
    ($t:ident, $f:ident, $a:expr, $($x:expr),+) => {
        $t([$f($a.0[0], $($x.0[0]),+), $f($a.0[1], $($x.0[1]),+)])
    };
}

/// `f` on the register of one-register values.
macro_rules! on_one {
    ($t:ident, $f:ident, $a:expr, $($x:expr),+) => {
        $t($f($a.0, $($x.0),+))
    };
}

lane_vector!(Avx2Eight: EightLanes, 8, on_two, neg_two,
    add _mm256_add_pd, sub _mm256_sub_pd, mul _mm256_mul_pd, div _mm256_div_pd,
    fmadd _mm256_fmadd_pd, fmsub _mm256_fmsub_pd, fnmadd _mm256_fnmadd_pd, fnmsub _mm256_fnmsub_pd);
lane_vector!(Avx512Eight: EightLanes, 8, on_one, neg_one,
    add _mm512_add_pd, sub _mm512_sub_pd, mul _mm512_mul_pd, div _mm512_div_pd,
    fmadd _mm512_fmadd_pd, fmsub _mm512_fmsub_pd, fnmadd _mm512_fnmadd_pd, fnmsub _mm512_fnmsub_pd);
lane_vector!(Avx2Four: FourLanes, 4, on_one, neg_four,
    add _mm256_add_pd, sub _mm256_sub_pd, mul _mm256_mul_pd, div _mm256_div_pd,
    fmadd _mm256_fmadd_pd, fmsub _mm256_fmsub_pd, fnmadd _mm256_fnmadd_pd, fnmsub _mm256_fnmsub_pd);

/// # Safety
/// The processor must have AVX.
#[inline(always)]
unsafe fn neg_two(a: Avx2Eight) -> Avx2Eight {
    // SAFETY: the caller's promise.
    unsafe {
        let sign = _mm256_set1_pd(-0.0);
        Avx2Eight([_mm256_xor_pd(a.0[0], sign), _mm256_xor_pd(a.0[1], sign)])
    }
}

/// # Safety
/// The processor must have AVX.
#[inline(always)]
unsafe fn neg_four(a: Avx2Four) -> Avx2Four {
    // SAFETY: the caller's promise.
    unsafe { Avx2Four(_mm256_xor_pd(a.0, _mm256_set1_pd(-0.0))) }
}

/// The sign-bit flip on 512 bits, on the integer view (a floating-point `xor` is AVX-512DQ).
///
/// # Safety
/// The processor must have AVX-512F.
#[inline(always)]
unsafe fn neg_one(a: Avx512Eight) -> Avx512Eight {
    // SAFETY: the caller's promise; the casts only reinterpret the bits.
    unsafe {
        let bits = _mm512_xor_si512(_mm512_castpd_si512(a.0), _mm512_set1_epi64(i64::MIN));
        Avx512Eight(_mm512_castsi512_pd(bits))
    }
}

/// `$t` as the vector a `*_lanes` kernel computes in under the strategy `$m`, which
/// [`dispatch_eight`] creates only where the processor has `$t`'s instructions: so making one
/// through a value of `$m` is sound, and no other way to make one exists.
macro_rules! compute_vector {
    ($t:ident: $trait:ident under $m:ty) => {
        impl LaneVector<$m> for $t {
            #[inline(always)]
            fn splat_in(arith: $m, x: f64) -> Self {
                Self::from_fn_in(arith, |_| x)
            }
            #[inline(always)]
            fn from_fn_in(_: $m, f: impl FnMut(usize) -> f64) -> Self {
                // SAFETY: a value of `$m` exists only where the processor has the instructions
                // of `$t` (see the macro).
                unsafe { $t::new(core::array::from_fn(f)) }
            }
            #[inline(always)]
            fn lane(&self, k: usize) -> f64 {
                $trait::to_array(*self)[k]
            }
            #[inline(always)]
            fn mul_add(self, b: Self, c: Self) -> Self {
                $trait::mul_add(self, b, c)
            }
        }
    };
}

compute_vector!(Avx2Four: FourLanes under Fused);
compute_vector!(Avx2Eight: EightLanes under Fused);
compute_vector!(Avx2Four: FourLanes under Fused512);
compute_vector!(Avx512Eight: EightLanes under Fused512);

#[cfg(test)]
mod tests {
    use super::{Avx2Eight, Avx2Four, Avx512Eight};
    use crate::lane_vectors::{EightLanes, FourLanes};

    /// A test function `$name` for lane vectors of `$trait` (`$width` lanes).
    macro_rules! lane_by_lane {
        ($name:ident, $trait:ident, $width:literal) => {
            /// Every operation of `T` against the same one lane by lane: exact for `+ − · / −x`, one
            /// rounding (`f64::mul_add`) for the multiply-adds, bit for bit (signed zeros, infinities and
            /// NaN included).
            fn $name<T: $trait>(new: impl Fn([f64; $width]) -> T) {
                let mut rng = crate::SplitMix64::new(5);
                let special = [
                    0.0,
                    -0.0,
                    1.0,
                    -1.5,
                    f64::INFINITY,
                    f64::NEG_INFINITY,
                    f64::NAN,
                    1e-310,
                ];
                for round in 0..500 {
                    let draw = |rng: &mut crate::SplitMix64| -> [f64; $width] {
                        core::array::from_fn(|k| match (round + k) % 4 {
                            0 => special[(round * 3 + k) % special.len()],
                            _ => rng.uniform((-1e3, 1e3)),
                        })
                    };
                    let (a, b, c) = (draw(&mut rng), draw(&mut rng), draw(&mut rng));
                    let (x, y, z) = (new(a), new(b), new(c));
                    let lanes = |f: fn(f64, f64, f64) -> f64| -> [f64; $width] {
                        core::array::from_fn(|k| f(a[k], b[k], c[k]))
                    };
                    let cases: [(&str, [f64; $width], [f64; $width]); 9] = [
                        ("add", (x + y).to_array(), lanes(|a, b, _| a + b)),
                        ("sub", (x - y).to_array(), lanes(|a, b, _| a - b)),
                        ("mul", (x * y).to_array(), lanes(|a, b, _| a * b)),
                        ("div", (x / y).to_array(), lanes(|a, b, _| a / b)),
                        ("neg", (-x).to_array(), lanes(|a, _, _| -a)),
                        (
                            "mul_add",
                            x.mul_add(y, z).to_array(),
                            lanes(|a, b, c| a.mul_add(b, c)),
                        ),
                        (
                            "mul_sub",
                            x.mul_sub(y, z).to_array(),
                            lanes(|a, b, c| a.mul_add(b, -c)),
                        ),
                        (
                            "mul_neg_add",
                            x.mul_neg_add(y, z).to_array(),
                            lanes(|a, b, c| (-a).mul_add(b, c)),
                        ),
                        (
                            "mul_neg_sub",
                            x.mul_neg_sub(y, z).to_array(),
                            lanes(|a, b, c| (-a).mul_add(b, -c)),
                        ),
                    ];
                    for (name, got, want) in cases {
                        for k in 0..$width {
                            let same =
                                got[k].to_bits() == want[k].to_bits() || got[k].is_nan() && want[k].is_nan();
                            assert!(
                                same,
                                "{name} lane {k}: {} vs {} ({}, {}, {})",
                                got[k], want[k], a[k], b[k], c[k]
                            );
                        }
                    }
                }
            }
        };
    }

    lane_by_lane!(matches_lane_by_lane, EightLanes, 8);
    lane_by_lane!(four_match_lane_by_lane, FourLanes, 4);

    #[test]
    fn two_avx_registers_compute_lane_by_lane() {
        if crate::cpu::has_avx2_fma() {
            // SAFETY: the processor has AVX2 and FMA (just checked).
            matches_lane_by_lane(|lanes| unsafe { Avx2Eight::new(lanes) });
        }
    }

    #[test]
    fn one_avx512_register_computes_lane_by_lane() {
        if crate::cpu::has_avx512() {
            // SAFETY: the processor has AVX-512F (just checked).
            matches_lane_by_lane(|lanes| unsafe { Avx512Eight::new(lanes) });
        }
    }

    #[test]
    fn one_avx_register_computes_four_lanes_lane_by_lane() {
        if crate::cpu::has_avx2_fma() {
            // SAFETY: the processor has AVX2 and FMA (just checked).
            four_match_lane_by_lane(|lanes| unsafe { Avx2Four::new(lanes) });
        }
    }
}
