//! The symbolic engine: the dynamics algorithms, run on [`Expr`] instead of `f64`, record an
//! expression graph that is simplified as it is built and shared by construction.
//!
//! - `graph`: the hash-consed node arena; building a node applies the algebraic rules
//!   (constant folding, `x·0`, `x·1`, `x+0`, `−(−x)`, `sin²+cos²`, …) so no dead or trivial
//!   node is ever created, and identical subexpressions are the same node (CSE for free).
//! - `expr`: `Expr`, a `Copy` handle that implements [`Scalar`](crate::scalar::Scalar)
//!   against the graph being recorded on this thread.
//! - `eval`: an interpreter, so random robots are tested without compiling Rust.

mod eval;
mod expr;
mod graph;

pub use eval::evaluate;
pub use expr::{record, Expr, LaneExpr};
pub use graph::{Graph, Id, Node, OpCounts, LANES};
