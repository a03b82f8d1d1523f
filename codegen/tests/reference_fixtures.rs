//! Generic dynamics against reference values computed by an independent library (Pinocchio 4.1).

use dyngen_testkit as common;

use common::{assert_close, column, fixture};
use dyngen_codegen::dynamics::NumericDynamics;
use dyngen_codegen::model::Model;
use nalgebra::DMatrix;

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
        let (rot, pos) = dynamics.end_effector_pose(&s.q);
        assert_close(
            &at("ee translation"),
            &column(pos.as_slice()),
            &column(&s.ee_translation),
            TOL,
        );
        assert_close(
            &at("ee rotation"),
            &DMatrix::from_column_slice(3, 3, rot.as_slice()),
            &s.ee_rotation,
            TOL,
        );
        assert_close(&at("J"), &dynamics.jacobian(&s.q), &s.j, TOL);
        assert_close(&at("J̇"), &dynamics.jacobian_dot(&s.q, &s.v), &s.jdot, TOL);
        assert_close(&at("D"), &dynamics.mass_matrix(&s.q), &s.d, TOL);
        assert_close(&at("C"), &dynamics.coriolis_matrix(&s.q, &s.v), &s.c, TOL);
        assert_close(
            &at("g"),
            &column(dynamics.gravity_torque(&s.q).as_slice()),
            &column(&s.g),
            TOL,
        );
        assert_close(
            &at("τ"),
            &column(dynamics.inverse_dynamics(&s.q, &s.v, &s.a).as_slice()),
            &column(&s.tau),
            TOL,
        );
        let tau_ref = dynamics.slotine_li(&s.q, &s.v, &s.vr, &s.ar, true);
        assert_close(
            &at("Slotine–Li τ"),
            &column(tau_ref.as_slice()),
            &column(&s.tau_ref),
            TOL,
        );
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

#[test]
fn ur5_model_from_fixture_matches_pinocchio() {
    let fx = fixture::load("ur5");
    check_all("ur5", &fx.model());
}
