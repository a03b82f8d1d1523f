//! Timings of the G1's constrained functions on its two feet, as Solo-12's in the repository
//! (`generated/benches/contacts.rs`): the same timing loop, states and calls, included from
//! there.

#[path = "../../../../../generated/benches/common/timing.rs"]
mod common;
#[path = "../../../../../generated/benches/common/constrained.rs"]
mod constrained;

use criterion::{criterion_group, criterion_main, Criterion};
use dyngen_contacts_g1::g1::{DOF, G1, NQ, NV};

fn g1(c: &mut Criterion) {
    constrained::bench::<G1, DOF, NQ, NV, 12>(c, "g1");
}

criterion_group! {
    name = benches;
    config = common::config();
    targets = g1
}
criterion_main!(benches);
