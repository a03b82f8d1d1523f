//! Stack frames aligned for vector spills (call stack frames, unrelated to a robot's named frames
//! in `frames.rs`).

/// Makes the function this is inlined into keep its stack frame aligned to 64 bytes, so that
/// the vector registers it spills are stored whole in one cache line each.
///
/// A function that holds more 256- or 512-bit vectors than there are registers (the derivatives
/// of the dynamics, several states per call) spills the rest to its stack. The register
/// allocator can align those slots only if the function realigns its frame, and that is decided
/// before allocation: without a local of its own that needs the alignment, a spill slot lies
/// wherever the caller's stack pointer puts it (16-byte alignment is all the ABI promises), most
/// 64-byte spills and reloads straddle two cache lines, and how many depends on the process,
/// since the initial stack pointer moves with the environment and address randomisation. One
/// 64-byte-aligned local whose address escapes makes the function realign its frame; the cost
/// is the realignment and one byte stored.
///
/// Generated lane functions call it first; [`dispatch_eight`](crate::dispatch::dispatch_eight)
/// calls it in the function that runs the kernel, and a default build's joint sines and cosines
/// in theirs. Scalar kernels ([`dispatch`](crate::dispatch::dispatch)) spill few vectors and do
/// without it.
#[inline(always)]
pub fn align_stack_frame() {
    #[repr(align(64))]
    struct CacheLine([u8; 1]);
    // A `let` binding: the reference of a constant expression (`&CacheLine(..)`) would be
    // promoted to a static, and the frame left as it is.
    let mut line = CacheLine([0]);
    core::hint::black_box(&mut line.0);
}
