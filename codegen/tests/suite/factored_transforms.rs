//! Joint transforms kept as two factors, the constant placement and then the joint's own motion,
//! which the generator uses for `D`, `τ`, forward dynamics, `D⁻¹` and the derivatives where a
//! placement is tilted:
//! on random trees (branches, prismatic and mimic joints, skew axes, tilted placements) they
//! are the multiplied-out transforms, and every algorithm run through them gives the same
//! values.

use dyngen_testkit as common;

use common::random_model::{arb_model_and_state, deterministic_runner};
use common::{assert_close, column};
use dyngen_codegen::internals::dynamics::{
    body_inertias, forward_dynamics, forward_dynamics_derivatives_by, inverse_dynamics,
    inverse_dynamics_derivatives_by, joint_factored_transforms, joint_term_values, joint_transforms,
    mass_matrix, mass_matrix_inverse, Directions, Placements,
};
use std::cell::Cell;

const TOL: f64 = 1e-10;

#[test]
fn factored_transforms_are_the_joint_transforms_and_give_the_same_dynamics() {
    let models = Cell::new(0);
    let result = deterministic_runner(200).run(&arb_model_and_state(8), |(model, s)| {
        let plain = joint_transforms::<f64>(&model, &s.q);
        let factored = joint_factored_transforms::<f64>(&model, &s.q);
        for (k, (x, f)) in plain.iter().zip(&factored).enumerate() {
            let product = f.outer.compose(&f.inner);
            for r in 0..3 {
                for c in 0..3 {
                    let (a, b) = (x.rot.0[r][c], product.rot.0[r][c]);
                    assert!((a - b).abs() < 1e-14, "joint {k} rotation ({r}, {c}): {a} vs {b}");
                }
                let (a, b) = (x.pos.0[r], product.pos.0[r]);
                assert!((a - b).abs() < 1e-14, "joint {k} position {r}: {a} vs {b}");
            }
        }
        let inertias = body_inertias::<f64>(&model);
        let jv = joint_term_values(&model);
        assert_close(
            "D",
            &mass_matrix(&model, &factored, &inertias),
            &mass_matrix(&model, &plain, &inertias),
            TOL,
        );
        assert_close(
            "τ",
            &column(&inverse_dynamics(&model, &factored, &inertias, &s.qd, &s.qdd)),
            &column(&inverse_dynamics(&model, &plain, &inertias, &s.qd, &s.qdd)),
            TOL,
        );
        // Torques of a few N·m, so the accelerations are of the usual size.
        let tau: Vec<f64> = s.a.iter().map(|t| 10.0 * t).collect();
        assert_close(
            "q̈",
            &column(&forward_dynamics(&model, &factored, &inertias, &jv, &s.qd, &tau)),
            &column(&forward_dynamics(&model, &plain, &inertias, &jv, &s.qd, &tau)),
            TOL,
        );
        assert_close(
            "D⁻¹",
            &mass_matrix_inverse(&model, &factored, &inertias, &jv),
            &mass_matrix_inverse(&model, &plain, &inertias, &jv),
            TOL,
        );
        // The derivatives carry their tangents through seeded frames of either form (a
        // prismatic joint's origin moves with its coordinate in both).
        for directions in [Directions::OneByOne, Directions::Lanes] {
            let through = |placements| {
                let at = (&model, &s.q[..], &inertias[..], &jv[..], &s.qd[..]);
                let inverse = inverse_dynamics_derivatives_by(
                    directions, placements, at.0, at.1, at.2, at.3, at.4, &s.qdd,
                );
                let forward = forward_dynamics_derivatives_by(
                    directions, placements, at.0, at.1, at.2, at.3, at.4, &tau,
                );
                [inverse.0, inverse.1, forward.0, forward.1]
            };
            let (factored, plain) = (through(Placements::Factored), through(Placements::Multiplied));
            for (name, (f, p)) in ["∂τ/∂q", "∂τ/∂q̇", "∂q̈/∂q", "∂q̈/∂q̇"]
                .iter()
                .zip(factored.iter().zip(&plain))
            {
                assert_close(&format!("{name} ({directions:?})"), f, p, TOL);
            }
        }
        models.set(models.get() + 1);
        Ok(())
    });
    if let Err(e) = result {
        panic!("{e}");
    }
    assert_eq!(models.get(), 200, "every random tree was checked");
}
