//! Constrained dynamics of floating-base robots against Pinocchio 4.1
//! (`codegen/tests/fixtures/constrained/`, made by `tools/constraint_fixtures.py`): Solo-12
//! with its four feet held as points and the G1 with its two ankles held as frames, half the
//! contacts in `LOCAL` axes and half in `LOCAL_WORLD_ALIGNED`. Forward dynamics and the
//! contact forces (exact, Baumgarte-stabilised, proximal), impulses (exact and damped), and the
//! operational-space inertia against `(J M⁻¹ Jᵀ)⁻¹` from Pinocchio's `J` and `M`, to 1e-9
//! relative, joint by joint name.

use dyngen_testkit as common;

use common::fixture::{matrix, vector};
use common::floating_fixture::{self, Order};
use common::{assert_close, column, workspace_root};
use dyngen_codegen::description::{self, Choices, FrameSelection, FrameSpec, Loaded};
use dyngen_codegen::dynamics::{FloatingDynamics, FloatingState};
use dyngen_codegen::model::Contact;
use dyngen_runtime::{ContactKind, ProximalSettings, Stabilisation};
use nalgebra::DMatrix;
use serde_json::Value;

const TOL: f64 = 1e-9;

pub(crate) fn load(urdf: &str, fixture: &Value) -> Loaded {
    let frames: Vec<FrameSpec> = fixture["contacts"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| FrameSpec::link(c["frame"].as_str().unwrap()))
        .collect();
    let options = Choices {
        floating_base: true,
        frames: FrameSelection::Listed(frames),
        ..Choices::default()
    };
    let path = workspace_root()
        .join("codegen/tests/data/example-robot-data")
        .join(urdf);
    description::load_with(&path, &options).unwrap_or_else(|e| panic!("{e}"))
}

/// Pinocchio's `computeConstraintDynamicsDerivatives` against ours; where Pinocchio's `∂/∂q`
/// is an approximation (6-D contacts with Baumgarte gains: it leaves out the derivative of
/// `log₆`), ours refuses, saying why.
#[allow(clippy::too_many_arguments)]
fn check_derivatives(
    what: &str,
    dynamics: &FloatingDynamics,
    s: &FloatingState,
    (v, tau): (&[f64], &[f64]),
    contacts: &[Contact],
    stabilisation: Option<Stabilisation>,
    expected: &Value,
    order: &Order,
) {
    let ours = dynamics.constrained_forward_dynamics_derivatives(s, v, tau, contacts, stabilisation);
    let frames = contacts.iter().any(|c| c.kind == ContactKind::Frame);
    if frames && stabilisation.is_some() {
        let message = ours.expect_err("a stabilised frame contact").to_string();
        assert!(message.contains("log₆"), "{message}");
        return;
    }
    let ours = ours.unwrap_or_else(|e| panic!("{what}: {e}"));
    let theirs =
        |field: &str, rows_velocity: bool| order.matrix(&matrix(&expected[field]), rows_velocity, true);
    for (name, mine, field, rows_velocity) in [
        ("∂ν̇/∂q", &ours.acceleration_q, "ddq_dq", true),
        ("∂ν̇/∂ν", &ours.acceleration_v, "ddq_dv", true),
        ("∂ν̇/∂τ", &ours.acceleration_tau, "ddq_dtau", true),
        ("∂λ/∂q", &ours.forces_q, "dlambda_dq", false),
        ("∂λ/∂ν", &ours.forces_v, "dlambda_dv", false),
        ("∂λ/∂τ", &ours.forces_tau, "dlambda_dtau", false),
    ] {
        assert_close(
            &format!("{what} {name}"),
            mine,
            &theirs(field, rows_velocity),
            TOL,
        );
    }
}

fn check_robot(robot: &str, urdf: &str) {
    let fx = floating_fixture::load_constrained(robot);
    let loaded = load(urdf, &fx);
    let model = &loaded.model;
    let order = Order::new(model, &fx);
    let contacts = floating_fixture::contacts(&loaded.model, &fx);
    let dynamics = FloatingDynamics::new(model).unwrap();
    let proximal = floating_fixture::proximal(&fx);
    let restitution = fx["restitution"].as_f64().unwrap();
    for (k, st) in fx["states"].as_array().unwrap().iter().enumerate() {
        let what = |q: &str| format!("{robot} state {k}: {q}");
        let q = order.configuration(&vector(&st["q"]));
        let [v, tau] = ["v", "tau"].map(|f| order.vector(&vector(&st[f])));
        let s = dynamics.state(&q).unwrap();
        let anchors = floating_fixture::anchors(st);
        let velocity = |field: &Value| column(&order.vector(&vector(field)));

        for (label, stabilisation) in floating_fixture::solves(&fx, &anchors) {
            let expected = &st["forward"][label];
            check_derivatives(
                &what(label),
                &dynamics,
                &s,
                (&v, &tau),
                &contacts,
                stabilisation,
                expected,
                &order,
            );
            for (how, settings) in [("exact", ProximalSettings::default()), ("proximal", proximal)] {
                let solved = dynamics
                    .constrained_forward_dynamics(&s, &v, &tau, &contacts, stabilisation, &settings)
                    .unwrap_or_else(|e| panic!("{}: {e}", what(label)));
                let name = |q: &str| what(&format!("{label} {how} {q}"));
                assert_close(
                    &name("ν̇"),
                    &column(solved.acceleration.as_slice()),
                    &velocity(&expected["ddq"]),
                    TOL,
                );
                assert_close(
                    &name("λ"),
                    &column(solved.forces.as_slice()),
                    &column(&vector(&expected["lambda"])),
                    TOL,
                );
            }
        }

        for (field, mu) in [
            ("impulse", 0.0),
            ("impulse_damped", fx["damped_mu"].as_f64().unwrap()),
        ] {
            let (after, impulses) = dynamics
                .impulse_dynamics(&s, &v, &contacts, restitution, mu)
                .unwrap_or_else(|e| panic!("{}: {e}", what(field)));
            assert_close(
                &what(&format!("{field} ν⁺")),
                &column(after.as_slice()),
                &velocity(&st[field]["v_after"]),
                TOL,
            );
            assert_close(
                &what(&format!("{field} Λ")),
                &column(impulses.as_slice()),
                &column(&vector(&st[field]["impulse"])),
                TOL,
            );
        }

        // Λ from Pinocchio's own M and J, inverted here.
        let m = order.square(st, "M");
        let j = order.matrix(&matrix(&st["J"]), false, true);
        let delassus: DMatrix<f64> = &j * m.clone().try_inverse().unwrap() * j.transpose();
        let lambda = dynamics.operational_space_inertia(&s, &contacts, 0.0).unwrap();
        assert_close(&what("Λ"), &lambda, &delassus.try_inverse().unwrap(), TOL);
    }
}

#[test]
fn solo12_with_four_point_feet_matches_pinocchio() {
    check_robot("solo12", "solo_description/solo12.urdf");
}

#[test]
fn g1_with_two_flat_feet_matches_pinocchio() {
    check_robot("g1", "g1_description/g1_29dof_rev_1_0.urdf");
}
