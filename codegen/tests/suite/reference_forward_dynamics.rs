//! Generic forward dynamics, `D⁻¹` and the derivatives of the dynamics against Pinocchio 4.1's
//! reference values (`aba`, `computeMinverse`, `computeRNEADerivatives`, `computeABADerivatives`).

use dyngen_testkit as common;

use common::fixture;
use dyngen_codegen::dynamics::NumericDynamics;

const TOL: f64 = 1e-9;

fn check(robot: &str) {
    let fx = fixture::load(robot);
    let model = fx.model();
    let dynamics = NumericDynamics::new(&model);
    for (k, s) in fx.states.iter().enumerate() {
        let at = |what: &str| format!("{robot} state {k}: {what}");
        fixture::assert_forward_dynamics_fields(&dynamics, s, &at, TOL);
    }
}

#[test]
fn panda_forward_dynamics_and_derivatives_match_pinocchio() {
    check("panda");
}

#[test]
fn panda_rounded_forward_dynamics_and_derivatives_match_pinocchio() {
    check("panda_rounded");
}

#[test]
fn ur5_forward_dynamics_and_derivatives_match_pinocchio() {
    check("ur5");
}
