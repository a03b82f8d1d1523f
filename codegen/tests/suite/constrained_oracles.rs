//! Constrained dynamics on random trees (fixed and floating bases, light links and heavy
//! tools) against what the solution must satisfy, with no constrained algorithm in the oracle:
//! the equations of motion through inverse dynamics (`τ + Jᵀ λ` is what makes `a` happen), the
//! held frames' accelerations through the frame functions (a held point's classical
//! acceleration is zero), the held point's drift along a short step of the motion (third order
//! in the step: nothing of first or second order is left), an impact's velocities and momentum,
//! and the operational-space inertia against `(J D⁻¹ Jᵀ)⁻¹`. Redundant contacts need `μ > 0`
//! and then share the force; bad settings are refused.

use dyngen_codegen::dynamics::{ConstraintError, FloatingDynamics, NumericDynamics};
use dyngen_codegen::model::{Contact, Frame, Model, Pose as Placement};
use dyngen_runtime::{ContactError, ContactKind, Pose, ProximalSettings, ReferenceFrame, Stabilisation};
use dyngen_testkit::random_model::{
    arb_floating_model, arb_model_and_state, arb_pose, deterministic_runner, random_floating_sample,
};
use nalgebra::{DMatrix, DVector, Vector3};
use proptest::prelude::*;
use proptest::sample::Index;
use std::path::Path;

fn close(what: &str, actual: &DVector<f64>, expected: &DVector<f64>, tol: f64) -> Result<(), TestCaseError> {
    let err = (actual - expected).amax() / expected.amax().max(1.0);
    prop_assert!(
        err <= tol,
        "{what}: error {err:.2e}\nactual {actual:.6}\nexpected {expected:.6}"
    );
    Ok(())
}

/// Whether the rows `j` are independent (no more rows than joints, none near a combination of
/// the others) enough for an exact solve to be a fair test.
fn well_posed(j: &DMatrix<f64>) -> bool {
    let s = j.clone().svd(false, false).singular_values;
    s.len() == j.nrows() && s.min() > 1e-3 * s.max().max(1.0)
}

fn stacked_jacobian(frames: impl Iterator<Item = (DMatrix<f64>, ContactKind)>) -> DMatrix<f64> {
    let blocks: Vec<DMatrix<f64>> = frames
        .map(|(j, kind)| j.rows(0, kind.rows()).into_owned())
        .collect();
    let rows = blocks.iter().map(|b| b.nrows()).sum();
    let mut out = DMatrix::zeros(rows, blocks[0].ncols());
    let mut row = 0;
    for b in blocks {
        out.rows_mut(row, b.nrows()).copy_from(&b);
        row += b.nrows();
    }
    out
}

/// A fixed-base tree with one contact frame at a random body and pose.
fn with_contact_frame(model: Model, body: Index, pose: Placement) -> Model {
    let n = model.joints().len();
    let frame = Frame {
        name: "contact".into(),
        parent: Some(body.index(n)),
        placement: pose,
    };
    model.with_frames(vec![frame]).expect("a valid frame")
}

fn reference_of(local: bool) -> ReferenceFrame {
    if local {
        ReferenceFrame::Local
    } else {
        ReferenceFrame::LocalWorldAligned
    }
}

#[test]
fn a_held_point_of_a_random_tree_does_not_accelerate_and_the_forces_balance() {
    let strategy = (arb_model_and_state(7), any::<Index>(), arb_pose(), any::<bool>());
    deterministic_runner(48)
        .run(&strategy, |((model, state), body, pose, local)| {
            let model = with_contact_frame(model, body, pose);
            let dynamics = NumericDynamics::new(&model);
            let n = model.dof();
            let frame = model.frames().iter().position(|f| f.name == "contact").unwrap();
            let reference = reference_of(local);
            let contact = Contact {
                frame,
                kind: ContactKind::Point,
                reference,
                to: None,
            };
            let here = dynamics.frame_motion("contact", &state.q, &state.qd).unwrap();
            let j = here.jacobian(reference).rows(0, 3).into_owned();
            prop_assume!(well_posed(&j));
            let tau: Vec<f64> = state.a.iter().map(|a| 3.0 * a).collect();
            let solved = dynamics
                .constrained_forward_dynamics(
                    &state.q,
                    &state.qd,
                    &tau,
                    &[contact],
                    None,
                    &ProximalSettings::default(),
                )
                .map_err(|e| TestCaseError::fail(e.to_string()))?;
            let a = solved.acceleration.as_slice();
            // 1. τ + Jᵀ λ is the torque that makes `a` happen.
            let needed = dynamics.inverse_dynamics(&state.q, &state.qd, a);
            let applied = DVector::from_column_slice(&tau) + j.transpose() * &solved.forces;
            close("D a + C q̇ + g = τ + Jᵀ λ", &needed, &applied, 1e-9)?;
            // 2. The point's classical acceleration is zero.
            let acceleration = here.classical_acceleration(reference, a);
            close(
                "held point's acceleration",
                &DVector::from_column_slice(&acceleration.as_slice()[..3]),
                &DVector::zeros(3),
                1e-9,
            )?;
            // 3. Starting at rest in the contact's directions, a step of h moves the point by
            // O(h³): halving h divides the displacement by about 8, not 4.
            let null = DMatrix::identity(n, n) - j.clone().pseudo_inverse(1e-12).unwrap() * &j;
            let qd = null * DVector::from_column_slice(&state.qd);
            let start = dynamics
                .constrained_forward_dynamics(
                    &state.q,
                    qd.as_slice(),
                    &tau,
                    &[contact],
                    None,
                    &ProximalSettings::default(),
                )
                .map_err(|e| TestCaseError::fail(e.to_string()))?;
            let position = |x: &[f64]| {
                dynamics
                    .frame_motion("contact", x, &vec![0.0; n])
                    .unwrap()
                    .pose()
                    .1
            };
            let displacement = |h: f64| {
                let x: Vec<f64> = (0..n)
                    .map(|i| state.q[i] + qd[i] * h + 0.5 * start.acceleration[i] * h * h)
                    .collect();
                (position(&x) - position(&state.q)).norm()
            };
            let (coarse, fine) = (displacement(2e-3), displacement(1e-3));
            prop_assume!(fine > 1e-13);
            prop_assert!(
                coarse / fine > 6.0,
                "drift of order {:.2} in the step",
                (coarse / fine).log2()
            );
            Ok(())
        })
        .unwrap();
}

#[test]
fn an_impact_stops_the_contact_and_changes_momentum_only_along_its_rows() {
    let strategy = (
        arb_model_and_state(7),
        any::<Index>(),
        arb_pose(),
        any::<bool>(),
        0.0..1.0f64,
    );
    deterministic_runner(48)
        .run(&strategy, |((model, state), body, pose, local, restitution)| {
            let model = with_contact_frame(model, body, pose);
            let dynamics = NumericDynamics::new(&model);
            let frame = model.frames().iter().position(|f| f.name == "contact").unwrap();
            let reference = reference_of(local);
            let contact = Contact {
                frame,
                kind: ContactKind::Point,
                reference,
                to: None,
            };
            let before = dynamics.frame_motion("contact", &state.q, &state.qd).unwrap();
            let j = before.jacobian(reference).rows(0, 3).into_owned();
            prop_assume!(well_posed(&j));
            let (velocity, impulses) = dynamics
                .impulse_dynamics(&state.q, &state.qd, &[contact], restitution, 0.0)
                .map_err(|e| TestCaseError::fail(e.to_string()))?;
            let after = dynamics
                .frame_motion("contact", &state.q, velocity.as_slice())
                .unwrap();
            let v_before = DVector::from_column_slice(&before.velocity(reference).as_slice()[..3]);
            let v_after = DVector::from_column_slice(&after.velocity(reference).as_slice()[..3]);
            close("J ν⁺ = −r J ν⁻", &v_after, &(-restitution * v_before), 1e-9)?;
            let d = dynamics.mass_matrix(&state.q);
            let momentum = &d * (&velocity - DVector::from_column_slice(&state.qd));
            close(
                "D (ν⁺ − ν⁻) = Jᵀ Λ",
                &momentum,
                &(j.transpose() * &impulses),
                1e-9,
            )?;
            // The operational-space inertia of the same row is (J D⁻¹ Jᵀ)⁻¹.
            let lambda = dynamics
                .operational_space_inertia(&state.q, &[contact], 0.0)
                .unwrap();
            let expected = (&j * d.try_inverse().unwrap() * j.transpose())
                .try_inverse()
                .unwrap();
            let err = (&lambda - &expected).amax() / expected.amax();
            prop_assert!(err < 1e-8, "Λ: error {err:.2e}");
            Ok(())
        })
        .unwrap();
}

#[test]
fn a_floating_robot_held_at_two_bodies_keeps_them_still_and_balances() {
    let strategy = (arb_floating_model(8), any::<u64>(), any::<Index>(), any::<bool>());
    deterministic_runner(32)
        .run(&strategy, |(model, seed, other, local)| {
            let dynamics = FloatingDynamics::new(&model).unwrap();
            let sample = random_floating_sample(&model, seed);
            let s = dynamics.state(&sample.q).unwrap();
            let bodies = model.bodies().len();
            // A frame held at the first body, a point at another (frame `1 + i` is body i's origin).
            let second = 1 + other.index(bodies);
            prop_assume!(second != 1);
            let reference = reference_of(local);
            let contacts = [
                Contact {
                    frame: 1,
                    kind: ContactKind::Frame,
                    reference,
                    to: None,
                },
                Contact {
                    frame: second,
                    kind: ContactKind::Point,
                    reference: reference_of(!local),
                    to: None,
                },
            ];
            let j = stacked_jacobian(
                contacts
                    .iter()
                    .map(|c| (dynamics.frame_jacobian(&s, c.frame, c.reference), c.kind)),
            );
            prop_assume!(well_posed(&j));
            let tau: Vec<f64> = sample.a.iter().map(|a| 2.0 * a).collect();
            let solved = dynamics
                .constrained_forward_dynamics(
                    &s,
                    &sample.v,
                    &tau,
                    &contacts,
                    None,
                    &ProximalSettings::default(),
                )
                .map_err(|e| TestCaseError::fail(e.to_string()))?;
            let a = solved.acceleration.as_slice();
            let needed = dynamics.inverse_dynamics(&s, &sample.v, a);
            let applied = DVector::from_column_slice(&tau) + j.transpose() * &solved.forces;
            close("D ν̇ + C ν + g = τ + Jᵀ λ", &needed, &applied, 1e-9)?;
            // The held point's classical acceleration is zero; the held frame's spatial
            // acceleration (its classical one less ω × v) is zero.
            let point =
                dynamics.frame_classical_acceleration(&s, &sample.v, a, second, contacts[1].reference);
            close(
                "held point",
                &DVector::from_column_slice(&point.as_slice()[..3]),
                &DVector::zeros(3),
                1e-9,
            )?;
            let classical = dynamics.frame_classical_acceleration(&s, &sample.v, a, 1, reference);
            let velocity = dynamics.frame_velocity(&s, &sample.v, 1, reference);
            let (v, w) = (velocity.fixed_rows::<3>(0), velocity.fixed_rows::<3>(3));
            let mut spatial = DVector::from_column_slice(classical.as_slice());
            spatial
                .rows_mut(0, 3)
                .copy_from(&(classical.fixed_rows::<3>(0) - w.cross(&v)));
            close("held frame", &spatial, &DVector::zeros(6), 1e-9)?;
            Ok(())
        })
        .unwrap();
}

#[test]
fn baumgarte_pulls_a_drifted_point_back_to_its_anchor() {
    // A point held 1 cm away from where it is, at rest: with gains it accelerates towards the
    // anchor by K_p times the error (its classical acceleration is −K_p e − K_d J q̇ = K_p Δ).
    let strategy = (arb_model_and_state(6), any::<Index>(), arb_pose());
    deterministic_runner(32)
        .run(&strategy, |((model, state), body, pose)| {
            let model = with_contact_frame(model, body, pose);
            let dynamics = NumericDynamics::new(&model);
            let n = model.dof();
            let frame = model.frames().iter().position(|f| f.name == "contact").unwrap();
            let contact = Contact {
                frame,
                kind: ContactKind::Point,
                reference: ReferenceFrame::LocalWorldAligned,
                to: None,
            };
            let rest = vec![0.0; n];
            let here = dynamics.frame_motion("contact", &state.q, &rest).unwrap();
            prop_assume!(well_posed(
                &here.jacobian(contact.reference).rows(0, 3).into_owned()
            ));
            let (rotation, translation) = here.pose();
            let offset = Vector3::new(0.01, -0.005, 0.002);
            let anchor = Pose {
                rotation,
                translation: translation + offset,
            };
            let kp = 25.0;
            let solved = dynamics
                .constrained_forward_dynamics(
                    &state.q,
                    &rest,
                    &state.a,
                    &[contact],
                    Some(Stabilisation {
                        anchors: &[anchor],
                        kp,
                        kd: 10.0,
                    }),
                    &ProximalSettings::default(),
                )
                .map_err(|e| TestCaseError::fail(e.to_string()))?;
            let acceleration = here.classical_acceleration(contact.reference, solved.acceleration.as_slice());
            let expected = DVector::from_column_slice((kp * offset).as_slice());
            close(
                "pulled towards the anchor",
                &DVector::from_column_slice(&acceleration.as_slice()[..3]),
                &expected,
                1e-9,
            )?;
            Ok(())
        })
        .unwrap();
}

/// Two-link planar arm, its tip a frame: a fixed case where the rows can be made redundant.
fn planar_arm() -> Model {
    let yaml = r#"
name: planar
gravity: [0.0, 0.0, -9.81]
end_effector: { name: tip, link: hand, xyz: [0.0, 0.0, 0.1] }
links:
  - name: base
  - name: upper
    inertial: { mass: 2.0, origin: { xyz: [0.0, 0.0, 0.25] }, inertia: { ixx: 0.05, ixy: 0.0, ixz: 0.0, iyy: 0.05, iyz: 0.0, izz: 0.01 } }
  - name: fore
    inertial: { mass: 1.5, origin: { xyz: [0.0, 0.0, 0.2] }, inertia: { ixx: 0.03, ixy: 0.0, ixz: 0.0, iyy: 0.03, iyz: 0.0, izz: 0.01 } }
  - name: hand
    inertial: { mass: 0.5, origin: { xyz: [0.0, 0.0, 0.05] }, inertia: { ixx: 0.002, ixy: 0.0, ixz: 0.0, iyy: 0.002, iyz: 0.0, izz: 0.001 } }
joints:
  - { name: shoulder, type: revolute, parent: base, child: upper, origin: { xyz: [0.0, 0.0, 0.0] }, axis: [0.0, 1.0, 0.0], limit: { lower: -3.0, upper: 3.0, velocity: 2.0, effort: 50.0 } }
  - { name: elbow, type: revolute, parent: upper, child: fore, origin: { xyz: [0.0, 0.0, 0.5] }, axis: [0.0, 1.0, 0.0], limit: { lower: -3.0, upper: 3.0, velocity: 2.0, effort: 50.0 } }
  - { name: wrist, type: revolute, parent: fore, child: hand, origin: { xyz: [0.0, 0.0, 0.4] }, axis: [0.0, 1.0, 0.0], limit: { lower: -3.0, upper: 3.0, velocity: 2.0, effort: 50.0 } }
"#;
    dyngen_codegen::description::load_yaml_str(yaml, Path::new("planar.yaml"))
        .unwrap_or_else(|e| panic!("{e}"))
        .model
}

#[test]
fn a_point_held_twice_is_refused_exactly_and_shares_its_force_when_regularised() {
    let model = planar_arm();
    let dynamics = NumericDynamics::new(&model);
    let q = [0.3, -0.7, 0.4];
    let (qd, tau) = ([0.5, -0.2, 0.8], [1.0, -2.0, 0.5]);
    // In the arm's plane a point's rows are x and z; y is not a motion it can have, so a
    // point contact on a planar arm is redundant already. A frame's rows hold two of them.
    let once = Contact {
        frame: 0,
        kind: ContactKind::Point,
        reference: ReferenceFrame::LocalWorldAligned,
        to: None,
    };
    let exact =
        dynamics.constrained_forward_dynamics(&q, &qd, &tau, &[once], None, &ProximalSettings::default());
    assert!(
        matches!(exact, Err(ConstraintError::Solve(ContactError::Redundant { .. }))),
        "{exact:?}"
    );
    let settings = ProximalSettings {
        mu: 1e-6,
        max_iterations: 2000,
        accuracy: 1e-13,
    };
    let single = dynamics
        .constrained_forward_dynamics(&q, &qd, &tau, &[once], None, &settings)
        .unwrap();
    let twice = dynamics
        .constrained_forward_dynamics(&q, &qd, &tau, &[once, once], None, &settings)
        .unwrap();
    let (a1, a2) = (&single.acceleration, &twice.acceleration);
    assert!((a1 - a2).amax() < 1e-8 * a1.amax().max(1.0), "{a1} {a2}");
    // The point does not accelerate in the plane (x, z).
    let values = dynamics.frame_motion(&model.frames()[0].name, &q, &qd).unwrap();
    let held = values.classical_acceleration(ReferenceFrame::LocalWorldAligned, a2.as_slice());
    assert!(held[0].abs() < 1e-8 && held[2].abs() < 1e-8, "{held}");
    // Two copies of one row carry half the force each.
    let (f, f2) = (&single.forces, &twice.forces);
    for k in 0..3 {
        assert!((f2[k] - f2[3 + k]).abs() < 1e-7 * f.amax(), "{f2}");
        assert!((f2[k] + f2[3 + k] - f[k]).abs() < 1e-7 * f.amax(), "{f} {f2}");
    }
}

#[test]
fn bad_settings_and_contacts_are_refused_with_a_reason() {
    let model = planar_arm();
    let dynamics = NumericDynamics::new(&model);
    let (q, qd, tau) = ([0.3, -0.7, 0.4], [0.0; 3], [0.0; 3]);
    let world = Contact {
        frame: 0,
        kind: ContactKind::Point,
        reference: ReferenceFrame::World,
        to: None,
    };
    let past = Contact {
        frame: 9,
        kind: ContactKind::Point,
        reference: ReferenceFrame::Local,
        to: None,
    };
    let fine = Contact {
        frame: 0,
        kind: ContactKind::Point,
        reference: ReferenceFrame::Local,
        to: None,
    };
    let exact = ProximalSettings::default();
    let cases: Vec<(Result<_, ConstraintError>, &str)> = vec![
        (
            dynamics
                .constrained_forward_dynamics(&q, &qd, &tau, &[world], None, &exact)
                .map(|_| ()),
            "world axes",
        ),
        (
            dynamics
                .constrained_forward_dynamics(&q, &qd, &tau, &[past], None, &exact)
                .map(|_| ()),
            "past the model",
        ),
        (
            dynamics
                .constrained_forward_dynamics(
                    &q,
                    &qd,
                    &tau,
                    &[fine],
                    None,
                    &ProximalSettings { mu: -1.0, ..exact },
                )
                .map(|_| ()),
            "not negative",
        ),
        (
            dynamics
                .constrained_forward_dynamics(
                    &q,
                    &qd,
                    &tau,
                    &[fine],
                    Some(Stabilisation {
                        anchors: &[],
                        kp: 1.0,
                        kd: 1.0,
                    }),
                    &ProximalSettings {
                        mu: 1e-6,
                        max_iterations: 10,
                        accuracy: 1e-12,
                    },
                )
                .map(|_| ()),
            "anchors",
        ),
        (
            dynamics.impulse_dynamics(&q, &qd, &[fine], 1.5, 1e-6).map(|_| ()),
            "outside [0, 1]",
        ),
    ];
    for (result, expected) in cases {
        let message = result.expect_err(expected).to_string();
        assert!(message.contains(expected), "{message:?} should say {expected:?}");
    }
    let unknown = Contact::at(&model, "nowhere", ContactKind::Point, ReferenceFrame::Local);
    assert!(unknown
        .unwrap_err()
        .to_string()
        .contains("no frame named `nowhere`"));
}

/// The traced rows of a fixed-base robot with contacts (what generated code computes), on
/// random trees: `J` the held frame's Jacobian rows, the drift its acceleration at `q̈ = 0`
/// (a point's classical, a frame's spatial), and `M⁻¹ Jᵀ` from the generic `D⁻¹`.
#[test]
fn the_traced_contact_rows_are_the_frames_own_on_random_trees() {
    use dyngen_codegen::internals::generate::trace;
    let strategy = (
        arb_model_and_state(8),
        any::<Index>(),
        arb_pose(),
        any::<bool>(),
        any::<bool>(),
    );
    deterministic_runner(24)
        .run(&strategy, |((model, state), body, pose, local, whole)| {
            let kind = if whole {
                ContactKind::Frame
            } else {
                ContactKind::Point
            };
            prop_assume!(model.dof() > kind.rows());
            let model = with_contact_frame(model, body, pose);
            let frame = model.frames().iter().position(|f| f.name == "contact").unwrap();
            let reference = reference_of(local);
            let model = model
                .with_contacts(vec![Contact {
                    frame,
                    kind,
                    reference,
                    to: None,
                }])
                .map_err(|e| TestCaseError::fail(e.to_string()))?;
            let n = model.dof();
            let traced = trace(&model);
            let dynamics = NumericDynamics::new(&model);
            let here = dynamics.frame_motion("contact", &state.q, &state.qd).unwrap();
            let rows = kind.rows();
            let j = here.jacobian(reference).rows(0, rows).into_owned();
            let evaluate = |name: &str| traced.evaluate(name, &state.q, &state.qd, &[], &[]).unwrap();
            let traced_j = DMatrix::from_column_slice(rows, n, &evaluate("contact_jacobian"));
            close(
                "J",
                &DVector::from_column_slice(traced_j.as_slice()),
                &DVector::from_column_slice(j.as_slice()),
                1e-12,
            )?;
            let classical = here.classical_acceleration(reference, &vec![0.0; n]);
            let mut drift = DVector::from_column_slice(&classical.as_slice()[..rows]);
            if kind == ContactKind::Frame {
                let velocity = here.velocity(reference);
                let (v, w) = (velocity.fixed_rows::<3>(0), velocity.fixed_rows::<3>(3));
                drift
                    .rows_mut(0, 3)
                    .copy_from(&(classical.fixed_rows::<3>(0) - w.cross(&v)));
            }
            close(
                "drift",
                &DVector::from_column_slice(&evaluate("contact_drift")),
                &drift,
                1e-10,
            )?;
            let response = dynamics.mass_matrix_inverse(&state.q) * j.transpose();
            close(
                "M⁻¹ Jᵀ",
                &DVector::from_column_slice(&evaluate("contact_response")),
                &DVector::from_column_slice(response.as_slice()),
                1e-8,
            )?;
            Ok(())
        })
        .unwrap();
}

/// The derivatives of constrained forward dynamics against central differences of the
/// constrained solution itself, on random floating trees held at a frame and a point
/// (stabilised towards anchors off the contacts, so the gains' terms are differentiated too,
/// where the error is a point's), `q` moved on the manifold (`integrate`).
#[test]
fn constrained_derivatives_are_the_differences_of_the_solution() {
    let strategy = (arb_floating_model(6), any::<u64>(), any::<Index>(), any::<bool>());
    deterministic_runner(16)
        .run(&strategy, |(model, seed, other, local)| {
            let dynamics = FloatingDynamics::new(&model).unwrap();
            let sample = random_floating_sample(&model, seed);
            let second = 1 + other.index(model.bodies().len());
            prop_assume!(second != 1);
            let contacts = [
                Contact {
                    frame: 1,
                    kind: ContactKind::Point,
                    reference: reference_of(local),
                    to: None,
                },
                Contact {
                    frame: second,
                    kind: ContactKind::Point,
                    reference: reference_of(!local),
                    to: None,
                },
            ];
            let s = dynamics.state(&sample.q).unwrap();
            let j = stacked_jacobian(
                contacts
                    .iter()
                    .map(|c| (dynamics.frame_jacobian(&s, c.frame, c.reference), c.kind)),
            );
            prop_assume!(well_posed(&j));
            let anchors: Vec<Pose> = contacts
                .iter()
                .map(|c| {
                    let (rotation, translation) = dynamics.frame_pose(&s, c.frame);
                    Pose {
                        rotation,
                        translation: translation + Vector3::new(0.01, -0.02, 0.005),
                    }
                })
                .collect();
            let stabilisation = Some(Stabilisation {
                anchors: &anchors,
                kp: 20.0,
                kd: 9.0,
            });
            let tau: Vec<f64> = sample.a.iter().map(|a| 2.0 * a).collect();
            let solve = |q: &[f64], v: &[f64], tau: &[f64]| {
                let s = dynamics.state(q).unwrap();
                let m = dynamics
                    .constrained_forward_dynamics(
                        &s,
                        v,
                        tau,
                        &contacts,
                        stabilisation,
                        &ProximalSettings::default(),
                    )
                    .unwrap();
                let mut out = m.acceleration.as_slice().to_vec();
                out.extend(m.forces.iter());
                DVector::from_vec(out)
            };
            let ours = dynamics
                .constrained_forward_dynamics_derivatives(&s, &sample.v, &tau, &contacts, stabilisation)
                .map_err(|e| TestCaseError::fail(e.to_string()))?;
            let nv = model.nv();
            let h = 1e-6;
            let size = solve(&sample.q, &sample.v, &tau).amax();
            for k in 0..nv {
                let mut e = vec![0.0; nv];
                e[k] = h;
                let minus: Vec<f64> = e.iter().map(|x| -x).collect();
                let moved = |d: &[f64]| dynamics.integrate(&sample.q, d, 1.0).unwrap();
                let by_q =
                    (solve(&moved(&e), &sample.v, &tau) - solve(&moved(&minus), &sample.v, &tau)) / (2.0 * h);
                let shifted =
                    |x: &[f64], d: &[f64]| x.iter().zip(d).map(|(a, b)| a + b).collect::<Vec<f64>>();
                let by_v = (solve(&sample.q, &shifted(&sample.v, &e), &tau)
                    - solve(&sample.q, &shifted(&sample.v, &minus), &tau))
                    / (2.0 * h);
                let by_tau = (solve(&sample.q, &sample.v, &shifted(&tau, &e))
                    - solve(&sample.q, &sample.v, &shifted(&tau, &minus)))
                    / (2.0 * h);
                for (name, fd, acceleration, forces) in [
                    ("∂/∂q", by_q, &ours.acceleration_q, &ours.forces_q),
                    ("∂/∂ν", by_v, &ours.acceleration_v, &ours.forces_v),
                    ("∂/∂τ", by_tau, &ours.acceleration_tau, &ours.forces_tau),
                ] {
                    let mut column: Vec<f64> = acceleration.column(k).iter().copied().collect();
                    column.extend(forces.column(k).iter());
                    // A difference of values of size |x| carries rounding of about ε |x| / h.
                    let rounding = 1e-11 * size / h;
                    let err = (DVector::from_vec(column) - &fd).amax();
                    prop_assert!(
                        err <= 1e-5 * fd.amax().max(1.0) + rounding,
                        "{name} column {k}: error {err:.2e} (rounding {rounding:.1e})"
                    );
                }
            }
            Ok(())
        })
        .unwrap();
}
