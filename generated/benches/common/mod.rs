//! What the generated-code benchmarks share: the robot's model, its random states in both
//! forms (slices for the generic code, fixed-size vectors for the generated code), and the
//! loop that cycles through them (`timing`, shared with the G1's benches).

// Its floating-base states serve only the benches of floating bases.
#[allow(dead_code)]
mod timing;
pub use timing::*;

use dyngen_codegen::description::load;
use dyngen_codegen::model::Model;
use dyngen_runtime::nalgebra::SVector;
use dyngen_runtime::SplitMix64;
use std::path::Path;

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
