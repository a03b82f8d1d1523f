//! Loop closures (a frame held to another frame of the tree) against Pinocchio 4.1
//! (`codegen/tests/fixtures/constrained/{four_bar,two_branches}.json`, made by
//! `tools/loop_fixtures.py` from the URDFs of `codegen/tests/data/loops/`): a planar four-bar
//! on its loop (a point loop, whose out-of-plane row is zero: the proximal solve), and two
//! spatial branches whose tips are held as points and frames in both axes, beside a point held
//! to the world. The rows `J` and their drift as generated code traces them, forward dynamics
//! plain and Baumgarte-stabilised, and Pinocchio's derivatives where they are those of its own
//! solution; then what Pinocchio does not hold: impulses, and the derivatives of point loops
//! against central differences.

use dyngen_testkit as common;

use common::fixture::{matrix, vector};
use common::{assert_close, column, floating_fixture, workspace_root};
use dyngen_codegen::description::{self, Choices, FrameSelection, FrameSpec, Loaded};
use dyngen_codegen::dynamics::NumericDynamics;
use dyngen_codegen::internals::generate::trace;
use dyngen_codegen::model::Contact;
use dyngen_runtime::{ContactKind, ProximalSettings, ReferenceFrame, Stabilisation};
use nalgebra::{DMatrix, DVector};
use serde_json::Value;

const TOL: f64 = 1e-9;

pub(crate) fn fixture(name: &str) -> Value {
    let path = workspace_root().join(format!("codegen/tests/fixtures/constrained/{name}.json"));
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    serde_json::from_str(&text).expect("JSON")
}

/// The mechanism with every frame the fixture's sets name.
pub(crate) fn load(name: &str, fixture: &Value) -> Loaded {
    let mut frames: Vec<String> = Vec::new();
    for set in fixture["sets"].as_array().unwrap() {
        for c in set["contacts"].as_array().unwrap() {
            for key in ["frame", "to"] {
                if let Some(frame) = c[key].as_str() {
                    if !frames.iter().any(|f| f == frame) {
                        frames.push(frame.to_owned());
                    }
                }
            }
        }
    }
    let choices = Choices {
        frames: FrameSelection::Listed(frames.iter().map(FrameSpec::link).collect()),
        ..Choices::default()
    };
    let path = workspace_root().join(format!("codegen/tests/data/loops/{name}.urdf"));
    let loaded = description::load_with(&path, &choices).unwrap_or_else(|e| panic!("{e}"));
    let joints: Vec<&str> = loaded.model.joints().iter().map(|j| j.name.as_str()).collect();
    let theirs: Vec<&str> = (fixture["joints"].as_array().unwrap().iter())
        .map(|j| j.as_str().unwrap())
        .collect();
    assert_eq!(joints, theirs, "the fixture's joints in another order");
    loaded
}

fn check_mechanism(name: &str) {
    let fx = fixture(name);
    let loaded = load(name, &fx);
    for (k, set) in fx["sets"].as_array().unwrap().iter().enumerate() {
        let contacts = floating_fixture::contacts(&loaded.model, set);
        let model = loaded.model.clone().with_contacts(contacts.clone()).unwrap();
        let dynamics = NumericDynamics::new(&model);
        let traced = trace(&model);
        // Rows that are not independent (the planar loop's zero row) need the proximal solve.
        let exact = !set["states"][0]["drift"].is_null();
        let settings = match exact {
            true => ProximalSettings::default(),
            false => floating_fixture::proximal(&fx),
        };
        for (s, st) in set["states"].as_array().unwrap().iter().enumerate() {
            let what = |q: &str| format!("{name} set {k} state {s}: {q}");
            let [q, v, tau] = ["q", "v", "tau"].map(|f| vector(&st[f]));
            let n = q.len();
            let rows = model.contact_rows();
            let evaluate = |f: &str| traced.evaluate(f, &q, &v, &[], &[]).unwrap();
            let j = DMatrix::from_column_slice(rows, n, &evaluate("contact_jacobian"));
            assert_close(&what("J"), &j, &matrix(&st["J"]), TOL);
            if exact {
                let drift = column(&evaluate("contact_drift"));
                assert_close(&what("drift"), &drift, &column(&vector(&st["drift"])), TOL);
            }
            let anchors = floating_fixture::anchors(st);
            for (label, stabilisation) in floating_fixture::solves(&fx, &anchors) {
                let expected = &st["forward"][label];
                let solved = dynamics
                    .constrained_forward_dynamics(&q, &v, &tau, &contacts, stabilisation, &settings)
                    .unwrap_or_else(|e| panic!("{}: {e}", what(label)));
                let acceleration = DMatrix::from_column_slice(n, 1, solved.acceleration.as_slice());
                let forces = DMatrix::from_column_slice(rows, 1, solved.forces.as_slice());
                assert_close(
                    &what(&format!("{label} q̈")),
                    &acceleration,
                    &column(&vector(&expected["ddq"])),
                    TOL,
                );
                assert_close(
                    &what(&format!("{label} λ")),
                    &forces,
                    &column(&vector(&expected["lambda"])),
                    TOL,
                );
                if expected["ddq_dq"].is_null() {
                    continue;
                }
                let frames = contacts.iter().any(|c| c.kind == ContactKind::Frame);
                let ours =
                    dynamics.constrained_forward_dynamics_derivatives(&q, &v, &tau, &contacts, stabilisation);
                if frames && stabilisation.is_some() {
                    let message = ours.expect_err("a stabilised frame contact").to_string();
                    assert!(message.contains("log₆"), "{message}");
                    continue;
                }
                let ours = ours.unwrap_or_else(|e| panic!("{}: {e}", what(label)));
                for (field, mine) in [
                    ("ddq_dq", &ours.acceleration_q),
                    ("ddq_dv", &ours.acceleration_v),
                    ("ddq_dtau", &ours.acceleration_tau),
                    ("dlambda_dq", &ours.forces_q),
                    ("dlambda_dv", &ours.forces_v),
                    ("dlambda_dtau", &ours.forces_tau),
                ] {
                    assert_close(
                        &what(&format!("{label} {field}")),
                        mine,
                        &matrix(&expected[field]),
                        TOL,
                    );
                }
            }
        }
    }
}

#[test]
fn a_four_bar_on_its_loop_matches_pinocchio() {
    check_mechanism("four_bar");
}

#[test]
fn spatial_loops_of_every_kind_and_axes_match_pinocchio() {
    check_mechanism("two_branches");
}

/// What Pinocchio does not hold for loops: an impact leaves the loop's rows at `−r` times their
/// velocity before it, changing momentum only along the rows; and the derivatives of a point
/// loop, plain and stabilised, are the central differences of the solution.
#[test]
fn loop_impulses_and_point_loop_derivatives_hold_their_equations() {
    let fx = fixture("two_branches");
    let loaded = load("two_branches", &fx);
    for set in fx["sets"].as_array().unwrap() {
        let contacts = floating_fixture::contacts(&loaded.model, set);
        let model = loaded.model.clone().with_contacts(contacts.clone()).unwrap();
        let dynamics = NumericDynamics::new(&model);
        let traced = trace(&model);
        let st = &set["states"][0];
        let [q, v, tau] = ["q", "v", "tau"].map(|f| vector(&st[f]));
        let (n, rows) = (q.len(), model.contact_rows());
        let j = DMatrix::from_column_slice(
            rows,
            n,
            &traced.evaluate("contact_jacobian", &q, &v, &[], &[]).unwrap(),
        );
        let restitution = 0.4;
        let (after, impulses) = dynamics
            .impulse_dynamics(&q, &v, &contacts, restitution, 0.0)
            .unwrap();
        let before = DVector::from_column_slice(&v);
        let residual = &j * &after + restitution * (&j * &before);
        assert!(
            residual.norm() <= 1e-10 * (&j * &before).norm(),
            "J v⁺ + r J v⁻ = {residual}"
        );
        let m = dynamics.mass_matrix(&q);
        let momentum = &m * (&after - &before) - j.transpose() * &impulses;
        assert!(
            momentum.norm() <= 1e-10 * impulses.norm(),
            "M Δv − Jᵀ Λ = {momentum}"
        );

        if contacts.iter().any(|c| c.kind == ContactKind::Frame) {
            continue;
        }
        let anchors = floating_fixture::anchors(st);
        for stabilisation in [
            None,
            Some(Stabilisation {
                anchors: &anchors,
                kp: 20.0,
                kd: 9.0,
            }),
        ] {
            let settings = ProximalSettings::default();
            let solve = |q: &[f64], v: &[f64], tau: &[f64]| {
                let m = dynamics
                    .constrained_forward_dynamics(q, v, tau, &contacts, stabilisation, &settings)
                    .unwrap();
                let mut out = m.acceleration.as_slice().to_vec();
                out.extend_from_slice(m.forces.as_slice());
                DVector::from_vec(out)
            };
            let ours = dynamics
                .constrained_forward_dynamics_derivatives(&q, &v, &tau, &contacts, stabilisation)
                .unwrap();
            let h = 1e-6;
            for (along, (acceleration, forces)) in [
                (0, (&ours.acceleration_q, &ours.forces_q)),
                (1, (&ours.acceleration_v, &ours.forces_v)),
                (2, (&ours.acceleration_tau, &ours.forces_tau)),
            ] {
                for c in 0..n {
                    let step = |sign: f64| {
                        let mut x = [q.clone(), v.clone(), tau.clone()];
                        x[along][c] += sign * h;
                        solve(&x[0], &x[1], &x[2])
                    };
                    let difference = (step(1.0) - step(-1.0)) / (2.0 * h);
                    let mut analytic = acceleration.column(c).into_owned().as_slice().to_vec();
                    analytic.extend_from_slice(forces.column(c).as_slice());
                    let analytic = DVector::from_vec(analytic);
                    let error = (&analytic - &difference).norm() / (1.0 + analytic.norm());
                    assert!(error < 1e-6, "∂/∂x[{along}][{c}]: {analytic} vs {difference}");
                }
            }
        }
    }
}

/// A loop between frames of one body holds nothing, and a frame named as its own `to` is one:
/// the model refuses both, naming the frames.
#[test]
fn a_loop_within_one_body_is_refused() {
    let fx = fixture("two_branches");
    let loaded = load("two_branches", &fx);
    let model = &loaded.model;
    // `a_mid` and `a_tip` are both on `a3`'s body… `a_tip` is on `a4`: hold `a_tip` to itself.
    let onto_itself = Contact::at(model, "a_tip", ContactKind::Point, ReferenceFrame::Local)
        .unwrap()
        .to(model, "a_tip")
        .unwrap();
    let message = model
        .clone()
        .with_contacts(vec![onto_itself])
        .unwrap_err()
        .to_string();
    assert!(
        message.contains("frames of one body") && message.contains("a_tip"),
        "{message}"
    );
}

/// A mechanism with one contact (the four-bar's loop) has its contact's poses written without
/// a `match` on the contact: one arm is what clippy refuses in generated code.
#[test]
fn one_contact_s_poses_are_written_without_a_match() {
    use dyngen_codegen::description::ContactSpec;
    let out = tempfile::tempdir().expect("a temporary directory");
    let report =
        dyngen_codegen::Builder::new(workspace_root().join("codegen/tests/data/loops/four_bar.urdf"))
            .frames(FrameSelection::Listed(vec![
                FrameSpec::link("coupler_end"),
                FrameSpec::link("rocker_end"),
            ]))
            .contact(ContactSpec::new("coupler_end", ContactKind::Point).to("rocker_end"))
            .out_dir(out.path())
            .cargo_directives(false)
            .compile_report()
            .unwrap_or_else(|e| panic!("{e}"));
    let code = &report.robot.code;
    for function in ["fn contact_pose(", "fn contact_to_pose("] {
        let at = code.find(function).unwrap_or_else(|| panic!("no {function}"));
        let body = &code[at..at + code[at..].find("\n    }\n").expect("its end")];
        assert!(
            body.contains("frame_pose(Frame::") && !body.contains("match"),
            "{body}"
        );
    }
}
