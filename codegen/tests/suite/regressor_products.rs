//! `Y θ` and `Yᵀ r` without forming `Y` (`dynamics::regressor_products`, the adaptive law's
//! products) against the two products of the regressor itself, on the reference arms, an arm
//! with joint friction and armature, an arm with mimic joints and random trees (prismatic
//! joints, branches and joint terms included), for every column and for the base columns.

use dyngen_testkit as common;

use common::joint_terms::with_joint_terms;
use common::random_model::{arb_model_and_state, deterministic_runner, random_state, SplitMix64};
use dyngen_codegen::base_parameters::BaseParameterSet;
use dyngen_codegen::description::load;
use dyngen_codegen::internals::dynamics::{joint_transforms, regressor, regressor_products};
use dyngen_codegen::model::Model;
use nalgebra::{DMatrix, DVector};
use std::path::Path;

fn robot(file: &str) -> Model {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("..").join(file);
    load(&path).unwrap_or_else(|e| panic!("{e}")).model
}

/// The largest difference of the two ways, relative to the size of the products.
fn worst_difference(
    model: &Model,
    q: &[f64],
    qd: &[f64],
    v: &[f64],
    a: &[f64],
    cols: &[usize],
    seed: u64,
) -> f64 {
    let mut rng = SplitMix64::new(seed);
    let theta: Vec<f64> = cols.iter().map(|_| rng.uniform((-2.0, 2.0))).collect();
    let r: Vec<f64> = (0..model.dof()).map(|_| rng.uniform((-1.0, 1.0))).collect();
    let x = joint_transforms(model, q);
    let y = regressor(model, &x, qd, v, a).select_columns(cols);
    let y_theta = &y * DVector::from_column_slice(&theta);
    let y_tr_r = y.tr_mul(&DVector::from_column_slice(&r));
    let (fast_y_theta, fast_y_tr_r) = regressor_products(model, &x, qd, v, a, cols, &theta, &r);
    assert_eq!((fast_y_theta.len(), fast_y_tr_r.len()), (model.dof(), cols.len()));
    let scale = 1.0 + y.amax() * (1.0 + theta.iter().fold(0.0f64, |m, t| m.max(t.abs())));
    let diff = |a: &[f64], b: &DVector<f64>| {
        a.iter()
            .zip(b.iter())
            .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
    };
    diff(&fast_y_theta, &y_theta).max(diff(&fast_y_tr_r, &y_tr_r)) / scale
}

fn check(model: &Model, states: u64) {
    let all: Vec<usize> = (0..model.parameter_count()).collect();
    let base = BaseParameterSet::compute(model);
    for seed in 0..states {
        let s = random_state(model, seed);
        for cols in [&all, &base.columns] {
            let e = worst_difference(model, &s.q, &s.qd, &s.v, &s.a, cols, seed);
            assert!(
                e < 1e-12,
                "{}: relative difference {e:e} at seed {seed}",
                model.name()
            );
        }
    }
}

#[test]
fn reference_arms() {
    for file in ["robots/arm7.yaml", "robots/panda.yaml", "robots/ur5.yaml"] {
        check(&robot(file), 16);
    }
}

#[test]
fn joint_friction_and_armature() {
    let arm = robot("robots/arm7_friction.yaml");
    assert!(!arm.joint_terms().kinds.is_empty(), "the arm chooses joint terms");
    check(&arm, 16);
    check(&with_joint_terms(robot("robots/ur5.yaml"), None, 3), 8);
}

#[test]
fn mimic_joints() {
    let arm = robot("codegen/tests/data/mimic/mimic_arm.urdf");
    assert!(arm.has_mimics(), "the arm has mimic joints");
    check(&arm, 16);
}

/// A product that mixed up two columns, or dropped the joint terms, is caught.
#[test]
fn a_wrong_column_is_caught() {
    let model = robot("robots/arm7.yaml");
    let s = random_state(&model, 1);
    let x = joint_transforms(&model, &s.q);
    let cols: Vec<usize> = (0..model.parameter_count()).collect();
    let mut swapped = cols.clone();
    swapped.swap(3, 14);
    let r = vec![0.5; model.dof()];
    let theta = vec![1.0; cols.len()];
    let (_, right) = regressor_products(&model, &x, &s.qd, &s.v, &s.a, &cols, &theta, &r);
    let (_, wrong) = regressor_products(&model, &x, &s.qd, &s.v, &s.a, &swapped, &theta, &r);
    let y: DMatrix<f64> = regressor(&model, &x, &s.qd, &s.v, &s.a);
    let y_tr_r = y.tr_mul(&DVector::from_element(model.dof(), 0.5));
    assert!((right[3] - y_tr_r[3]).abs() < 1e-12 * (1.0 + y_tr_r[3].abs()));
    assert!((wrong[3] - y_tr_r[3]).abs() > 1e-6, "column 14 is not column 3");
}

#[test]
fn random_trees_with_joint_terms() {
    let mut runner = deterministic_runner(120);
    runner
        .run(&arb_model_and_state(7), |(model, s)| {
            let model = with_joint_terms(model, Some(0.05), s.q.len() as u64);
            let all: Vec<usize> = (0..model.parameter_count()).collect();
            let base = BaseParameterSet::compute(&model);
            for cols in [&all, &base.columns] {
                let e = worst_difference(&model, &s.q, &s.qd, &s.v, &s.a, cols, 7);
                assert!(e < 1e-12, "relative difference {e:e} on {model:?}");
            }
            Ok(())
        })
        .expect("every tree");
}
