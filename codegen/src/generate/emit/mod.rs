//! Rust source from a traced robot: one flat, single-assignment function per quantity.
//!
//! The files form a one-way chain of layers; each uses only files listed before it (a test
//! holds them to it):
//!
//! 1. `sizes` (the sizes the emitter's choices turn on), `constants` (literals and the module's
//!    constant items), `lane_width` (how wide a function's lane vectors are), `leaves` (how
//!    inputs are spelled), `file` (what every generated file has: header, provenance,
//!    formatting): they use no other file;
//! 2. `plan`: what a function computes, in what order, with which multiply-adds;
//! 3. `signature` (its parameters and the inputs' destructuring) and `outputs` (its result:
//!    type, zero, value, the slots of a result written in place);
//! 4. `kernel` (its body as a kernel, and the dispatch that runs it), `vector_stores` (outputs
//!    written a vector at a time) and `header` (what a function is called, returns and says);
//! 5. `into_form`: its form writing into a kept `ResultBuffer`;
//! 6. `body` (a function in one piece) and `chunks` (a large one in chunks);
//! 7. `function`: one quantity, planned and emitted in one piece or in chunks; `composed`: one
//!    written composed, a method calling the robot's smaller functions and the runtime;
//! 8. `frames`: the per-frame functions and the frame trait; `contacts`: the contact trait;
//! 9. `fixed` and `floating`: the module of a fixed-base or a floating-base robot;
//! 10. this file, which chooses the [`Sizes`] and passes them down.
//!
//! Each function declares all its temporaries once (`let [x0, x1, …]: [f64; K];`), then assigns
//! every live node in creation order, `xK = a op b;`, with atoms (literals, inputs, earlier
//! temporaries) as operands: never nested expressions, which overflow rustc's parser on large
//! robots, and never one `let` per node, which nests debug-info scopes as deep as the function
//! is long (see `Plan::statements`). Functions of more than [`Sizes::chunk_values`] values are
//! split into `<name>_partK` chunk functions that hand on the values later chunks read through
//! arrays the calling function owns (`chunks`). Inputs are destructured once at the top of a
//! function; vector and matrix results are written in place through destructured `&mut`
//! entries, the others built with `from_array_storage`, so the generated code has no indexing,
//! no allocation and no panic path.

mod body;
mod chunks;
mod composed;
mod constants;
mod contacts;
mod file;
mod fixed;
mod floating;
mod frames;
mod function;
mod header;
mod into_form;
mod kernel;
mod lane_width;
mod leaves;
mod outputs;
mod plan;
mod signature;
mod sizes;
mod vector_stores;

use crate::generate::trace::SymbolicRobot;
use crate::model::Model;
pub use file::{type_name, Provenance, MODULE_ATTRIBUTES};
pub use sizes::Sizes;

/// Values per chunk function. Chunks bound the size of what LLVM optimises at once, whose cost
/// grows faster than linearly, for very large robots; every function of a 7-DOF arm but its
/// derivatives fits in one. Chunks do not shrink what a call runs, and a chunk boundary costs a
/// store and a load for each value that crosses it, so a function runs faster whole than split
/// by count (`BENCHMARKS.md`); split where a first stage ends (forward dynamics in its
/// derivatives), it runs faster than whole.
pub const CHUNK_VALUES: usize = 4096;

/// Functions that compute more values than this, and the derivatives of the dynamics, run
/// through `dyngen_runtime::__private::dispatch_eight` (lane kernels) or `dispatch_many`
/// (scalar ones): their values outnumber sixteen registers many times over, and in a default
/// build those give them the 32 of AVX-512 where the processor has it, as a native build does
/// (`BENCHMARKS.md`). On processors where AVX-512 slows scalar code, `dispatch_many` keeps the
/// AVX2 function. Small kernels stay in the AVX2 function, where they ran faster.
const MANY_VALUES: usize = 1000;

/// Results larger than this, up to [`UNROLLED_FILL_BYTES`], start from
/// `dyngen_runtime::__private::fill_zero()` rather than a constant zero, whose fill the compiler
/// would make a call to `memset` (see that function). Smaller ones keep the constant: the
/// compiler fills them with at most sixteen inline stores (AVX2), or drops the fill when every
/// entry is written.
const LIBRARY_FILL_BYTES: usize = 512;

/// Results larger than this start from a constant zero again, filled by one `memset` into the
/// result itself. The compiler unrolls `fill_zero`'s fill into the result only up to about
/// 5 KiB; a larger one it fills in a temporary and copies into the result, three passes over
/// the memory where the library call makes one (`BENCHMARKS.md`).
const UNROLLED_FILL_BYTES: usize = 4096;

/// The sizes every module is emitted with.
pub const SIZES: Sizes = Sizes {
    chunk_values: CHUNK_VALUES,
    many_values: MANY_VALUES,
    library_fill_bytes: LIBRARY_FILL_BYTES,
    unrolled_fill_bytes: UNROLLED_FILL_BYTES,
};

/// The complete generated module of `model` (fixed or floating base), formatted. The module
/// declaration that includes it carries the lint allows of [`MODULE_ATTRIBUTES`].
pub fn emit(model: &Model, robot: &SymbolicRobot, provenance: &Provenance) -> String {
    emit_with(model, robot, provenance, &SIZES)
}

/// [`emit`] with other [`Sizes`] than [`SIZES`] (tests split small robots' functions in chunks).
pub fn emit_with(model: &Model, robot: &SymbolicRobot, provenance: &Provenance, sizes: &Sizes) -> String {
    match model.floating_base() {
        Some(_) => floating::module(model, robot, provenance, sizes),
        None => fixed::module(model, robot, provenance, sizes),
    }
}
