//! The robots of `build.rs`, each straight-line (`*_flat`) and composed (`*_composed`).

// The chunks of a humanoid's largest generated functions hand their values on through more
// than seven arrays.
#![allow(clippy::too_many_arguments)]

dyngen_runtime::include_robot!(g1_flat);
dyngen_runtime::include_robot!(g1_composed);
dyngen_runtime::include_robot!(solo12_flat);
dyngen_runtime::include_robot!(solo12_composed);
#[cfg(tiago)]
dyngen_runtime::include_robot!(tiago_flat);
#[cfg(tiago)]
dyngen_runtime::include_robot!(tiago_composed);
