//! `a·b + c`, fused or not by the build's target alone: for hand-written code beside the
//! generated functions (the controller's products). Generated scalar functions choose at run
//! time instead ([`dispatch`](crate::dispatch::dispatch)).
//!
//! Where the whole build targets FMA (`-C target-cpu=native` on any x86-64 of the last decade,
//! or `-C target-feature=+fma`), one fused instruction: one rounding instead of two, and one
//! instruction instead of two, which is most of what a C compiler's floating-point contraction
//! gives CppADCodeGen's generated code. Rust never contracts `a * b + c` on its own. Elsewhere,
//! `a * b + c` exactly as written (never the slow software `fma`).
//!
//! SIMD lanes do the same ([`Lanes::mul_add`](crate::Lanes::mul_add), FMA under the same
//! condition).

/// `a·b + c`: fused where the build targets FMA, else `a * b + c`.
#[inline(always)]
pub fn mul_add(a: f64, b: f64, c: f64) -> f64 {
    #[cfg(all(target_arch = "x86_64", target_feature = "fma"))]
    {
        // SAFETY: the `fma` target feature is enabled for the whole build (the `cfg` above).
        #[allow(unused_unsafe)]
        unsafe {
            fused_instruction(a, b, c)
        }
    }
    #[cfg(not(all(target_arch = "x86_64", target_feature = "fma")))]
    {
        a * b + c
    }
}

/// `a·b + c` as one `vfmadd` in code compiled with FMA enabled.
///
/// Written with one intrinsic and bit casts rather than `_mm_set_sd`/`_mm_cvtsd_f64`: those are
/// functions too, and a generated function inlines this thousands of times: with them, the
/// generated modules took several times as long to compile, for the same machine code.
///
/// # Safety
/// The processor must have FMA.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
pub(crate) unsafe fn fused_instruction(a: f64, b: f64, c: f64) -> f64 {
    use core::arch::x86_64::{__m128d, _mm_fmadd_sd};
    use core::mem::transmute;
    // SAFETY: `[f64; 2]` and `__m128d` are both 16 bytes of two `f64`s; the caller promises FMA.
    unsafe {
        let low = |x: f64| transmute::<[f64; 2], __m128d>([x, 0.0]);
        transmute::<__m128d, [f64; 2]>(_mm_fmadd_sd(low(a), low(b), low(c)))[0]
    }
}

#[cfg(test)]
mod tests {
    use super::mul_add;

    #[test]
    fn is_a_times_b_plus_c() {
        assert_eq!(mul_add(2.0, 3.0, 4.0), 10.0);
        assert_eq!(mul_add(-2.0, 3.0, 4.0), -2.0);
        assert_eq!(mul_add(0.5, 0.25, -0.125), 0.0);
    }

    #[test]
    fn rounds_once_exactly_when_the_target_has_fma() {
        // (1 + 2⁻³⁰)² − (1 + 2⁻²⁹) = 2⁻⁶⁰: lost when the product is rounded first.
        let x = 1.0 + f64::powi(2.0, -30);
        let fused = mul_add(x, x, -(1.0 + f64::powi(2.0, -29)));
        let expected = if cfg!(all(target_arch = "x86_64", target_feature = "fma")) {
            f64::powi(2.0, -60)
        } else {
            0.0
        };
        assert_eq!(fused, expected);
    }
}
