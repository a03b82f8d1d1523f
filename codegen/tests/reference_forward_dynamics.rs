//! Generic forward dynamics, `D⁻¹` and the derivatives of the dynamics against Pinocchio 4.1's
//! reference values (`aba`, `computeMinverse`, `computeRNEADerivatives`, `computeABADerivatives`).

use dyngen_testkit as common;

use common::{assert_close, column, fixture};
use dyngen_codegen::dynamics::NumericDynamics;

const TOL: f64 = 1e-9;

fn check(robot: &str) {
    let fx = fixture::load(robot);
    let model = fx.model();
    let dynamics = NumericDynamics::new(&model);
    for (k, s) in fx.states.iter().enumerate() {
        let at = |what: &str| format!("{robot} state {k}: {what}");
        let qdd = dynamics.forward_dynamics(&s.q, &s.v, &s.tau);
        assert_close(&at("q̈"), &column(qdd.as_slice()), &column(&s.aba), TOL);
        assert_close(&at("D⁻¹"), &dynamics.mass_matrix_inverse(&s.q), &s.minv, TOL);
        let (dq, dv) = dynamics.inverse_dynamics_derivatives(&s.q, &s.v, &s.a);
        assert_close(&at("∂τ/∂q"), &dq, &s.dtau_dq, TOL);
        assert_close(&at("∂τ/∂q̇"), &dv, &s.dtau_dv, TOL);
        let (dq, dv) = dynamics.forward_dynamics_derivatives(&s.q, &s.v, &s.tau);
        assert_close(&at("∂q̈/∂q"), &dq, &s.dqdd_dq, TOL);
        assert_close(&at("∂q̈/∂q̇"), &dv, &s.dqdd_dv, TOL);
    }
}

#[test]
fn panda_forward_dynamics_and_derivatives_match_pinocchio() {
    check("panda");
}

#[test]
fn ur5_forward_dynamics_and_derivatives_match_pinocchio() {
    check("ur5");
}
