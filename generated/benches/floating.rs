//! Timings of a floating-base robot's generated functions (Solo-12), named as the numeric
//! Pinocchio anchors name their algorithms: `common/floating.rs`, which the G1's bench
//! (`tools/anchors/floating-cg/dyngen/`) shares. Inputs cycle through 256 random states: base
//! position in ±1 m, a random unit quaternion, joints in ±π, velocities in ±2, accelerations in
//! ±5, generalised forces in ±10.

// Its own states: `common::model` and `common::states` are for fixed bases.
#[allow(dead_code)]
mod common;
#[path = "common/floating.rs"]
mod floating;

use criterion::{criterion_group, criterion_main, Criterion};
use dyngen_generated::solo12::{Frame, Solo12, BASE_PARAMETER_COUNT, DOF, NQ, NV, PARAMETER_COUNT};

fn solo12(c: &mut Criterion) {
    let inputs = floating::states::<NQ, NV>();
    floating::preparation::<DOF, NQ, NV>(c, "solo12", &inputs);
    floating::frames::<Solo12, DOF, NQ, NV>(c, "solo12", &inputs, Frame::FlFoot);
    floating::dynamics::<Solo12, DOF, NQ, NV, PARAMETER_COUNT>(c, "solo12", &inputs);
    floating::regressors::<Solo12, DOF, NQ, NV, PARAMETER_COUNT, BASE_PARAMETER_COUNT>(c, "solo12", &inputs);
}

criterion_group! {
    name = benches;
    config = common::config();
    targets = solo12
}
criterion_main!(benches);
