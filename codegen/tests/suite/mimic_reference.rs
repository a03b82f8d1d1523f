//! Mimic joints against Pinocchio 4.1 (`buildModelFromUrdf(path, mimic=True)`): the Panda with
//! its fingers free (a prismatic mimic, multiplier 1) and `mimic_arm` (revolute mimic joints
//! with multiplier 1.5 and offset 0.3, and multiplier −1 and offset 0.2), both loaded by
//! dyngen's own loaders from the URDFs Pinocchio read. Which values Pinocchio computes on the
//! mimic model and which through its model without mimic joints: `codegen/tests/fixtures/README.md`.

use dyngen_testkit as common;

use common::fixture::{self, Fixture};
use common::{assert_close, column};
use dyngen_codegen::dynamics::NumericDynamics;
use dyngen_codegen::model::Model;
use nalgebra::DMatrix;
use std::path::Path;

const TOL: f64 = 1e-9;

fn load(yaml: &str) -> Model {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/mimic")
        .join(yaml);
    dyngen_codegen::description::load(&path)
        .unwrap_or_else(|e| panic!("{e}"))
        .model
}

/// For each of the model's bodies, the index of the same body (by joint name) in the fixture,
/// whose joints Pinocchio orders depth-first (possibly not as dyngen does).
fn body_order(model: &Model, fx: &Fixture) -> Vec<usize> {
    let names: Vec<&str> = fx.json["joints"]
        .as_array()
        .unwrap()
        .iter()
        .map(|j| j["name"].as_str().unwrap())
        .collect();
    model
        .joints()
        .iter()
        .map(|j| {
            names
                .iter()
                .position(|n| *n == j.name)
                .expect("joint in the fixture")
        })
        .collect()
}

/// `Y`'s column blocks (ten per body) reordered from dyngen's body order to the fixture's.
fn in_fixture_order(y: &DMatrix<f64>, order: &[usize]) -> DMatrix<f64> {
    let mut out = y.clone();
    for (ours, &theirs) in order.iter().enumerate() {
        for k in 0..10 {
            out.set_column(10 * theirs + k, &y.column(10 * ours + k));
        }
    }
    out
}

fn check_against_pinocchio(robot: &str, model: &Model) {
    let fx = fixture::load(robot);
    let names: Vec<&str> = (model.coordinate_joints().into_iter())
        .map(|k| model.joints()[k].name.as_str())
        .collect();
    assert_eq!(names, fx.joint_names, "{robot}: coordinates");
    assert!(model.has_mimics() && model.dof() < model.joints().len());
    let order = body_order(model, &fx);
    let theta = model.parameters();
    let mut theta_fx_order = vec![0.0; theta.len()];
    for (ours, &theirs) in order.iter().enumerate() {
        theta_fx_order[10 * theirs..10 * theirs + 10].copy_from_slice(&theta[10 * ours..10 * ours + 10]);
    }
    assert_close(
        &format!("{robot} θ"),
        &column(&theta_fx_order),
        &column(&fx.pi),
        TOL,
    );

    let dynamics = NumericDynamics::new(model);
    for (k, s) in fx.states.iter().enumerate() {
        let at = |what: &str| format!("{robot} state {k}: {what}");
        fixture::assert_rigid_body_fields(&dynamics, s, &at, TOL);
        let y = dynamics.regressor(&s.q, &s.v, &s.v, &s.a);
        assert_close(&at("Y"), &in_fixture_order(&y, &order), &s.y, TOL);
        let y_ref = dynamics.regressor(&s.q, &s.v, &s.vr, &s.ar);
        assert_close(
            &at("Y(q, q̇, v, a) θ"),
            &(y_ref * column(&theta)),
            &column(&s.tau_ref),
            TOL,
        );
        fixture::assert_forward_dynamics_fields(&dynamics, s, &at, TOL);
    }
}

#[test]
fn panda_with_free_fingers_matches_pinocchio() {
    let model = load("panda_mimic.yaml");
    assert_eq!(
        (model.dof(), model.joints().len(), model.parameter_count()),
        (8, 9, 90)
    );
    check_against_pinocchio("panda_mimic", &model);
}

#[test]
fn arm_with_revolute_mimic_joints_matches_pinocchio() {
    let model = load("mimic_arm.yaml");
    assert_eq!((model.dof(), model.joints().len()), (3, 5));
    check_against_pinocchio("mimic_arm", &model);
}
