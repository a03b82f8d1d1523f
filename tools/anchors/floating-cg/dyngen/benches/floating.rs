//! Timings of the G1's dynamics and derivatives, as Solo-12's in the repository
//! (`generated/benches/floating.rs`): the same timing loop, states and calls, included from
//! there.

#[path = "../../../../../generated/benches/common/timing.rs"]
mod common;
// Its frames and regressors: the G1 here is generated without them.
#[allow(dead_code)]
#[path = "../../../../../generated/benches/common/floating.rs"]
mod floating;

use criterion::{criterion_group, criterion_main, Criterion};
use dyngen_floating_g1::g1::{DOF, G1, NQ, NV, PARAMETER_COUNT};

fn g1(c: &mut Criterion) {
    let inputs = floating::states::<NQ, NV>();
    floating::preparation::<DOF, NQ, NV>(c, "g1", &inputs);
    floating::dynamics::<G1, DOF, NQ, NV, PARAMETER_COUNT>(c, "g1", &inputs);
}

criterion_group! {
    name = benches;
    config = common::config();
    targets = g1
}
criterion_main!(benches);
