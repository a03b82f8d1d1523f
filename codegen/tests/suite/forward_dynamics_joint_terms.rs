//! Forward dynamics, `D⁻¹` and derivatives with joint-level terms (armature, viscous and Coulomb
//! friction, offset): the generic code against oracles (`D⁻¹ D = I` with the armature in `D`,
//! `FD(ID(q̈)) = q̈` with the terms in `τ`, central differences of `τ` and `q̈`), and the traced
//! graph against the generic code.

use dyngen_testkit as common;

use common::joint_terms::with_joint_terms;
use common::oracles::jacobian_by_differences;
use common::random_model::random_state;
use common::{assert_close, column};
use dyngen_codegen::description::load;
use dyngen_codegen::dynamics::NumericDynamics;
use dyngen_codegen::internals::generate::trace;
use dyngen_codegen::model::Model;
use nalgebra::DMatrix;
use std::path::Path;

fn with_joint_terms_on(name: &str, smoothing: Option<f64>) -> Model {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("../robots/{name}.yaml"));
    let model = load(&path).unwrap_or_else(|e| panic!("{e}")).model;
    with_joint_terms(model, smoothing, 7)
}

/// The Jacobian of `f` at `x` by extrapolated central differences.
fn differenced(f: impl Fn(&[f64]) -> DMatrix<f64>, x: &[f64]) -> DMatrix<f64> {
    jacobian_by_differences(f, x, 1e-3)
}

fn check(name: &str, smoothing: Option<f64>) {
    let model = with_joint_terms_on(name, smoothing);
    let n = model.dof();
    let dynamics = NumericDynamics::new(&model);
    let robot = trace(&model);
    for seed in 0..10 {
        let s = random_state(&model, 500 + seed);
        let at = |what: &str| format!("{name} ({smoothing:?}) seed {seed}: {what}");
        let tau = dynamics.inverse_dynamics(&s.q, &s.qd, &s.qdd);
        let qdd = dynamics.forward_dynamics(&s.q, &s.qd, tau.as_slice());
        assert_close(
            &at("FD(ID(q̈)) = q̈"),
            &column(qdd.as_slice()),
            &column(&s.qdd),
            1e-9,
        );
        let minv = dynamics.mass_matrix_inverse(&s.q);
        let eye = &minv * dynamics.mass_matrix(&s.q);
        assert_close(&at("D⁻¹ D = I"), &eye, &DMatrix::identity(n, n), 1e-9);

        let id = |q: &[f64], qd: &[f64]| column(dynamics.inverse_dynamics(q, qd, &s.qdd).as_slice());
        let (dq, dv) = dynamics.inverse_dynamics_derivatives(&s.q, &s.qd, &s.qdd);
        assert_close(&at("∂τ/∂q"), &dq, &differenced(|x| id(x, &s.qd), &s.q), 1e-7);
        assert_close(&at("∂τ/∂q̇"), &dv, &differenced(|x| id(&s.q, x), &s.qd), 1e-7);
        let fd = |q: &[f64], qd: &[f64]| column(dynamics.forward_dynamics(q, qd, tau.as_slice()).as_slice());
        let (fq, fv) = dynamics.forward_dynamics_derivatives(&s.q, &s.qd, tau.as_slice());
        assert_close(&at("∂q̈/∂q"), &fq, &differenced(|x| fd(x, &s.qd), &s.q), 1e-7);
        assert_close(&at("∂q̈/∂q̇"), &fv, &differenced(|x| fd(&s.q, x), &s.qd), 1e-7);

        // The traced graph (what is emitted) against the generic code.
        let traced = robot
            .evaluate_tau("forward_dynamics", &s.q, &s.qd, tau.as_slice())
            .unwrap();
        assert_close(&at("traced q̈"), &column(&traced), &column(qdd.as_slice()), 1e-10);
        let traced = robot
            .evaluate("mass_matrix_inverse", &s.q, &[], &[], &[])
            .unwrap();
        assert_close(
            &at("traced D⁻¹"),
            &DMatrix::from_column_slice(n, n, &traced),
            &minv,
            1e-10,
        );
        let traced = robot
            .evaluate("inverse_dynamics_derivatives", &s.q, &s.qd, &[], &s.qdd)
            .unwrap();
        let traced = DMatrix::from_column_slice(n, 2 * n, &traced);
        assert_close(
            &at("traced ∂τ/∂q̇"),
            &traced.columns(n, n).into_owned(),
            &dv,
            1e-10,
        );
        let traced = robot
            .evaluate_tau("forward_dynamics_derivatives", &s.q, &s.qd, tau.as_slice())
            .unwrap();
        let traced = DMatrix::from_column_slice(n, 2 * n, &traced);
        assert_close(
            &at("traced ∂q̈/∂q̇"),
            &traced.columns(n, n).into_owned(),
            &fv,
            1e-10,
        );
    }
}

#[test]
fn arm7_with_smoothed_friction_and_armature() {
    check("arm7", Some(0.05));
}

#[test]
fn ur5_with_coulomb_sign_friction_and_armature() {
    check("ur5", None);
}
