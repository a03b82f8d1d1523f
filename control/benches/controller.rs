//! One full control tick of the adaptive hybrid force/position controller on arm7: joint
//! trigonometry, FK, J, J̇, projections with the singularity guard, q̇_r, q̈_r, the regressor
//! Y(q, q̇, q̇_r, q̈_r), τ = Jᵀ F̄ + Y θ̂ − G r and the adaptation step θ̂ += −Γ Yᵀ r dt.
//! Inputs cycle through 256 states of the demo's closed-loop run.
//! `cargo bench --bench controller`
//!
//! Measured on the base parameters (the default) and on the standard ones, and with the task
//! dimension 6 (position and orientation) on the base parameters.

use criterion::{criterion_group, criterion_main, Criterion};
use dyngen_control::controller::{Desired, Measurement};
use dyngen_control::sim::{rk4_step, start_posture, Demo, DemoOptions, PlantState, RunKind};
use dyngen_generated::{arm7, Arm7};
use dyngen_runtime::nalgebra::SVector;
use dyngen_runtime::{JointTrig, Kinematics, Parameterization};
use std::hint::black_box;
use std::time::Duration;

fn ticks(c: &mut Criterion) {
    tick::<arm7::Base, { arm7::BASE_PARAMETER_COUNT }, 3>(c, "base_parameters");
    tick::<arm7::Standard, { arm7::PARAMETER_COUNT }, 3>(c, "standard_parameters");
    tick::<arm7::Base, { arm7::BASE_PARAMETER_COUNT }, 6>(c, "base_parameters_pose_task");
}

fn tick<Z: Parameterization<{ arm7::DOF }, M>, const M: usize, const T: usize>(
    c: &mut Criterion,
    parameters: &str,
) {
    let q0 = start_posture("arm7").expect("arm7 start posture");
    let demo = Demo::<Z, { arm7::DOF }, M, T>::new(DemoOptions::default(), q0).expect("demo");
    // 256 realistic inputs: states of the closed loop along the scenario (every 40 ms).
    let mut ctrl = demo.controller(RunKind::Adaptive).expect("controller");
    let mut state = PlantState {
        q: q0,
        qd: SVector::zeros(),
    };
    let mut inputs: Vec<(
        Measurement<{ arm7::DOF }>,
        Desired<{ arm7::DOF }, 1>,
        SVector<f64, M>,
    )> = Vec::new();
    let dt = 1e-3;
    let mut tau = SVector::zeros();
    for k in 0..(256 * 40) {
        let t = k as f64 * dt;
        let m = Measurement {
            q: state.q,
            qd: state.qd,
            force: demo.plant.contact_force(&state, &tau).expect("plant"),
        };
        let d = demo.scenario.desired(t);
        if k % 40 == 0 {
            inputs.push((m, d, *ctrl.theta_hat()));
        }
        tau = ctrl.tick(&m, &d, dt).expect("tick").tau;
        state = rk4_step(t, &state, dt, |_, s| demo.plant.derivative(s, &tau)).expect("plant");
    }
    let mut ctrl = demo.controller(RunKind::Adaptive).expect("controller");
    let mut k = 0;
    c.bench_function(&format!("arm7/control_tick/adaptive_{parameters}"), |b| {
        b.iter(|| {
            k = (k + 1) % inputs.len();
            let (m, d, theta) = &inputs[k];
            ctrl.set_theta_hat(*theta);
            black_box(ctrl.tick(black_box(m), black_box(d), dt).map(|o| o.tau))
        })
    });
}

/// Where the time of a tick goes: the generated quantities it calls, alone.
fn parts(c: &mut Criterion) {
    let q0 = start_posture::<{ arm7::DOF }>("arm7").expect("arm7 start posture");
    let qd = SVector::<f64, 7>::from_element(0.2);
    let mut g = c.benchmark_group("arm7/control_tick_parts");
    g.bench_function("trig+fk+J+Jdot", |b| {
        b.iter(|| {
            let t = JointTrig::new(black_box(&q0));
            black_box((
                Arm7::forward_kinematics(&t),
                Arm7::jacobian(&t),
                Arm7::jacobian_dot(&t, black_box(&qd)),
            ))
        })
    });
    // What the tick calls: the three in one generated function sharing their transforms.
    g.bench_function("trig+kinematics (fused)", |b| {
        b.iter(|| {
            let t = JointTrig::new(black_box(&q0));
            black_box(Arm7::kinematics(&t, black_box(&qd)))
        })
    });
    let t = JointTrig::new(&q0);
    g.bench_function("base_regressor", |b| {
        b.iter(|| black_box(arm7::Base::regressor(black_box(&t), &qd, &qd, &qd)))
    });
    let (theta, r) = (arm7::Base::description(), SVector::<f64, 7>::from_element(0.1));
    g.bench_function("base_regressor_products", |b| {
        b.iter(|| {
            black_box(arm7::Base::regressor_products(
                black_box(&t),
                &qd,
                &qd,
                &qd,
                &theta,
                &r,
            ))
        })
    });
    g.bench_function("regressor", |b| {
        b.iter(|| black_box(arm7::Standard::regressor(black_box(&t), &qd, &qd, &qd)))
    });
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(3))
        .sample_size(60);
    targets = ticks, parts
}
criterion_main!(benches);
