//! Forward dynamics, `D⁻¹` and the derivatives of the dynamics: generated against generic, on
//! every committed robot. Rows are named after the Pinocchio benchmark's functions (`aba`,
//! `minv`, `rnea_derivatives`, `aba_derivatives`) so the two join side by side; every call
//! includes the joint sines and cosines. `cargo bench --bench forward_dynamics`.

mod common;

use common::{cycle, model, states};
use criterion::{criterion_group, criterion_main, Criterion};
use dyngen_codegen::dynamics::NumericDynamics;
use dyngen_generated::{Arm7, Panda, PandaRounded, Ur5, Xarm7, Xarm7Snapped};
use dyngen_runtime::{DynamicsDerivatives, ForwardDynamics, JointTrig, ResultBuffer};
use std::hint::black_box;

fn bench_robot<R: ForwardDynamics<N, P> + DynamicsDerivatives<N, P>, const N: usize, const P: usize>(
    c: &mut Criterion,
    robot: &str,
) {
    let model = model(robot);
    let generic = NumericDynamics::new(&model);
    // `[q, q̇, q̈, τ]`: q̇ ±2, q̈ ±5, τ ±10 (Pinocchio's pool).
    let (raw, fixed) = states::<N>(0xfd5eed, [(-2.0, 2.0), (-5.0, 5.0), (-10.0, 10.0)]);
    let g = |quantity: &str| format!("{robot}/{quantity}");

    cycle(c, &g("aba"), "generated", &fixed, |[q, qd, _, tau]| {
        black_box(R::forward_dynamics(&JointTrig::new(q), qd, tau));
    });
    cycle(c, &g("aba"), "generic", &raw, |[q, qd, _, tau]| {
        black_box(generic.forward_dynamics(q, qd, tau));
    });
    cycle(c, &g("minv"), "generated", &fixed, |[q, ..]| {
        black_box(R::mass_matrix_inverse(&JointTrig::new(q)));
    });
    // The `_into` forms write into a result kept between calls (`ResultBuffer`).
    let mut minv = ResultBuffer::new();
    cycle(c, &g("minv"), "generated_into", &fixed, |[q, ..]| {
        R::mass_matrix_inverse_into(&JointTrig::new(q), &mut minv);
        black_box(&minv);
    });
    cycle(c, &g("minv"), "generic", &raw, |[q, ..]| {
        black_box(generic.mass_matrix_inverse(q));
    });
    cycle(
        c,
        &g("rnea_derivatives"),
        "generated",
        &fixed,
        |[q, qd, qdd, _]| {
            black_box(R::inverse_dynamics_derivatives(&JointTrig::new(q), qd, qdd));
        },
    );
    let mut d_tau = ResultBuffer::new();
    cycle(
        c,
        &g("rnea_derivatives"),
        "generated_into",
        &fixed,
        |[q, qd, qdd, _]| {
            R::inverse_dynamics_derivatives_into(&JointTrig::new(q), qd, qdd, &mut d_tau);
            black_box(&d_tau);
        },
    );
    cycle(c, &g("rnea_derivatives"), "generic", &raw, |[q, qd, qdd, _]| {
        black_box(generic.inverse_dynamics_derivatives(q, qd, qdd));
    });
    cycle(c, &g("aba_derivatives"), "generated", &fixed, |[q, qd, _, tau]| {
        black_box(R::forward_dynamics_derivatives(&JointTrig::new(q), qd, tau));
    });
    let mut d_qdd = ResultBuffer::new();
    cycle(
        c,
        &g("aba_derivatives"),
        "generated_into",
        &fixed,
        |[q, qd, _, tau]| {
            R::forward_dynamics_derivatives_into(&JointTrig::new(q), qd, tau, &mut d_qdd);
            black_box(&d_qdd);
        },
    );
    cycle(c, &g("aba_derivatives"), "generic", &raw, |[q, qd, _, tau]| {
        black_box(generic.forward_dynamics_derivatives(q, qd, tau));
    });
    // A default build on an AVX-512 processor: the derivatives' lanes also in two AVX registers,
    // the speed an AVX2 processor would get from the same binary.
    if dyngen_runtime::__private::avx512_lanes() && !dyngen_runtime::__private::set_avx512_lanes(false) {
        cycle(
            c,
            &g("rnea_derivatives"),
            "generated_avx2_lanes",
            &fixed,
            |[q, qd, qdd, _]| {
                black_box(R::inverse_dynamics_derivatives(&JointTrig::new(q), qd, qdd));
            },
        );
        cycle(
            c,
            &g("aba_derivatives"),
            "generated_avx2_lanes",
            &fixed,
            |[q, qd, _, tau]| {
                black_box(R::forward_dynamics_derivatives(&JointTrig::new(q), qd, tau));
            },
        );
        dyngen_runtime::__private::set_avx512_lanes(true);
    }
}

fn forward_dynamics(c: &mut Criterion) {
    bench_robot::<Panda, 7, 70>(c, "panda");
    bench_robot::<PandaRounded, 7, 70>(c, "panda_rounded");
    bench_robot::<Ur5, 6, 60>(c, "ur5");
    bench_robot::<Arm7, 7, 70>(c, "arm7");
    bench_robot::<Xarm7, 7, 70>(c, "xarm7");
    bench_robot::<Xarm7Snapped, 7, 70>(c, "xarm7_snapped");
}

/// Instruction-cache footprint. Each call above runs one function in a loop, and a function of
/// up to about 30 KB of code then stays in the 32 KB level-1 instruction cache. Here the
/// Panda's `∂τ/∂x` (about 30 KB) runs twice per state: twice the same code, then once the
/// Panda's and once the rounded Panda's (the same operations, a second copy: 60 KB between
/// them), whose code has to come from the level-2 cache on every call
/// (`docs/performance-notes.md`, *Code size*).
fn code_footprint(c: &mut Criterion) {
    let (_, fixed) = states::<7>(0xfd5eed, [(-2.0, 2.0), (-5.0, 5.0), (-10.0, 10.0)]);
    let group = "footprint/rnea_derivatives_twice";
    cycle(c, group, "same_function", &fixed, |[q, qd, qdd, _]| {
        let t = JointTrig::new(q);
        black_box(Panda::inverse_dynamics_derivatives(&t, qd, qdd));
        black_box(Panda::inverse_dynamics_derivatives(&t, qd, qdd));
    });
    cycle(c, group, "two_copies", &fixed, |[q, qd, qdd, _]| {
        let t = JointTrig::new(q);
        black_box(Panda::inverse_dynamics_derivatives(&t, qd, qdd));
        black_box(PandaRounded::inverse_dynamics_derivatives(&t, qd, qdd));
    });
}

criterion_group! {
    name = benches;
    config = common::config();
    targets = forward_dynamics, code_footprint
}
criterion_main!(benches);
