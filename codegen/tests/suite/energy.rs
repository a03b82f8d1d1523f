//! The energy regressors against oracles that use no energy code: `e_T·θ = ½ q̇ᵀ D q̇`, the
//! gradient of `e_V·θ` by central differences against `g(q)`, and the power balance
//! `d(e_T + e_V)/dt·θ + e_P·θ = q̇ᵀ τ` along a motion, by differences of the energy in time;
//! on the reference arms with every joint term and on random trees (mimic joints included).

use dyngen_testkit as common;

use common::joint_terms::with_joint_terms;
use common::random_model::{arb_model_and_state, deterministic_runner, random_state};
use dyngen_codegen::description::load;
use dyngen_codegen::dynamics::NumericDynamics;
use dyngen_codegen::model::Model;
use std::path::Path;

fn robot(name: &str) -> Model {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../robots")
        .join(format!("{name}.yaml"));
    load(&path).unwrap_or_else(|e| panic!("{e}")).model
}

/// Largest relative mismatch of the three identities at one state, relative to the size of
/// the terms compared.
fn check(model: &Model, seed: u64) -> (f64, f64, f64) {
    let dynamics = NumericDynamics::new(model);
    let theta = nalgebra::DVector::from_vec(model.parameters());
    let s = random_state(model, seed);

    let kinetic = dynamics.kinetic_energy_regressor(&s.q, &s.qd).dot(&theta);
    let qd = nalgebra::DVector::from_column_slice(&s.qd);
    let expected = 0.5 * qd.dot(&(dynamics.mass_matrix(&s.q) * &qd));
    let kinetic_error = (kinetic - expected).abs() / expected.abs().max(1e-12);

    let potential = |q: &[f64]| dynamics.potential_energy_regressor(q).dot(&theta);
    let g = dynamics.gravity_torque(&s.q);
    let h = 1e-6;
    let mut gradient_error = 0.0f64;
    for j in 0..model.dof() {
        let (mut up, mut down) = (s.q.clone(), s.q.clone());
        up[j] += h;
        down[j] -= h;
        let d = (potential(&up) - potential(&down)) / (2.0 * h);
        gradient_error = gradient_error.max((d - g[j]).abs() / g.amax().max(1e-9));
    }

    // Along q(t) = q + q̇ t + ½ q̈ t², the energy's rate by a fourth-order central difference.
    let energy_at = |t: f64| {
        let q: Vec<f64> = (0..s.q.len())
            .map(|j| s.q[j] + s.qd[j] * t + 0.5 * s.qdd[j] * t * t)
            .collect();
        let qd: Vec<f64> = (0..s.qd.len()).map(|j| s.qd[j] + s.qdd[j] * t).collect();
        dynamics.energy_regressor(&q, &qd).dot(&theta)
    };
    let dt = 1e-4;
    let rate = (energy_at(-2.0 * dt) - 8.0 * energy_at(-dt) + 8.0 * energy_at(dt) - energy_at(2.0 * dt))
        / (12.0 * dt);
    let tau = dynamics.inverse_dynamics(&s.q, &s.qd, &s.qdd);
    let power = qd.dot(&tau);
    let dissipated = dynamics.joint_term_power_regressor(&s.qd).dot(&theta);
    let size = power.abs().max(dissipated.abs()).max(rate.abs()).max(1e-9);
    let balance_error = (rate + dissipated - power).abs() / size;
    (kinetic_error, gradient_error, balance_error)
}

#[test]
fn energy_regressors_on_the_reference_arms_with_joint_terms() {
    for name in ["arm7", "panda", "ur5"] {
        for smoothing in [None, Some(0.05)] {
            let model = with_joint_terms(robot(name), smoothing, 3);
            for seed in 0..8 {
                let (kinetic, gradient, balance) = check(&model, seed);
                assert!(kinetic < 1e-12, "{name}, seed {seed}: kinetic {kinetic:.2e}");
                assert!(gradient < 1e-7, "{name}, seed {seed}: ∂V/∂q {gradient:.2e}");
                assert!(balance < 1e-7, "{name}, seed {seed}: power balance {balance:.2e}");
            }
        }
    }
}

#[test]
fn energy_regressors_on_random_trees() {
    let count = std::cell::Cell::new(0);
    let result = deterministic_runner(64).run(&arb_model_and_state(6), |(model, _)| {
        for seed in 0..2 {
            let (kinetic, gradient, balance) = check(&model, seed);
            assert!(kinetic < 1e-11, "kinetic {kinetic:.2e}");
            assert!(gradient < 1e-6, "∂V/∂q {gradient:.2e}");
            assert!(balance < 1e-6, "power balance {balance:.2e}");
        }
        count.set(count.get() + 1);
        Ok(())
    });
    if let Err(e) = result {
        panic!("{e}");
    }
    assert_eq!(count.get(), 64);
}
