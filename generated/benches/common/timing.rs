//! The timing loop of the generated-code benches and the floating-base states, with no
//! dependency but criterion and the runtime: the G1's benches (`tools/anchors/contacts/dyngen/`
//! and `tools/anchors/floating-cg/dyngen/`, crates of their own) include this file too, so that
//! both robots are timed alike.

use criterion::{BenchmarkId, Criterion};
use dyngen_runtime::nalgebra::SVector;
use dyngen_runtime::SplitMix64;
use std::hint::black_box;
use std::time::Duration;

/// States per robot, as in the Pinocchio benchmark of the reference figures.
pub const STATES: usize = 256;

/// Times `f` on each state in turn.
pub fn cycle<T>(c: &mut Criterion, group: &str, id: &str, inputs: &[T], mut f: impl FnMut(&T)) {
    let mut k = 0;
    c.benchmark_group(group)
        .bench_function(BenchmarkId::from_parameter(id), |b| {
            b.iter(|| {
                k = (k + 1) % inputs.len();
                f(black_box(&inputs[k]))
            })
        });
}

/// Criterion settings of the generated-code benches: short warm-up and measurement (each call
/// is nanoseconds), 40 samples.
pub fn config() -> Criterion {
    Criterion::default()
        .warm_up_time(Duration::from_millis(300))
        .measurement_time(Duration::from_secs(1))
        .sample_size(40)
}

/// A floating-base state: the configuration (Pinocchio's layout) and `[v, a, τ]`.
pub type FloatingState<const NQ: usize, const NV: usize> = (SVector<f64, NQ>, [SVector<f64, NV>; 3]);

/// The floating-base states, in this order per state: base position in ±1 m, a random unit
/// quaternion (four draws in ±1, normalised), joints in ±π, then velocities in ±2,
/// accelerations in ±5, generalised forces in ±10 (the numeric anchors draw the same stream).
pub fn floating_states<const NQ: usize, const NV: usize>(seed: u64) -> Vec<FloatingState<NQ, NV>> {
    let mut rng = SplitMix64::new(seed);
    let pi = std::f64::consts::PI;
    (0..STATES)
        .map(|_| {
            let mut q = SVector::<f64, NQ>::from_fn(|i, _| match i {
                0..7 => rng.uniform((-1.0, 1.0)),
                _ => rng.uniform((-pi, pi)),
            });
            let norm = q.fixed_rows::<4>(3).norm();
            q.fixed_rows_mut::<4>(3).unscale_mut(norm);
            let mut draw = |bound: f64| SVector::<f64, NV>::from_fn(|_, _| rng.uniform((-bound, bound)));
            (q, [draw(2.0), draw(5.0), draw(10.0)])
        })
        .collect()
}
