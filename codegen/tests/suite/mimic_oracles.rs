//! Mimic joints against what uses no coupled algorithm: the oracles of `tests/testkit/src/oracles.rs`
//! (finite differences, the Lagrangian from differenced link poses, Christoffel symbols of
//! differenced `D`, `C + Cᵀ = Ḋ`), the same tree without coupling carried through a `G` built
//! here (`D = Gᵀ D_tree G`, …), and the traced graph (interpreted) against the generic code; on
//! the two mimic robots of the fixtures and on random trees with random couplings.

use dyngen_testkit as common;

use common::oracles::{assert_passed, check_all};
use common::random_model::{arb_model, deterministic_runner, random_state, with_random_mimics, JointState};
use common::{assert_close, column, traced};
use dyngen_codegen::dynamics::NumericDynamics;
use dyngen_codegen::internals::generate::{trace, SymbolicRobot};
use dyngen_codegen::model::Model;
use nalgebra::{DMatrix, DVector};
use proptest::prelude::*;
use std::path::Path;

fn load(yaml: &str) -> Model {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/mimic")
        .join(yaml);
    dyngen_codegen::description::load(&path)
        .unwrap_or_else(|e| panic!("{e}"))
        .model
}

/// `G` and `o` of `q_tree = G q + o`, from the model's mimic list alone.
fn coupling(model: &Model) -> (DMatrix<f64>, DVector<f64>) {
    let coordinates = model.coordinate_joints();
    let n = model.joints().len();
    let mut g = DMatrix::zeros(n, coordinates.len());
    let mut o = DVector::zeros(n);
    for j in 0..n {
        match model.mimics()[j] {
            None => g[(j, coordinates.iter().position(|&k| k == j).unwrap())] = 1.0,
            Some(m) => {
                g[(j, coordinates.iter().position(|&k| k == m.master).unwrap())] = m.multiplier;
                o[j] = m.offset;
            }
        }
    }
    (g, o)
}

fn vec(x: &DVector<f64>) -> Vec<f64> {
    x.as_slice().to_vec()
}

/// Every coupled quantity against the uncoupled tree at `q_tree = G q + o`, `q̇_tree = G q̇`, …
fn check_against_tree(model: &Model, s: &JointState) {
    let tree_model = model
        .clone()
        .with_mimics(vec![None; model.joints().len()])
        .unwrap();
    let (g, o) = coupling(model);
    let (coupled, tree) = (NumericDynamics::new(model), NumericDynamics::new(&tree_model));
    let x = |v: &[f64]| vec(&(&g * DVector::from_column_slice(v)));
    let (q, qd, v, a) = (
        vec(&(&g * DVector::from_column_slice(&s.q) + &o)),
        x(&s.qd),
        x(&s.v),
        x(&s.a),
    );
    let at = |what: &str| format!("{}: {what} = tree through G", model.name());
    let gt = g.transpose();
    const TOL: f64 = 1e-12;
    assert_close(&at("J"), &coupled.jacobian(&s.q), &(tree.jacobian(&q) * &g), TOL);
    assert_close(
        &at("J̇"),
        &coupled.jacobian_dot(&s.q, &s.qd),
        &(tree.jacobian_dot(&q, &qd) * &g),
        TOL,
    );
    assert_close(
        &at("D"),
        &coupled.mass_matrix(&s.q),
        &(&gt * tree.mass_matrix(&q) * &g),
        TOL,
    );
    let c = coupled.coriolis_matrix(&s.q, &s.qd);
    assert_close(&at("C"), &c, &(&gt * tree.coriolis_matrix(&q, &qd) * &g), TOL);
    let g_coupled = coupled.gravity_torque(&s.q);
    assert_close(
        &at("g"),
        &column(g_coupled.as_slice()),
        &column((&gt * tree.gravity_torque(&q)).as_slice()),
        TOL,
    );
    let tau = coupled.inverse_dynamics(&s.q, &s.qd, &s.qdd);
    let tau_tree = tree.inverse_dynamics(&q, &qd, &x(&s.qdd));
    assert_close(
        &at("τ"),
        &column(tau.as_slice()),
        &column((&gt * tau_tree).as_slice()),
        TOL,
    );
    let y = coupled.regressor(&s.q, &s.qd, &s.v, &s.a);
    assert_close(&at("Y"), &y, &(&gt * tree.regressor(&q, &qd, &v, &a)), TOL);
    assert_eq!(model.parameters(), tree_model.parameters(), "θ unchanged");
    // Forward dynamics solves the coupled equations of motion.
    let qdd = coupled.forward_dynamics(&s.q, &s.qd, tau.as_slice());
    assert_close(&at("FD(τ)"), &column(qdd.as_slice()), &column(&s.qdd), 1e-9);
}

/// The traced graph of every quantity, evaluated, against the generic code.
fn check_traced(model: &Model, robot: &SymbolicRobot, s: &JointState) {
    let generic = NumericDynamics::new(model);
    let n = model.dof();
    let col = |x: DVector<f64>| DMatrix::from_column_slice(n, 1, x.as_slice());
    let pair = |(a, b): (DMatrix<f64>, DMatrix<f64>)| {
        let mut m = DMatrix::zeros(n, 2 * n);
        m.columns_mut(0, n).copy_from(&a);
        m.columns_mut(n, n).copy_from(&b);
        m
    };
    let (q, qd, v, a) = (&s.q[..], &s.qd[..], &s.v[..], &s.a[..]);
    let tau = generic.inverse_dynamics(q, qd, a);
    let mut expected = traced::generic_values(robot, &generic, [q, qd, v, a]);
    expected.push((
        "inverse_dynamics_derivatives",
        pair(generic.inverse_dynamics_derivatives(q, qd, a)),
    ));
    for (name, want) in expected {
        let got = traced::shaped(robot, name, robot.evaluate(name, q, qd, v, a).unwrap());
        assert_close(&format!("{} traced {name}", model.name()), &got, &want, 1e-10);
    }
    let forward = [
        (
            "forward_dynamics",
            col(generic.forward_dynamics(q, qd, tau.as_slice())),
        ),
        ("mass_matrix_inverse", generic.mass_matrix_inverse(q)),
        (
            "forward_dynamics_derivatives",
            pair(generic.forward_dynamics_derivatives(q, qd, tau.as_slice())),
        ),
    ];
    for (name, want) in forward {
        let got = traced::shaped(
            robot,
            name,
            robot.evaluate_tau(name, q, qd, tau.as_slice()).unwrap(),
        );
        assert_close(&format!("{} traced {name}", model.name()), &got, &want, 1e-9);
    }
}

fn check_robot(model: &Model, states: u64) {
    let robot = trace(model);
    for seed in 0..states {
        let s = random_state(model, seed);
        assert_passed(
            &format!("{} at seed {seed}, {s:?}", model.name()),
            &check_all(model, &NumericDynamics::new(model), &s),
        );
        check_against_tree(model, &s);
        check_traced(model, &robot, &s);
    }
}

#[test]
fn mimic_arm_oracles_tree_and_trace() {
    check_robot(&load("mimic_arm.yaml"), 12);
}

#[test]
fn panda_with_free_fingers_oracles_tree_and_trace() {
    check_robot(&load("panda_mimic.yaml"), 4);
}

/// Random trees (branches, prismatic joints, skew axes) with random couplings, across
/// branches and of either kind of joint.
#[test]
fn random_trees_with_mimic_joints() {
    let coupled = std::cell::Cell::new(0);
    let result = deterministic_runner(40).run(&(arb_model(6), any::<u64>()), |(model, seed)| {
        let model = with_random_mimics(model, seed);
        coupled.set(coupled.get() + usize::from(model.has_mimics()));
        let s = random_state(&model, seed);
        assert_passed(
            &format!("{} {s:?}", model.name()),
            &check_all(&model, &NumericDynamics::new(&model), &s),
        );
        check_against_tree(&model, &s);
        check_traced(&model, &trace(&model), &s);
        Ok(())
    });
    if let Err(e) = result {
        panic!("{e}");
    }
    let coupled = coupled.get();
    assert!(
        coupled >= 20,
        "most random trees get a mimic joint ({coupled} of 40)"
    );
}
