//! The joint sines and cosines of [`crate::trig`] written with AVX2 and FMA intrinsics, for
//! builds that do not target those features but run on a processor that has them
//! ([`crate::cpu::has_avx2_fma`]). The same steps and constants as the lane form, so the same
//! values where that form is fused (a `-C target-cpu=native` build).

use crate::trig::{COS, P1, P2, P3, ROUND, SIN, TWO_OVER_PI};
use core::arch::x86_64::*;

/// [`crate::trig::sin_cos_all`] with every step compiled for AVX2 and FMA.
///
/// # Safety
/// The processor must have AVX, AVX2 and FMA.
#[target_feature(enable = "avx,avx2,fma")]
pub(crate) unsafe fn sin_cos_all<const N: usize>(q: &[f64; N]) -> ([f64; N], [f64; N]) {
    crate::trig::sin_cos_all_with(q, |x| {
        let mut sin = [0.0; 8];
        let mut cos = [0.0; 8];
        for half in 0..2 {
            // SAFETY: the enclosing function's features; reads and writes stay in the arrays.
            unsafe {
                let (s, c) = sin_cos_4(_mm256_loadu_pd(x[4 * half..].as_ptr()));
                _mm256_storeu_pd(sin[4 * half..].as_mut_ptr(), s);
                _mm256_storeu_pd(cos[4 * half..].as_mut_ptr(), c);
            }
        }
        (sin, cos)
    })
}

/// The kernel on four angles (one lane vector of `JointTrigLanes`), compiled for AVX2 and FMA.
///
/// # Safety
/// The processor must have AVX, AVX2 and FMA.
#[target_feature(enable = "avx,avx2,fma")]
pub(crate) unsafe fn sin_cos_four(q: &[f64; 4]) -> ([f64; 4], [f64; 4]) {
    let (mut sin, mut cos) = ([0.0; 4], [0.0; 4]);
    // SAFETY: the enclosing function's features; reads and writes stay in the arrays.
    unsafe {
        let (s, c) = sin_cos_4(_mm256_loadu_pd(q.as_ptr()));
        _mm256_storeu_pd(sin.as_mut_ptr(), s);
        _mm256_storeu_pd(cos.as_mut_ptr(), c);
    }
    (sin, cos)
}

#[target_feature(enable = "avx,avx2,fma")]
#[inline]
unsafe fn sin_cos_4(q: __m256d) -> (__m256d, __m256d) {
    let splat = |x: f64| _mm256_set1_pd(x);
    let neg = |x: __m256d| _mm256_xor_pd(x, _mm256_set1_pd(-0.0));
    let round = splat(ROUND);
    let k = _mm256_sub_pd(_mm256_fmadd_pd(q, splat(TWO_OVER_PI), round), round);
    let minus_k = neg(k);
    let r = _mm256_fmadd_pd(
        minus_k,
        splat(P3),
        _mm256_fmadd_pd(minus_k, splat(P2), _mm256_fmadd_pd(minus_k, splat(P1), q)),
    );
    let z = _mm256_mul_pd(r, r);
    let minus_z = neg(z);
    let z2 = _mm256_mul_pd(z, z);
    let z4 = _mm256_mul_pd(z2, z2);
    let polynomial = |c: &[f64; 8]| {
        let term = |i: usize| _mm256_fmadd_pd(minus_z, splat(c[i + 1]), splat(c[i]));
        let low = _mm256_fmadd_pd(z2, term(2), term(0));
        let high = _mm256_fmadd_pd(z2, term(6), term(4));
        _mm256_fmadd_pd(z4, high, low)
    };
    let ps = polynomial(&SIN);
    let pc = polynomial(&COS);
    let sin_r = _mm256_fmadd_pd(neg(_mm256_mul_pd(r, z)), ps, r);
    let r_is_zero = _mm256_cmp_pd::<_CMP_EQ_OQ>(r, splat(0.0));
    let sin_r = _mm256_blendv_pd(sin_r, r, r_is_zero);
    let cos_r = _mm256_fmadd_pd(minus_z, pc, splat(1.0));
    let quarter = _mm256_sub_pd(
        _mm256_add_pd(_mm256_fmadd_pd(k, splat(0.25), splat(-0.375)), round),
        round,
    );
    let j = _mm256_fmadd_pd(quarter, splat(-4.0), k);
    let is = |v: f64| _mm256_cmp_pd::<_CMP_EQ_OQ>(j, splat(v));
    let odd = _mm256_or_pd(is(1.0), is(3.0));
    let sin = _mm256_blendv_pd(sin_r, cos_r, odd);
    let cos = _mm256_blendv_pd(cos_r, sin_r, odd);
    let sin = _mm256_blendv_pd(sin, neg(sin), _mm256_cmp_pd::<_CMP_GE_OQ>(j, splat(2.0)));
    let cos = _mm256_blendv_pd(cos, neg(cos), _mm256_or_pd(is(1.0), is(2.0)));
    (sin, cos)
}
