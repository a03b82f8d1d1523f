//! The regressor by the bodies' Jacobians, which generation keeps where it costs fewer
//! operations, gives the regressor of the usual recursion: on random trees, on a robot with
//! joint friction and armature, and on robots with mimic joints.

use dyngen_codegen::internals::dynamics::{joint_transforms, regressor, regressor_by_jacobians};
use dyngen_codegen::model::Model;
use dyngen_testkit::random_model::{arb_model_and_state, deterministic_runner, random_state};
use nalgebra::DMatrix;
use proptest::prelude::*;
use std::path::Path;

const TOL: f64 = 1e-10;

fn both(model: &Model, q: &[f64], qd: &[f64], v: &[f64], a: &[f64]) -> (DMatrix<f64>, DMatrix<f64>) {
    let x = joint_transforms(model, q);
    (
        regressor(model, &x, qd, v, a),
        regressor_by_jacobians(model, &x, qd, v, a),
    )
}

fn difference(usual: &DMatrix<f64>, by_jacobians: &DMatrix<f64>) -> f64 {
    (usual - by_jacobians).amax() / usual.amax().max(1.0)
}

#[test]
fn equal_on_random_trees() {
    deterministic_runner(64)
        .run(&arb_model_and_state(8), |(model, s)| {
            let (usual, by_jacobians) = both(&model, &s.q, &s.qd, &s.v, &s.a);
            let e = difference(&usual, &by_jacobians);
            prop_assert!(e <= TOL, "{}: difference {e:.2e}", model.name());
            Ok(())
        })
        .unwrap();
}

#[test]
fn equal_with_joint_terms_and_mimic_joints() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    for path in [
        "../robots/arm7_friction.yaml",
        "tests/data/mimic/mimic_arm.yaml",
        "tests/data/mimic/panda_mimic.yaml",
    ] {
        let model = dyngen_codegen::description::load(&root.join(path))
            .unwrap_or_else(|e| panic!("{e}"))
            .model;
        for seed in 0..8 {
            let s = random_state(&model, seed);
            let (usual, by_jacobians) = both(&model, &s.q, &s.qd, &s.v, &s.a);
            let e = difference(&usual, &by_jacobians);
            assert!(e <= TOL, "{path}: difference {e:.2e}");
        }
    }
}
