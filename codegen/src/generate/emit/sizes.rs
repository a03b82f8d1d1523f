//! The sizes the emitter's choices turn on. The module's assembler (`mod.rs`) chooses them and
//! passes them down; the layers below take them as a parameter and hold none of their own.

/// Where the emitter splits a function, which dispatch a kernel takes, and how a result is
/// zeroed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Sizes {
    /// Values per chunk function: a function that computes more is emitted in chunks
    /// (`<name>_partK`).
    pub chunk_values: usize,
    /// A scalar kernel that computes more values than this runs through
    /// `dyngen_runtime::__private::dispatch_many` (a lane kernel through `dispatch_eight`
    /// whatever its size).
    pub many_values: usize,
    /// A result written in place of more bytes than this, up to
    /// [`Sizes::unrolled_fill_bytes`], starts from `dyngen_runtime::__private::fill_zero()`
    /// rather than a constant zero.
    pub library_fill_bytes: usize,
    /// A result of more bytes than this starts from a constant zero again.
    pub unrolled_fill_bytes: usize,
}
