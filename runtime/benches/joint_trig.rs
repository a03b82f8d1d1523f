//! Sines and cosines of seven joint angles: `JointTrig::new` (one pass over the array) against
//! one `libm::sincos` per joint (what it did before). `cargo bench -p dyngen-runtime`.

use criterion::{criterion_group, criterion_main, Criterion};
use dyngen_runtime::nalgebra::SVector;
use dyngen_runtime::{JointTrig, SplitMix64};
use std::hint::black_box;

fn joint_trig(c: &mut Criterion) {
    let mut rng = SplitMix64::new(3);
    let states: Vec<SVector<f64, 7>> = (0..256)
        .map(|_| SVector::from_fn(|_, _| rng.uniform((-3.0, 3.0))))
        .collect();
    let mut g = c.benchmark_group("joint_trig_7");
    let mut k = 0;
    g.bench_function("batched", |b| {
        b.iter(|| {
            k = (k + 1) % states.len();
            black_box(JointTrig::new(black_box(&states[k])))
        })
    });
    g.bench_function("libm_per_joint", |b| {
        b.iter(|| {
            k = (k + 1) % states.len();
            let q: [f64; 7] = black_box(&states[k]).data.0[0];
            black_box(q.map(libm::sincos))
        })
    });
    g.finish();
}

criterion_group!(benches, joint_trig);
criterion_main!(benches);
