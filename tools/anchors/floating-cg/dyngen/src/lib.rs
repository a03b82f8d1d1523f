//! The Unitree G1 with its forward dynamics and derivatives (`g1.yaml`), generated at build
//! time: the dyngen side of the G1's rows in `tools/compare_floating.py` (`benches/floating.rs`).

// The chunks of a humanoid's largest generated functions hand their values on through more
// than seven arrays (the repository's committed robots have none that large).
#![allow(clippy::too_many_arguments)]

dyngen_runtime::include_robot!(g1);
