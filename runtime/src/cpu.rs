//! Whether the processor running this program has AVX2 and FMA, asked once, for builds that do
//! not target them (the default `x86-64` target): the joint sines and cosines then take their
//! fused form anyway ([`crate::trig`]), as they would in a `-C target-cpu=native` build.
//! `no_std`, so CPUID directly rather than `std::is_x86_feature_detected!`.

use core::sync::atomic::{AtomicU8, Ordering};

const UNKNOWN: u8 = 0;
const ABSENT: u8 = 1;
const PRESENT: u8 = 2;

static AVX2_FMA: AtomicU8 = AtomicU8::new(UNKNOWN);
// Read by the dispatch of optimised builds and by tests, not by other debug builds.
#[cfg_attr(all(debug_assertions, not(test)), allow(dead_code))]
static AVX512: AtomicU8 = AtomicU8::new(UNKNOWN);
// Read by the dispatch of optimised builds only.
#[cfg_attr(debug_assertions, allow(dead_code))]
static INTEL: AtomicU8 = AtomicU8::new(UNKNOWN);

/// AVX2 and FMA both present, and the operating system saves the AVX registers.
#[inline]
pub(crate) fn has_avx2_fma() -> bool {
    cached(&AVX2_FMA, detect)
}

/// [`has_avx2_fma`], AVX-512 F, DQ, BW and VL too, and the operating system saves the AVX-512
/// registers.
#[cfg_attr(all(debug_assertions, not(test)), allow(dead_code))]
#[inline]
pub(crate) fn has_avx512() -> bool {
    cached(&AVX512, || has_avx2_fma() && detect_avx512())
}

/// An Intel processor (CPUID vendor `GenuineIntel`): where 512-bit instructions slow the other
/// vector instructions around them (`dispatch::dispatch_many`).
#[cfg_attr(debug_assertions, allow(dead_code))]
#[inline]
pub(crate) fn is_intel() -> bool {
    cached(&INTEL, || {
        use core::arch::x86_64::__cpuid;
        // SAFETY: CPUID exists on every x86-64 processor; leaf 0 on every one.
        #[allow(unused_unsafe)]
        let leaf0 = unsafe { __cpuid(0) };
        // "GenuineIntel" in EBX, EDX, ECX.
        leaf0.ebx == u32::from_le_bytes(*b"Genu")
            && leaf0.edx == u32::from_le_bytes(*b"ineI")
            && leaf0.ecx == u32::from_le_bytes(*b"ntel")
    })
}

#[inline(always)]
fn cached(state: &AtomicU8, detect: impl FnOnce() -> bool) -> bool {
    match state.load(Ordering::Relaxed) {
        UNKNOWN => {
            let present = detect();
            state.store(if present { PRESENT } else { ABSENT }, Ordering::Relaxed);
            present
        }
        state => state == PRESENT,
    }
}

/// Asked only once AVX is known to be enabled (so XGETBV is).
#[cfg_attr(all(debug_assertions, not(test)), allow(dead_code))]
#[cold]
fn detect_avx512() -> bool {
    use core::arch::x86_64::{__cpuid_count, _xgetbv};
    // SAFETY: CPUID leaf 7 exists (`detect` read it); XGETBV is enabled (OSXSAVE, in `detect`).
    #[allow(unused_unsafe)]
    let ebx = unsafe { __cpuid_count(7, 0) }.ebx;
    // F (bit 16), DQ (17), BW (30), VL (31): what every AVX-512 processor since Skylake-SP has,
    // and what the lane kernels are compiled for.
    let subsets = 1 << 16 | 1 << 17 | 1 << 30 | 1 << 31;
    let avx512 = ebx & subsets == subsets;
    // XCR0 bits 5–7: the opmask registers and both halves of the 512-bit state are saved.
    #[allow(unused_unsafe)]
    let xcr0 = unsafe { _xgetbv(0) };
    avx512 && xcr0 & 0b1110_0000 == 0b1110_0000
}

#[cold]
fn detect() -> bool {
    use core::arch::x86_64::{__cpuid, __cpuid_count, _xgetbv};
    // SAFETY (all three blocks): CPUID exists on every x86-64 processor; XGETBV is executed
    // only once CPUID has reported OSXSAVE, which is when the instruction is enabled.
    #[allow(unused_unsafe)]
    let leaf1 = unsafe { __cpuid(1) };
    let fma = leaf1.ecx & (1 << 12) != 0;
    let osxsave = leaf1.ecx & (1 << 27) != 0;
    let avx = leaf1.ecx & (1 << 28) != 0;
    if !(fma && osxsave && avx) {
        return false;
    }
    // XCR0 bits 1 and 2: the OS saves the SSE and AVX register state on a context switch.
    #[allow(unused_unsafe)]
    let xcr0 = unsafe { _xgetbv(0) };
    if xcr0 & 0b110 != 0b110 {
        return false;
    }
    #[allow(unused_unsafe)]
    let max_leaf = unsafe { __cpuid(0) }.eax;
    #[allow(unused_unsafe)]
    let avx2 = max_leaf >= 7 && unsafe { __cpuid_count(7, 0) }.ebx & (1 << 5) != 0;
    avx2
}
