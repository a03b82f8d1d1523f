//! The generic dynamics against oracles that trust no dynamics algorithm (see
//! `common/oracles.rs`): the reference arms at fixed-seed random states, a few hundred random
//! kinematic trees, and a check that the oracles do catch a 1e-6 relative error.
//!
//! `cargo test -p dyngen-codegen --test suite oracles:: -- --nocapture` prints the worst error of every check against its
//! tolerance.

use dyngen_testkit as common;

use common::fixture;
use common::oracles::{assert_passed, check_all, Check, Dynamics, Summary};
use common::random_model::{arb_model, arb_model_and_state, deterministic_runner, random_state};
use dyngen_codegen::dynamics::NumericDynamics;
use dyngen_codegen::model::{JointKind, Model};
use nalgebra::{DMatrix, DVector, Matrix3, Vector3};
use proptest::prelude::*;
use std::cell::RefCell;
use std::path::Path;

/// States per reference arm.
const STATES: u64 = 24;

fn check_robot(model: &Model) {
    let dynamics = NumericDynamics::new(model);
    let mut summary = Summary::default();
    for seed in 0..STATES {
        let state = random_state(model, seed);
        let checks = check_all(model, &dynamics, &state);
        assert_passed(&format!("{} at seed {seed}, {state:?}", model.name()), &checks);
        summary.record(&checks);
    }
    println!("{} ({STATES} states):\n{summary}", model.name());
}

#[test]
fn panda_oracles() {
    check_robot(&fixture::load("panda").model());
}

#[test]
fn panda_rounded_oracles() {
    check_robot(&fixture::load("panda_rounded").model());
}

#[test]
fn ur5_oracles() {
    check_robot(&fixture::load("ur5").model());
}

/// The iiwa-like arm as the YAML loader builds it: its inertias come from a real CAD export
/// (products of inertia, offset centres of mass), not from Pinocchio's fixtures.
#[test]
fn arm7_oracles() {
    let path = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../robots/arm7.yaml"));
    let loaded =
        dyngen_codegen::description::load(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    check_robot(&loaded.model);
}

/// Whether some joint does not hang from the joint before it (a branch or a second root).
fn is_branched(model: &Model) -> bool {
    model
        .joints()
        .iter()
        .enumerate()
        .any(|(i, j)| j.parent != i.checked_sub(1))
}

#[test]
fn random_tree_oracles() {
    let summary = RefCell::new(Summary::default());
    let coverage = RefCell::new([0usize; 4]); // models, branched models, joints, prismatic joints
    let result = deterministic_runner(256).run(&arb_model_and_state(10), |(model, state)| {
        let checks = check_all(&model, &NumericDynamics::new(&model), &state);
        summary.borrow_mut().record(&checks);
        let prismatic = model.joints().iter().filter(|j| j.kind == JointKind::Prismatic);
        let counts = [
            1,
            usize::from(is_branched(&model)),
            model.dof(),
            prismatic.count(),
        ];
        let mut coverage = coverage.borrow_mut();
        *coverage = std::array::from_fn(|k| coverage[k] + counts[k]);
        let failed: Vec<String> = checks
            .iter()
            .filter(|c| !c.passed())
            .map(|c| format!("  {c}"))
            .collect();
        prop_assert!(failed.is_empty(), "oracle checks failed:\n{}", failed.join("\n"));
        Ok(())
    });
    if let Err(e) = result {
        panic!("{e}");
    }
    let [models, branched, joints, prismatic] = *coverage.borrow();
    println!("random trees: {models} models ({branched} branched), {joints} joints ({prismatic} prismatic)");
    println!("{}", summary.borrow());
}

/// The generated trees satisfy the invariants the project relies on, so the oracles run on
/// models the project accepts: `arb_model` builds each through `Model::new`, which checks them
/// (and the strategy panics on a refusal), and each tree has one body per joint.
#[test]
fn random_trees_are_valid_models() {
    let result = deterministic_runner(256).run(&arb_model(10), |model| {
        prop_assert_eq!(model.joints().len(), model.bodies().len());
        prop_assert!(model.end_effector_body() < model.dof());
        Ok(())
    });
    if let Err(e) = result {
        panic!("{e}");
    }
}

/// Relative error injected to show that the tolerances are tight enough.
const INJECTED: f64 = 1e-6;

#[derive(Clone, Copy, Debug, PartialEq)]
enum Quantity {
    Jacobian,
    JacobianDot,
    MassMatrix,
    Coriolis,
    Gravity,
    InverseDynamics,
    Regressor,
}

/// The numeric dynamics with one quantity off by `INJECTED` relative: its largest entry scaled
/// by `1 + INJECTED` (an error of exactly `INJECTED` in the max norm the checks use).
struct Perturbed<'a> {
    inner: &'a NumericDynamics<'a>,
    target: Quantity,
}

impl Perturbed<'_> {
    fn matrix(&self, quantity: Quantity, mut m: DMatrix<f64>) -> DMatrix<f64> {
        if quantity == self.target {
            let k = m.iamax_full();
            m[k] *= 1.0 + INJECTED;
        }
        m
    }
    fn vector(&self, quantity: Quantity, mut v: DVector<f64>) -> DVector<f64> {
        if quantity == self.target {
            let k = v.iamax();
            v[k] *= 1.0 + INJECTED;
        }
        v
    }
}

impl Dynamics for Perturbed<'_> {
    fn end_effector_pose(&self, q: &[f64]) -> (Matrix3<f64>, Vector3<f64>) {
        self.inner.end_effector_pose(q)
    }
    fn jacobian(&self, q: &[f64]) -> DMatrix<f64> {
        self.matrix(Quantity::Jacobian, self.inner.jacobian(q))
    }
    fn jacobian_dot(&self, q: &[f64], qd: &[f64]) -> DMatrix<f64> {
        self.matrix(Quantity::JacobianDot, self.inner.jacobian_dot(q, qd))
    }
    fn mass_matrix(&self, q: &[f64]) -> DMatrix<f64> {
        self.matrix(Quantity::MassMatrix, self.inner.mass_matrix(q))
    }
    fn coriolis_matrix(&self, q: &[f64], qd: &[f64]) -> DMatrix<f64> {
        self.matrix(Quantity::Coriolis, self.inner.coriolis_matrix(q, qd))
    }
    fn gravity_torque(&self, q: &[f64]) -> DVector<f64> {
        self.vector(Quantity::Gravity, self.inner.gravity_torque(q))
    }
    fn inverse_dynamics(&self, q: &[f64], qd: &[f64], qdd: &[f64]) -> DVector<f64> {
        self.vector(Quantity::InverseDynamics, self.inner.inverse_dynamics(q, qd, qdd))
    }
    fn slotine_li(&self, q: &[f64], qd: &[f64], v: &[f64], a: &[f64], gravity: bool) -> DVector<f64> {
        self.inner.slotine_li(q, qd, v, a, gravity)
    }
    fn regressor(&self, q: &[f64], qd: &[f64], v: &[f64], a: &[f64]) -> DMatrix<f64> {
        self.matrix(Quantity::Regressor, self.inner.regressor(q, qd, v, a))
    }
    fn weightless_regressor(&self, q: &[f64], qd: &[f64], v: &[f64], a: &[f64]) -> DMatrix<f64> {
        self.matrix(Quantity::Regressor, self.inner.weightless_regressor(q, qd, v, a))
    }
}

/// Each quantity, off by 1e-6 relative, must fail the check that is its oracle.
#[test]
fn oracles_catch_a_1e6_relative_error() {
    let cases = [
        (Quantity::Jacobian, "J = ∂fk/∂q"),
        (Quantity::JacobianDot, "J̇ = dJ/dt"),
        (Quantity::MassMatrix, "Lagrange: D = ∂²T/∂q̇²"),
        (Quantity::Coriolis, "C = Christoffel(∂D/∂q)"),
        (Quantity::Coriolis, "C + Cᵀ = Ḋ"),
        (Quantity::Coriolis, "Lagrange: C q̇"),
        (Quantity::Gravity, "g = ∂V/∂q"),
        (Quantity::Gravity, "Lagrange: g"),
        (Quantity::InverseDynamics, "Lagrange: τ = ID(q, q̇, q̈)"),
        (Quantity::Regressor, "Y = Y_id,g(0, a) + ½[Y_id,0 …]"),
    ];
    for robot in ["panda", "ur5"] {
        let model = fixture::load(robot).model();
        let inner = NumericDynamics::new(&model);
        for seed in 100..104 {
            let state = random_state(&model, seed);
            for (target, name) in cases {
                let subject = Perturbed {
                    inner: &inner,
                    target,
                };
                let checks = check_all(&model, &subject, &state);
                let check: &Check = checks.iter().find(|c| c.name == name).expect("check exists");
                println!("{robot} seed {seed}: {target:?} off by {INJECTED:.0e} → {check}");
                assert!(
                    !check.passed(),
                    "{robot} seed {seed}: {target:?} off by {INJECTED:.0e} passed {check}"
                );
            }
        }
    }
}
