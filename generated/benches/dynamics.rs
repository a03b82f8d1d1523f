//! Generated against generic dynamics, per quantity, on every committed robot, in one run.
//!
//! Each call includes the joint sines and cosines (`JointTrig::new` for generated code, the
//! joint transforms for the generic code), as a controller pays them. Inputs cycle through 256
//! precomputed random states, as in the Pinocchio benchmark of the reference figures.
//! `cargo bench --bench dynamics`, then `cargo xtask bench-table` for the table.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use dyngen_codegen::base_parameters::BaseParameterSet;
use dyngen_codegen::description::load;
use dyngen_codegen::dynamics::NumericDynamics;
use dyngen_codegen::model::Model;
use dyngen_generated::{Arm7, Panda, Ur5};
use dyngen_runtime::nalgebra::SVector;
use dyngen_runtime::{BaseParameters, JointTrig, SplitMix64};
use std::hint::black_box;
use std::path::Path;
use std::time::Duration;

const STATES: usize = 256;

/// Deterministic random states: q in ±π, velocities ±2, accelerations ±5.
fn states(n: usize) -> Vec<[Vec<f64>; 4]> {
    let mut rng = SplitMix64::new(0x5eed);
    let pi = std::f64::consts::PI;
    let mut draw = |range: (f64, f64)| -> Vec<f64> { (0..n).map(|_| rng.uniform(range)).collect() };
    (0..STATES)
        .map(|_| {
            [
                draw((-pi, pi)),
                draw((-2.0, 2.0)),
                draw((-2.0, 2.0)),
                draw((-5.0, 5.0)),
            ]
        })
        .collect()
}

fn model(robot: &str) -> Model {
    let path = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/..")).join(format!("robots/{robot}.yaml"));
    load(&path).unwrap_or_else(|e| panic!("{e}")).model
}

/// Times `f` on each state in turn.
fn cycle<T>(c: &mut Criterion, group: &str, id: &str, inputs: &[T], mut f: impl FnMut(&T)) {
    let mut k = 0;
    c.benchmark_group(group)
        .bench_function(BenchmarkId::from_parameter(id), |b| {
            b.iter(|| {
                k = (k + 1) % inputs.len();
                f(black_box(&inputs[k]))
            })
        });
}

fn bench_robot<R: BaseParameters<N, P, B>, const N: usize, const P: usize, const B: usize>(
    c: &mut Criterion,
    robot: &str,
) {
    let model = model(robot);
    let generic = NumericDynamics::new(&model);
    let raw = states(N);
    let fixed: Vec<[SVector<f64, N>; 4]> = raw
        .iter()
        .map(|s| std::array::from_fn(|i| SVector::from_column_slice(&s[i])))
        .collect();
    let g = |quantity: &str| format!("{robot}/{quantity}");

    // The share of every generated call below that is sines and cosines.
    cycle(c, &g("joint_trig"), "generated", &fixed, |[q, ..]| {
        black_box(JointTrig::new(q));
    });
    cycle(c, &g("fk"), "generated", &fixed, |[q, ..]| {
        black_box(R::forward_kinematics(&JointTrig::new(q)));
    });
    cycle(c, &g("fk"), "generic", &raw, |[q, ..]| {
        black_box(generic.end_effector_pose(q));
    });
    cycle(c, &g("jacobian"), "generated", &fixed, |[q, ..]| {
        black_box(R::jacobian(&JointTrig::new(q)));
    });
    cycle(c, &g("jacobian"), "generic", &raw, |[q, ..]| {
        black_box(generic.jacobian(q));
    });
    cycle(c, &g("jacobian_dot"), "generated", &fixed, |[q, qd, ..]| {
        black_box(R::jacobian_dot(&JointTrig::new(q), qd));
    });
    cycle(c, &g("jacobian_dot"), "generic", &raw, |[q, qd, ..]| {
        black_box(generic.jacobian_dot(q, qd));
    });
    cycle(c, &g("mass_matrix"), "generated", &fixed, |[q, ..]| {
        black_box(R::mass_matrix(&JointTrig::new(q)));
    });
    cycle(c, &g("mass_matrix"), "generic", &raw, |[q, ..]| {
        black_box(generic.mass_matrix(q));
    });
    cycle(c, &g("coriolis"), "generated", &fixed, |[q, qd, ..]| {
        black_box(R::coriolis_matrix(&JointTrig::new(q), qd));
    });
    cycle(c, &g("coriolis"), "generic", &raw, |[q, qd, ..]| {
        black_box(generic.coriolis_matrix(q, qd));
    });
    cycle(c, &g("gravity"), "generated", &fixed, |[q, ..]| {
        black_box(R::gravity(&JointTrig::new(q)));
    });
    cycle(c, &g("gravity"), "generic", &raw, |[q, ..]| {
        black_box(generic.gravity_torque(q));
    });
    cycle(c, &g("rnea"), "generated", &fixed, |[q, qd, _, a]| {
        black_box(R::inverse_dynamics(&JointTrig::new(q), qd, a));
    });
    cycle(c, &g("rnea"), "generic", &raw, |[q, qd, _, a]| {
        black_box(generic.inverse_dynamics(q, qd, a));
    });
    cycle(c, &g("regressor"), "generated", &fixed, |[q, qd, v, a]| {
        black_box(R::regressor(&JointTrig::new(q), qd, v, a));
    });
    cycle(c, &g("regressor"), "generic", &raw, |[q, qd, v, a]| {
        black_box(generic.regressor(q, qd, v, a));
    });
    // Y_b: the generated function computes only the base columns; the generic baseline is Y
    // followed by a column pick.
    let base = BaseParameterSet::compute(&model);
    cycle(c, &g("base_regressor"), "generated", &fixed, |[q, qd, v, a]| {
        black_box(R::base_regressor(&JointTrig::new(q), qd, v, a));
    });
    cycle(c, &g("base_regressor"), "generic", &raw, |[q, qd, v, a]| {
        black_box(base.base_regressor(&generic.regressor(q, qd, v, a)));
    });
}

fn dynamics(c: &mut Criterion) {
    bench_robot::<Panda, 7, 70, { dyngen_generated::panda::BASE_PARAMETER_COUNT }>(c, "panda");
    bench_robot::<Ur5, 6, 60, { dyngen_generated::ur5::BASE_PARAMETER_COUNT }>(c, "ur5");
    bench_robot::<Arm7, 7, 70, { dyngen_generated::arm7::BASE_PARAMETER_COUNT }>(c, "arm7");
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .warm_up_time(Duration::from_millis(300))
        .measurement_time(Duration::from_secs(1))
        .sample_size(40);
    targets = dynamics
}
criterion_main!(benches);
