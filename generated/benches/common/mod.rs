//! What the generated-code benchmarks share: the robot's model, its random states in both
//! forms (slices for the generic code, fixed-size vectors for the generated code), and the
//! loop that cycles through them.

use criterion::{BenchmarkId, Criterion};
use dyngen_codegen::description::load;
use dyngen_codegen::model::Model;
use dyngen_runtime::nalgebra::SVector;
use dyngen_runtime::SplitMix64;
use std::hint::black_box;
use std::path::Path;
use std::time::Duration;

/// States per robot, as in the Pinocchio benchmark of the reference figures.
pub const STATES: usize = 256;

/// A committed robot's model (`robots/<robot>.yaml`).
pub fn model(robot: &str) -> Model {
    let path = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/..")).join(format!("robots/{robot}.yaml"));
    load(&path).unwrap_or_else(|e| panic!("{e}")).model
}

/// Deterministic random states: q in ±π, then three vectors drawn from `ranges`; as slices
/// and as fixed-size vectors.
#[allow(clippy::type_complexity)]
pub fn states<const N: usize>(
    seed: u64,
    ranges: [(f64, f64); 3],
) -> (Vec<[Vec<f64>; 4]>, Vec<[SVector<f64, N>; 4]>) {
    let mut rng = SplitMix64::new(seed);
    let pi = std::f64::consts::PI;
    let mut draw = |range: (f64, f64)| -> Vec<f64> { (0..N).map(|_| rng.uniform(range)).collect() };
    let raw: Vec<[Vec<f64>; 4]> = (0..STATES)
        .map(|_| [draw((-pi, pi)), draw(ranges[0]), draw(ranges[1]), draw(ranges[2])])
        .collect();
    let fixed = raw
        .iter()
        .map(|s| std::array::from_fn(|i| SVector::from_column_slice(&s[i])))
        .collect();
    (raw, fixed)
}

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
