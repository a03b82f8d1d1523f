//! Forward dynamics, `D⁻¹` and the derivatives of the dynamics on 200 random trees (branches,
//! prismatic joints, skew axes, tilted gravity), through the traced graph that the generated code
//! is printed from (evaluated by the interpreter): against the generic f64 algorithms, and
//! against oracles that use none of our algorithms twice (`D⁻¹ D = I`, `FD(ID(q̈)) = q̈`, central
//! differences of the traced `τ` and `q̈`).

use dyngen_testkit as common;

use common::oracles::jacobian_by_differences;
use common::random_model::{arb_model_and_state, deterministic_runner};
use common::{assert_close, column};
use dyngen_codegen::dynamics::NumericDynamics;
use dyngen_codegen::internals::generate::{trace, SymbolicRobot};
use dyngen_codegen::model::Model;
use nalgebra::DMatrix;
use std::cell::Cell;

const TOL_GENERIC: f64 = 1e-10;
const TOL_IDENTITY: f64 = 1e-9;
const TOL_DIFFERENCE: f64 = 1e-7;
/// See `tests/generated_forward_dynamics.rs`: `q̈(q)` needs a smaller step than the 1e-2 of
/// `common::oracles`.
const STEP: f64 = 1e-3;

fn matrix(values: Vec<f64>, rows: usize) -> DMatrix<f64> {
    let cols = values.len() / rows;
    DMatrix::from_column_slice(rows, cols, &values)
}

/// The Jacobian of `f` at `x` by extrapolated central differences.
fn differenced(f: impl Fn(&[f64]) -> DMatrix<f64>, x: &[f64]) -> DMatrix<f64> {
    jacobian_by_differences(f, x, STEP)
}

fn check(model: &Model, robot: &SymbolicRobot, q: &[f64], qd: &[f64], qdd: &[f64]) {
    let n = model.dof();
    let generic = NumericDynamics::new(model);
    let none: &[f64] = &[];
    let tau_of =
        |q: &[f64], qd: &[f64]| matrix(robot.evaluate("inverse_dynamics", q, qd, none, qdd).unwrap(), n);
    let tau = tau_of(q, qd);
    let fd_of = |q: &[f64], qd: &[f64]| {
        matrix(
            robot
                .evaluate_tau("forward_dynamics", q, qd, tau.as_slice())
                .unwrap(),
            n,
        )
    };
    let at = |what: &str| format!("{} ({n} joints): {what}", model.name());

    // The traced graph against the generic algorithms.
    let qdd_traced = fd_of(q, qd);
    let generic_fd = generic.forward_dynamics(q, qd, tau.as_slice());
    assert_close(&at("q̈"), &qdd_traced, &column(generic_fd.as_slice()), TOL_GENERIC);
    let minv = matrix(
        robot
            .evaluate("mass_matrix_inverse", q, none, none, none)
            .unwrap(),
        n,
    );
    assert_close(&at("D⁻¹"), &minv, &generic.mass_matrix_inverse(q), TOL_GENERIC);
    let id_d = matrix(
        robot
            .evaluate("inverse_dynamics_derivatives", q, qd, none, qdd)
            .unwrap(),
        n,
    );
    let (gq, gv) = generic.inverse_dynamics_derivatives(q, qd, qdd);
    assert_close(&at("∂τ/∂(q, q̇)"), &id_d, &concat(&gq, &gv), TOL_GENERIC);
    let fd_d = matrix(
        robot
            .evaluate_tau("forward_dynamics_derivatives", q, qd, tau.as_slice())
            .unwrap(),
        n,
    );
    let (gq, gv) = generic.forward_dynamics_derivatives(q, qd, tau.as_slice());
    assert_close(&at("∂q̈/∂(q, q̇)"), &fd_d, &concat(&gq, &gv), TOL_GENERIC);

    // Oracles.
    let d = matrix(robot.evaluate("mass_matrix", q, none, none, none).unwrap(), n);
    assert_close(
        &at("D⁻¹ D = I"),
        &(&minv * d),
        &DMatrix::identity(n, n),
        TOL_IDENTITY,
    );
    assert_close(&at("FD(ID(q̈)) = q̈"), &qdd_traced, &column(qdd), TOL_IDENTITY);
    let num = concat(
        &differenced(|x| tau_of(x, qd), q),
        &differenced(|x| tau_of(q, x), qd),
    );
    assert_close(&at("∂τ/∂(q, q̇) vs differenced τ"), &id_d, &num, TOL_DIFFERENCE);
    let num = concat(
        &differenced(|x| fd_of(x, qd), q),
        &differenced(|x| fd_of(q, x), qd),
    );
    assert_close(&at("∂q̈/∂(q, q̇) vs differenced q̈"), &fd_d, &num, TOL_DIFFERENCE);
}

fn concat(a: &DMatrix<f64>, b: &DMatrix<f64>) -> DMatrix<f64> {
    let n = a.nrows();
    DMatrix::from_fn(n, 2 * n, |i, j| if j < n { a[(i, j)] } else { b[(i, j - n)] })
}

#[test]
fn random_trees_forward_dynamics_and_derivatives() {
    let models = Cell::new(0);
    let result = deterministic_runner(200).run(&arb_model_and_state(10), |(model, s)| {
        let robot = trace(&model);
        check(&model, &robot, &s.q, &s.qd, &s.qdd);
        models.set(models.get() + 1);
        Ok(())
    });
    if let Err(e) = result {
        panic!("{e}");
    }
    assert_eq!(models.get(), 200, "every random tree was checked");
}
