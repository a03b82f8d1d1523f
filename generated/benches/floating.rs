//! Timings of a floating-base robot's generated functions (Solo-12), named as the numeric
//! Pinocchio anchor names its algorithms (`tools/compare_anchors.py` sets them side by side):
//! each call includes preparing the configuration (`FloatingTrig::from_configuration`: the
//! rotation of the base quaternion and the joint sines and cosines), as Pinocchio's calls
//! include its joint transforms. Inputs cycle through 256 random states: base position in
//! ±1 m, a random unit quaternion, joints in ±π, velocities in ±2, accelerations in ±5,
//! generalised forces in ±10.

// Its own states: `common::model` and `common::states` are for fixed bases.
#[allow(dead_code)]
mod common;

use common::{cycle, floating_states};
use criterion::{criterion_group, criterion_main, Criterion};
use dyngen_generated::solo12::{Frame, Solo12, NQ, NV};
use dyngen_runtime::nalgebra::SVector;
use dyngen_runtime::{
    FloatingBaseDynamics, FloatingBaseParameters, FloatingDynamicsDerivatives, FloatingForwardDynamics,
    FloatingFrameKinematics, FloatingRegressors, FloatingTrig, ReferenceFrame, ResultBuffer,
};
use std::hint::black_box;

fn trig(q: &SVector<f64, NQ>) -> FloatingTrig<12> {
    // The states are unit quaternions by construction.
    FloatingTrig::from_configuration(q.as_slice()).unwrap_or_else(|e| panic!("{e}"))
}

fn solo12(c: &mut Criterion) {
    let inputs = floating_states::<NQ, NV>(18);
    let g = |f: &str| format!("solo12/{f}");
    let lwa = ReferenceFrame::LocalWorldAligned;
    cycle(c, &g("floating_trig"), "generated", &inputs, |(q, _)| {
        black_box(trig(q));
    });
    cycle(c, &g("joint_trig"), "generated", &inputs, |(q, _)| {
        black_box(dyngen_runtime::JointTrig::new(
            &q.fixed_rows::<12>(7).into_owned(),
        ));
    });
    cycle(c, &g("base_pose"), "generated", &inputs, |(q, _)| {
        black_box(dyngen_runtime::BasePose::from_configuration(q.as_slice()).unwrap());
    });
    cycle(c, &g("fk"), "generated", &inputs, |(q, _)| {
        black_box(Solo12::frame_pose(Frame::FlFoot, &trig(q)));
    });
    cycle(c, &g("jacobian"), "generated", &inputs, |(q, _)| {
        black_box(Solo12::frame_jacobian(Frame::FlFoot, lwa, &trig(q)));
    });
    cycle(c, &g("jacobian_dot"), "generated", &inputs, |(q, [v, ..])| {
        black_box(Solo12::frame_jacobian_time_variation(
            Frame::FlFoot,
            lwa,
            &trig(q),
            v,
        ));
    });
    cycle(c, &g("mass_matrix"), "generated", &inputs, |(q, _)| {
        black_box(Solo12::mass_matrix(&trig(q)));
    });
    // The `_into` forms write into a result kept between calls (`ResultBuffer`).
    let mut d = ResultBuffer::new();
    cycle(c, &g("mass_matrix"), "generated_into", &inputs, |(q, _)| {
        Solo12::mass_matrix_into(&trig(q), &mut d);
        black_box(&d);
    });
    cycle(c, &g("coriolis"), "generated", &inputs, |(q, [v, ..])| {
        black_box(Solo12::coriolis_matrix(&trig(q), v));
    });
    let mut cm = ResultBuffer::new();
    cycle(c, &g("coriolis"), "generated_into", &inputs, |(q, [v, ..])| {
        Solo12::coriolis_matrix_into(&trig(q), v, &mut cm);
        black_box(&cm);
    });
    cycle(c, &g("gravity"), "generated", &inputs, |(q, _)| {
        black_box(Solo12::gravity(&trig(q)));
    });
    cycle(c, &g("rnea"), "generated", &inputs, |(q, [v, a, _])| {
        black_box(Solo12::inverse_dynamics(&trig(q), v, a));
    });
    cycle(
        c,
        &g("torque_regressor"),
        "generated",
        &inputs,
        |(q, [v, a, _])| {
            black_box(Solo12::torque_regressor(&trig(q), v, a));
        },
    );
    let mut y = ResultBuffer::new();
    cycle(
        c,
        &g("torque_regressor"),
        "generated_into",
        &inputs,
        |(q, [v, a, _])| {
            Solo12::torque_regressor_into(&trig(q), v, a, &mut y);
            black_box(&y);
        },
    );
    cycle(
        c,
        &g("base_torque_regressor"),
        "generated",
        &inputs,
        |(q, [v, a, _])| {
            black_box(Solo12::base_torque_regressor(&trig(q), v, a));
        },
    );
    let mut yb = ResultBuffer::new();
    cycle(
        c,
        &g("base_torque_regressor"),
        "generated_into",
        &inputs,
        |(q, [v, a, _])| {
            Solo12::base_torque_regressor_into(&trig(q), v, a, &mut yb);
            black_box(&yb);
        },
    );
    cycle(c, &g("aba"), "generated", &inputs, |(q, [v, _, tau])| {
        black_box(Solo12::forward_dynamics(&trig(q), v, tau));
    });
    cycle(
        c,
        &g("rnea_derivatives"),
        "generated",
        &inputs,
        |(q, [v, a, _])| {
            black_box(Solo12::inverse_dynamics_derivatives(&trig(q), v, a));
        },
    );
    let mut d_tau = ResultBuffer::new();
    cycle(
        c,
        &g("rnea_derivatives"),
        "generated_into",
        &inputs,
        |(q, [v, a, _])| {
            Solo12::inverse_dynamics_derivatives_into(&trig(q), v, a, &mut d_tau);
            black_box(&d_tau);
        },
    );
    cycle(
        c,
        &g("aba_derivatives"),
        "generated",
        &inputs,
        |(q, [v, _, tau])| {
            black_box(Solo12::forward_dynamics_derivatives(&trig(q), v, tau));
        },
    );
    let mut d_nu = ResultBuffer::new();
    cycle(
        c,
        &g("aba_derivatives"),
        "generated_into",
        &inputs,
        |(q, [v, _, tau])| {
            Solo12::forward_dynamics_derivatives_into(&trig(q), v, tau, &mut d_nu);
            black_box(&d_nu);
        },
    );
    cycle(c, &g("minv"), "generated", &inputs, |(q, _)| {
        black_box(Solo12::mass_matrix_inverse(&trig(q)));
    });
    let mut minv = ResultBuffer::new();
    cycle(c, &g("minv"), "generated_into", &inputs, |(q, _)| {
        Solo12::mass_matrix_inverse_into(&trig(q), &mut minv);
        black_box(&minv);
    });
    cycle(c, &g("com"), "generated", &inputs, |(q, _)| {
        black_box(Solo12::center_of_mass(&trig(q)));
    });
    cycle(c, &g("ccrba"), "generated", &inputs, |(q, _)| {
        black_box(Solo12::centroidal_momentum_matrix(&trig(q)));
    });
    cycle(c, &g("dccrba"), "generated", &inputs, |(q, [v, ..])| {
        black_box(Solo12::centroidal_bias(&trig(q), v));
    });
}

criterion_group! {
    name = benches;
    config = common::config();
    targets = solo12
}
criterion_main!(benches);
