//! Timings of the constrained functions of Solo-12 on its four point feet (`robots/solo12.yaml`,
//! `contacts:`): constrained forward dynamics (exact and Baumgarte-stabilised), the impact, the
//! feet's operational-space inertia and the generated pieces they are assembled from, each call
//! from the configuration (`common/constrained.rs`, shared with the G1's bench). The numeric
//! Pinocchio side is `tools/anchors/contacts/`; `tools/compare_contacts.py` sets them side by
//! side.

// The fixed-base helpers of `common` are not used here.
#[allow(dead_code)]
mod common;
#[path = "common/constrained.rs"]
mod constrained;

use criterion::{criterion_group, criterion_main, Criterion};
use dyngen_generated::solo12::{Solo12, DOF, NQ, NV};

fn solo12(c: &mut Criterion) {
    constrained::bench::<Solo12, DOF, NQ, NV, 12>(c, "solo12");
}

criterion_group! {
    name = benches;
    config = common::config();
    targets = solo12
}
criterion_main!(benches);
