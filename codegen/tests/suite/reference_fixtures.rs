//! Generic dynamics against reference values computed by an independent library (Pinocchio 4.1).

use dyngen_testkit as common;

use common::{assert_close, column, fixture};
use dyngen_codegen::dynamics::NumericDynamics;
use dyngen_codegen::model::Model;

const TOL: f64 = 1e-9;

fn check_all(robot: &str, model: &Model) {
    let fx = fixture::load(robot);
    let dynamics = NumericDynamics::new(model);
    assert_close(
        &format!("{robot} θ"),
        &column(&model.parameters()),
        &column(&fx.pi),
        TOL,
    );
    for (k, s) in fx.states.iter().enumerate() {
        let at = |what: &str| format!("{robot} state {k}: {what}");
        fixture::assert_rigid_body_fields(&dynamics, s, &at, TOL);
        assert_close(&at("Y"), &dynamics.regressor(&s.q, &s.v, &s.v, &s.a), &s.y, TOL);
        let y_ref = dynamics.regressor(&s.q, &s.v, &s.vr, &s.ar);
        assert_close(
            &at("Y(q, q̇, v, a) θ"),
            &(y_ref * column(&fx.pi)),
            &column(&s.tau_ref),
            TOL,
        );
    }
}

#[test]
fn panda_model_from_fixture_matches_pinocchio() {
    let fx = fixture::load("panda");
    check_all("panda", &fx.model());
}

/// The rounded Panda as dyngen snaps it (`robots/panda_rounded.yaml`), Pinocchio's model of the
/// same snapped angles.
#[test]
fn panda_rounded_model_from_fixture_matches_pinocchio() {
    let fx = fixture::load("panda_rounded");
    check_all("panda_rounded", &fx.model());
}

#[test]
fn ur5_model_from_fixture_matches_pinocchio() {
    let fx = fixture::load("ur5");
    check_all("ur5", &fx.model());
}
