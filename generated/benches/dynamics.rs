//! Generated against generic dynamics, per quantity, on every committed robot, in one run.
//!
//! Each call includes the joint sines and cosines (`JointTrig::new` for generated code, the
//! joint transforms for the generic code), as a controller pays them. Inputs cycle through 256
//! precomputed random states, as in the Pinocchio benchmark of the reference figures.
//! `cargo bench --bench dynamics`, then `cargo xtask bench-table` for the table.

mod common;

use common::{cycle, model, states};
use criterion::{criterion_group, criterion_main, Criterion};
use dyngen_codegen::base_parameters::BaseParameterSet;
use dyngen_codegen::dynamics::NumericDynamics;
use dyngen_generated::{Arm7, Panda, PandaRounded, Ur5, Xarm7, Xarm7Snapped};
use dyngen_runtime::nalgebra::SVector;
use dyngen_runtime::{
    f64x4, f64x8, pack, BaseParameters, JointTrig, JointTrigLanes, LaneDynamics, Lanes, ResultBuffer,
};
use std::hint::black_box;

fn bench_robot<
    R: BaseParameters<N, P, B> + LaneDynamics<N, B>,
    const N: usize,
    const P: usize,
    const B: usize,
>(
    c: &mut Criterion,
    robot: &str,
) {
    let model = model(robot);
    let generic = NumericDynamics::new(&model);
    // Velocities ±2, accelerations ±5.
    let (raw, fixed) = states::<N>(0x5eed, [(-2.0, 2.0), (-2.0, 2.0), (-5.0, 5.0)]);
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
    // The `_into` forms write into a result kept between calls (`ResultBuffer`).
    let mut d = ResultBuffer::new();
    cycle(c, &g("mass_matrix"), "generated_into", &fixed, |[q, ..]| {
        R::mass_matrix_into(&JointTrig::new(q), &mut d);
        black_box(&d);
    });
    cycle(c, &g("mass_matrix"), "generic", &raw, |[q, ..]| {
        black_box(generic.mass_matrix(q));
    });
    cycle(c, &g("coriolis"), "generated", &fixed, |[q, qd, ..]| {
        black_box(R::coriolis_matrix(&JointTrig::new(q), qd));
    });
    let mut cm = ResultBuffer::new();
    cycle(c, &g("coriolis"), "generated_into", &fixed, |[q, qd, ..]| {
        R::coriolis_matrix_into(&JointTrig::new(q), qd, &mut cm);
        black_box(&cm);
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
    let mut y = ResultBuffer::new();
    cycle(c, &g("regressor"), "generated_into", &fixed, |[q, qd, v, a]| {
        R::regressor_into(&JointTrig::new(q), qd, v, a, &mut y);
        black_box(&y);
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
    let mut yb = ResultBuffer::new();
    cycle(
        c,
        &g("base_regressor"),
        "generated_into",
        &fixed,
        |[q, qd, v, a]| {
            R::base_regressor_into(&JointTrig::new(q), qd, v, a, &mut yb);
            black_box(&yb);
        },
    );
    cycle(c, &g("base_regressor"), "generic", &raw, |[q, qd, v, a]| {
        black_box(base.base_regressor(&generic.regressor(q, qd, v, a)));
    });
    // What an adaptive law takes each tick, `Y_b θ_b` and `Y_bᵀ r` (here `r = a`): generated
    // without forming `Y_b`, against forming it and multiplying.
    let theta_b = R::base_parameters(&R::parameters());
    cycle(
        c,
        &g("base_regressor_products"),
        "generated",
        &fixed,
        |[q, qd, v, a]| {
            black_box(R::base_regressor_products(
                &JointTrig::new(q),
                qd,
                v,
                a,
                &theta_b,
                a,
            ));
        },
    );
    cycle(
        c,
        &g("base_regressor_products"),
        "through_base_regressor",
        &fixed,
        |[q, qd, v, a]| {
            let y = R::base_regressor(&JointTrig::new(q), qd, v, a);
            black_box((y * theta_b, y.tr_mul(a)));
        },
    );
    // The torque form `Y(q, q̇, q̇, q̈)` (Pinocchio's `computeJointTorqueRegressor`).
    cycle(c, &g("torque_regressor"), "generated", &fixed, |[q, qd, _, a]| {
        black_box(R::torque_regressor(&JointTrig::new(q), qd, a));
    });
    cycle(
        c,
        &g("torque_regressor"),
        "generated_into",
        &fixed,
        |[q, qd, _, a]| {
            R::torque_regressor_into(&JointTrig::new(q), qd, a, &mut y);
            black_box(&y);
        },
    );
    cycle(c, &g("torque_regressor"), "generic", &raw, |[q, qd, _, a]| {
        black_box(generic.regressor(q, qd, qd, a));
    });
    cycle(
        c,
        &g("base_torque_regressor"),
        "generated",
        &fixed,
        |[q, qd, _, a]| {
            black_box(R::base_torque_regressor(&JointTrig::new(q), qd, a));
        },
    );
    cycle(
        c,
        &g("base_torque_regressor"),
        "generated_into",
        &fixed,
        |[q, qd, _, a]| {
            R::base_torque_regressor_into(&JointTrig::new(q), qd, a, &mut yb);
            black_box(&yb);
        },
    );

    // Several states per call (SIMD lanes); a sample is one call, so divide by the lane count
    // for the time per state.
    lanes::<R, f64x4, N, P, B>(c, robot, &fixed);
    lanes::<R, f64x8, N, P, B>(c, robot, &fixed);
}

/// `τ` and the torque-form `Y_b` of `L::WIDTH` states per call, sines and cosines included.
fn lanes<R, L, const N: usize, const P: usize, const B: usize>(
    c: &mut Criterion,
    robot: &str,
    fixed: &[[SVector<f64, N>; 4]],
) where
    R: BaseParameters<N, P, B> + LaneDynamics<N, B>,
    L: Lanes,
{
    let batches: Vec<[[L; N]; 3]> = fixed
        .chunks_exact(L::WIDTH)
        .map(|states| [0, 1, 3].map(|i| pack::<L, N>(&states.iter().map(|s| s[i]).collect::<Vec<_>>())))
        .collect();
    let id = format!("generated_lanes{}", L::WIDTH);
    cycle(c, &format!("{robot}/rnea"), &id, &batches, |[q, qd, a]| {
        black_box(R::inverse_dynamics_lanes(&JointTrigLanes::new(q), qd, a));
    });
    cycle(
        c,
        &format!("{robot}/base_torque_regressor"),
        &id,
        &batches,
        |[q, qd, a]| {
            black_box(R::base_torque_regressor_lanes(&JointTrigLanes::new(q), qd, a));
        },
    );
}

fn dynamics(c: &mut Criterion) {
    bench_robot::<Panda, 7, 70, { dyngen_generated::panda::BASE_PARAMETER_COUNT }>(c, "panda");
    bench_robot::<PandaRounded, 7, 70, { dyngen_generated::panda_rounded::BASE_PARAMETER_COUNT }>(
        c,
        "panda_rounded",
    );
    bench_robot::<Ur5, 6, 60, { dyngen_generated::ur5::BASE_PARAMETER_COUNT }>(c, "ur5");
    bench_robot::<Arm7, 7, 70, { dyngen_generated::arm7::BASE_PARAMETER_COUNT }>(c, "arm7");
    bench_robot::<Xarm7, 7, 70, { dyngen_generated::xarm7::BASE_PARAMETER_COUNT }>(c, "xarm7");
    bench_robot::<Xarm7Snapped, 7, 70, { dyngen_generated::xarm7_snapped::BASE_PARAMETER_COUNT }>(
        c,
        "xarm7_snapped",
    );
}

criterion_group! {
    name = benches;
    config = common::config();
    targets = dynamics
}
criterion_main!(benches);
