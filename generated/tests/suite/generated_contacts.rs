//! The compiled Solo-12 with its four feet held (`robots/solo12.yaml`, `contacts:`): the
//! runtime's constrained functions over its generated `ContactDynamics` against Pinocchio 4.1's
//! `constraintDynamics` and `impulseDynamics` (`codegen/tests/fixtures/constrained/solo12.json`)
//! and against the generic dynamics at random states, stabilised or not, exact and proximal.

use dyngen_testkit as common;

use common::fixture::{matrix, vector};
use common::floating_fixture::{self, Order};
use common::{assert_close, column, workspace_root};
use dyngen_codegen::description::load;
use dyngen_codegen::dynamics::FloatingDynamics;
use dyngen_codegen::model::Model;
use dyngen_generated::solo12::{self, Solo12, Velocity, NV};
use dyngen_runtime::nalgebra::Const;
use dyngen_runtime::nalgebra::{DMatrix, Matrix3, SMatrix, Vector3};
use dyngen_runtime::{
    constrained_forward_dynamics, constrained_forward_dynamics_derivatives, impulse_dynamics,
    operational_space_inertia, ConstrainedDerivatives, ContactDynamics, Pose, ProximalSettings, SplitMix64,
    Stabilisation,
};

const TOL_FIXTURE: f64 = 1e-9;
const TOL_GENERIC: f64 = 1e-10;
/// The derivatives against the generic dynamics' (dual numbers one direction at a time, a solve
/// per column), relative to the largest entry.
const TOL_DERIVATIVES: f64 = 1e-12;

fn dm<const R: usize, const C: usize>(m: &SMatrix<f64, R, C>) -> DMatrix<f64> {
    DMatrix::from_column_slice(R, C, m.as_slice())
}

fn model() -> Model {
    load(&workspace_root().join("robots/solo12.yaml")).unwrap().model
}

#[test]
fn the_contacts_are_the_descriptions() {
    let model = model();
    let frames: Vec<&str> = model
        .contacts()
        .iter()
        .map(|c| model.frames()[c.frame].name.as_str())
        .collect();
    assert_eq!(Solo12::CONTACT_FRAMES, frames.as_slice());
    let kinds: Vec<_> = model.contacts().iter().map(|c| c.kind).collect();
    assert_eq!(Solo12::CONTACT_KINDS, kinds.as_slice());
    let references: Vec<_> = model.contacts().iter().map(|c| c.reference).collect();
    assert_eq!(Solo12::CONTACT_REFERENCES, references.as_slice());
}

#[test]
fn solo12_on_its_feet_matches_pinocchio() {
    let model = model();
    let fx = floating_fixture::load_constrained("solo12");
    let order = Order::new(&model, &fx);
    // The fixture holds the same feet in the same order and axes.
    let held: Vec<&str> = fx["contacts"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c["frame"].as_str().unwrap())
        .collect();
    assert_eq!(Solo12::CONTACT_FRAMES, held.as_slice());
    let kp = fx["baumgarte"]["kp"].as_f64().unwrap();
    let kd = fx["baumgarte"]["kd"].as_f64().unwrap();
    let proximal = ProximalSettings {
        mu: fx["proximal"]["mu"].as_f64().unwrap(),
        max_iterations: fx["proximal"]["max_iter"].as_u64().unwrap() as usize,
        accuracy: fx["proximal"]["accuracy"].as_f64().unwrap(),
    };
    let restitution = fx["restitution"].as_f64().unwrap();
    for (k, st) in fx["states"].as_array().unwrap().iter().enumerate() {
        let what = |q: &str| format!("state {k}: {q}");
        let q = order.configuration(&vector(&st["q"]));
        let t = solo12::trig(&solo12::Configuration::from_column_slice(&q)).unwrap();
        let [v, tau] = ["v", "tau"].map(|f| Velocity::from_column_slice(&order.vector(&vector(&st[f]))));
        let velocity = |field| column(&order.vector(&vector(field)));
        let anchors: Vec<Pose> = st["anchors"]
            .as_array()
            .unwrap()
            .iter()
            .map(|a| {
                let r = matrix(&a["rotation"]);
                Pose {
                    rotation: Matrix3::from_fn(|i, j| r[(i, j)]),
                    translation: Vector3::from_column_slice(&vector(&a["translation"])),
                }
            })
            .collect();
        for (label, stabilisation) in [
            ("plain", None),
            (
                "stabilised",
                Some(Stabilisation {
                    anchors: &anchors,
                    kp,
                    kd,
                }),
            ),
        ] {
            let expected = &st["forward"][label];
            for settings in [ProximalSettings::default(), proximal] {
                let solved = constrained_forward_dynamics::<Solo12, 18, 12>(
                    &t,
                    &v,
                    &tau,
                    stabilisation,
                    &settings,
                    None,
                )
                .unwrap_or_else(|e| panic!("{}: {e}", what(label)));
                assert_close(
                    &what(&format!("{label} ν̇")),
                    &dm(&solved.acceleration),
                    &velocity(&expected["ddq"]),
                    TOL_FIXTURE,
                );
                assert_close(
                    &what(&format!("{label} λ")),
                    &dm(&solved.forces),
                    &column(&vector(&expected["lambda"])),
                    TOL_FIXTURE,
                );
            }
        }
        for (field, mu) in [
            ("impulse", 0.0),
            ("impulse_damped", fx["damped_mu"].as_f64().unwrap()),
        ] {
            let (after, impulses) = impulse_dynamics::<Solo12, 18, 12>(&t, &v, restitution, mu).unwrap();
            assert_close(
                &what(field),
                &dm(&after),
                &velocity(&st[field]["v_after"]),
                TOL_FIXTURE,
            );
            assert_close(
                &what(field),
                &dm(&impulses),
                &column(&vector(&st[field]["impulse"])),
                TOL_FIXTURE,
            );
        }
        let m = order.square(st, "M");
        let j = order.matrix(&matrix(&st["J"]), false, true);
        assert_close(&what("J"), &dm(&Solo12::contact_jacobian(&t)), &j, TOL_FIXTURE);
        let expected = (&j * m.try_inverse().unwrap() * j.transpose())
            .try_inverse()
            .unwrap();
        let lambda = operational_space_inertia::<Solo12, 18, 12>(&t, 0.0).unwrap();
        assert_close(&what("Λ"), &dm(&lambda), &expected, TOL_FIXTURE);
    }
}

/// A configuration (its quaternion normalised), a velocity and torques, drawn from `rng`.
fn random_state(rng: &mut SplitMix64) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let mut q: Vec<f64> = (0..19).map(|_| rng.uniform((-3.0, 3.0))).collect();
    let norm = q[3..7].iter().map(|x| x * x).sum::<f64>().sqrt();
    q[3..7].iter_mut().for_each(|x| *x /= norm);
    let [v, tau] = [0; 2].map(|_| (0..NV).map(|_| rng.uniform((-4.0, 4.0))).collect::<Vec<f64>>());
    (q, v, tau)
}

#[test]
fn solo12_on_its_feet_matches_the_generic_dynamics() {
    let model = model();
    let generic = FloatingDynamics::new(&model).unwrap();
    let mut rng = SplitMix64::new(57);
    for k in 0..50 {
        let what = |q: &str| format!("state {k}: {q}");
        let (q, v, tau) = random_state(&mut rng);
        let t = solo12::trig(&solo12::Configuration::from_column_slice(&q)).unwrap();
        let s = generic.state(&q).unwrap();
        // Each foot held 1 to 3 cm from where it is, turned a little.
        let anchors: Vec<Pose> = (0..4)
            .map(|c| {
                let at = Solo12::contact_pose(&t, c);
                let offset = Vector3::from_fn(|_, _| rng.uniform((-0.03, 0.03)));
                Pose {
                    rotation: at.rotation * Matrix3::new_rotation(rng.uniform((-0.2, 0.2))),
                    translation: at.translation + offset,
                }
            })
            .collect();
        let stabilisation = Some(Stabilisation {
            anchors: &anchors,
            kp: 30.0,
            kd: 11.0,
        });
        let settings = ProximalSettings {
            mu: 1e-6,
            max_iterations: 50,
            accuracy: 1e-13,
        };
        let (vv, tauv) = (Velocity::from_column_slice(&v), Velocity::from_column_slice(&tau));
        let ours =
            constrained_forward_dynamics::<Solo12, 18, 12>(&t, &vv, &tauv, stabilisation, &settings, None)
                .unwrap();
        let theirs = generic
            .constrained_forward_dynamics(&s, &v, &tau, model.contacts(), stabilisation, &settings)
            .unwrap();
        assert_close(
            &what("ν̇"),
            &dm(&ours.acceleration),
            &column(theirs.acceleration.as_slice()),
            TOL_GENERIC,
        );
        assert_close(
            &what("λ"),
            &dm(&ours.forces),
            &column(theirs.forces.as_slice()),
            TOL_GENERIC,
        );
        let (after, impulses) = impulse_dynamics::<Solo12, 18, 12>(&t, &vv, 0.5, 0.0).unwrap();
        let (after_generic, impulses_generic) = generic
            .impulse_dynamics(&s, &v, model.contacts(), 0.5, 0.0)
            .unwrap();
        assert_close(
            &what("ν⁺"),
            &dm(&after),
            &column(after_generic.as_slice()),
            TOL_GENERIC,
        );
        assert_close(
            &what("Λ"),
            &dm(&impulses),
            &column(impulses_generic.as_slice()),
            TOL_GENERIC,
        );
        let lambda = operational_space_inertia::<Solo12, 18, 12>(&t, 1e-8).unwrap();
        let lambda_generic = generic
            .operational_space_inertia(&s, model.contacts(), 1e-8)
            .unwrap();
        assert_close(&what("Λ_c"), &dm(&lambda), &lambda_generic, 1e-9);
    }
}

/// `constrained_forward_dynamics_derivatives` over the compiled Solo-12's rows, plain and
/// Baumgarte-stabilised (two feet in local axes, whose error turns with the foot, two in
/// world-aligned ones), at the exact solution: Pinocchio's `computeConstraintDynamicsDerivatives`
/// at the fixture's states, the generic dynamics' derivatives at random ones with drifted
/// anchors and gains of their own.
#[test]
fn solo12_derivatives_match_pinocchio_and_the_generic_dynamics() {
    let model = model();
    let generic = FloatingDynamics::new(&model).unwrap();
    let fx = floating_fixture::load_constrained("solo12");
    let order = Order::new(&model, &fx);
    let exact = ProximalSettings::default();
    let check =
        |what: &str, ours: &ConstrainedDerivatives<Const<NV>, Const<12>>, theirs: [DMatrix<f64>; 6], tol| {
            let mine = [
                dm(&ours.acceleration_q),
                dm(&ours.acceleration_v),
                dm(&ours.acceleration_tau),
                dm(&ours.forces_q),
                dm(&ours.forces_v),
                dm(&ours.forces_tau),
            ];
            let names = ["∂ν̇/∂q", "∂ν̇/∂ν", "∂ν̇/∂τ", "∂λ/∂q", "∂λ/∂ν", "∂λ/∂τ"];
            for ((name, mine), theirs) in names.iter().zip(&mine).zip(&theirs) {
                assert_close(&format!("{what} {name}"), mine, theirs, tol);
            }
        };
    for (k, st) in fx["states"].as_array().unwrap().iter().enumerate() {
        let q = order.configuration(&vector(&st["q"]));
        let t = solo12::trig(&solo12::Configuration::from_column_slice(&q)).unwrap();
        let [v, tau] = ["v", "tau"].map(|f| Velocity::from_column_slice(&order.vector(&vector(&st[f]))));
        let anchors = floating_fixture::anchors(st);
        for (label, stabilisation) in floating_fixture::solves(&fx, &anchors) {
            let solved =
                constrained_forward_dynamics::<Solo12, 18, 12>(&t, &v, &tau, stabilisation, &exact, None)
                    .unwrap();
            let ours =
                constrained_forward_dynamics_derivatives::<Solo12, 18, 12>(&t, &v, &solved, stabilisation)
                    .unwrap();
            let expected = &st["forward"][label];
            let theirs = [
                "ddq_dq",
                "ddq_dv",
                "ddq_dtau",
                "dlambda_dq",
                "dlambda_dv",
                "dlambda_dtau",
            ]
            .map(|f| order.matrix(&matrix(&expected[f]), f.starts_with("ddq"), true));
            check(&format!("state {k} {label}"), &ours, theirs, TOL_FIXTURE);
        }
    }
    let mut rng = SplitMix64::new(91);
    for k in 0..20 {
        let (q, v, tau) = random_state(&mut rng);
        let t = solo12::trig(&solo12::Configuration::from_column_slice(&q)).unwrap();
        let s = generic.state(&q).unwrap();
        let anchors: Vec<Pose> = (0..4)
            .map(|c| {
                let at = Solo12::contact_pose(&t, c);
                Pose {
                    rotation: at.rotation,
                    translation: at.translation + Vector3::from_fn(|_, _| rng.uniform((-0.03, 0.03))),
                }
            })
            .collect();
        for stabilisation in [
            None,
            Some(Stabilisation {
                anchors: &anchors,
                kp: 30.0,
                kd: 11.0,
            }),
        ] {
            let (vv, tauv) = (Velocity::from_column_slice(&v), Velocity::from_column_slice(&tau));
            let solved =
                constrained_forward_dynamics::<Solo12, 18, 12>(&t, &vv, &tauv, stabilisation, &exact, None)
                    .unwrap();
            let ours =
                constrained_forward_dynamics_derivatives::<Solo12, 18, 12>(&t, &vv, &solved, stabilisation)
                    .unwrap();
            let theirs = generic
                .constrained_forward_dynamics_derivatives(&s, &v, &tau, model.contacts(), stabilisation)
                .unwrap();
            let what = format!("state {k} stabilised {}", stabilisation.is_some());
            let theirs = [
                theirs.acceleration_q,
                theirs.acceleration_v,
                theirs.acceleration_tau,
                theirs.forces_q,
                theirs.forces_v,
                theirs.forces_tau,
            ];
            check(&what, &ours, theirs, TOL_DERIVATIVES);
        }
    }
}
