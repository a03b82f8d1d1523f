//! What the contact solves of a C library must give (`P_constrained_forward_dynamics`, plain
//! and stabilised, `P_impulse_dynamics`, `P_operational_space_inertia`): the generic dynamics'
//! constrained functions at the same state and settings, or the same refusal.

use super::build::{Library, CONTACT_SETTINGS};
use dyngen_codegen::dynamics::constrained::ConstraintError;
use dyngen_codegen::dynamics::{FloatingDynamics, NumericDynamics};
use dyngen_runtime::nalgebra::{DMatrix, DVector, Matrix3, Vector3};
use dyngen_runtime::{ContactError, Pose, ProximalSettings, Stabilisation};

/// The solves the C program writes, by the name of its result.
pub(super) const SOLVES: [&str; 4] = [
    "constrained_forward_dynamics",
    "constrained_forward_dynamics_stabilised",
    "impulse_dynamics",
    "operational_space_inertia",
];

/// dyngen.h's status codes the solves return besides `DYNGEN_OK`.
pub(super) const NOT_GENERATED: i32 = 5;
const CONTACT_SETTINGS_STATUS: i32 = 6;
pub(super) const REDUNDANT_CONTACTS: i32 = 7;

/// A solve's outputs, in the C program's order, or the status of its refusal.
pub(super) type Expected = Result<Vec<DMatrix<f64>>, i32>;

fn status(error: ConstraintError) -> i32 {
    match error {
        ConstraintError::Solve(ContactError::Redundant { .. }) => REDUNDANT_CONTACTS,
        ConstraintError::Solve(ContactError::Settings(_) | ContactError::Restitution(_)) => {
            CONTACT_SETTINGS_STATUS
        }
        other => panic!("the generic dynamics refused with {other}"),
    }
}

fn column(values: &DVector<f64>) -> DMatrix<f64> {
    DMatrix::from_column_slice(values.len(), 1, values.as_slice())
}

/// The anchors the test wrote for state `s`: the rotation's columns, then the translation.
fn anchors(library: &Library, s: usize) -> Vec<Pose> {
    (library.input("anchors", s).chunks_exact(12))
        .map(|a| Pose {
            rotation: Matrix3::from_column_slice(&a[..9]),
            translation: Vector3::from_column_slice(&a[9..]),
        })
        .collect()
}

/// Solve `function` of `library` at state `s`.
pub(super) fn expected(library: &Library, function: &str, s: usize) -> Expected {
    let model = &library.model;
    let contacts = model.contacts();
    if contacts.is_empty() {
        return Err(NOT_GENERATED);
    }
    let [mu, max_iterations, accuracy, kp, kd, restitution, damping] = CONTACT_SETTINGS;
    let proximal = ProximalSettings {
        mu,
        max_iterations: max_iterations as usize,
        accuracy,
    };
    let anchors = anchors(library, s);
    let stabilised = Stabilisation {
        anchors: &anchors,
        kp,
        kd,
    };
    let [q, qd, tau] = ["q", "qd", "tau"].map(|name| library.input(name, s));
    let exact = ProximalSettings::default();
    let pair = |(first, second): (DVector<f64>, DVector<f64>)| vec![column(&first), column(&second)];
    let motion =
        |m: dyngen_codegen::dynamics::constrained::ConstrainedMotion| pair((m.acceleration, m.forces));
    match model.floating_base() {
        None => {
            let generic = NumericDynamics::new(model);
            match function {
                "constrained_forward_dynamics" => generic
                    .constrained_forward_dynamics(q, qd, tau, contacts, None, &exact)
                    .map(motion),
                "constrained_forward_dynamics_stabilised" => generic
                    .constrained_forward_dynamics(q, qd, tau, contacts, Some(stabilised), &proximal)
                    .map(motion),
                "impulse_dynamics" => (generic.impulse_dynamics(q, qd, contacts, restitution, mu)).map(pair),
                _ => (generic.operational_space_inertia(q, contacts, damping)).map(|m| vec![m]),
            }
        }
        Some(_) => {
            let generic = FloatingDynamics::new(model).expect("a floating base");
            let st = generic.state(q).expect("a unit quaternion");
            match function {
                "constrained_forward_dynamics" => generic
                    .constrained_forward_dynamics(&st, qd, tau, contacts, None, &exact)
                    .map(motion),
                "constrained_forward_dynamics_stabilised" => generic
                    .constrained_forward_dynamics(&st, qd, tau, contacts, Some(stabilised), &proximal)
                    .map(motion),
                "impulse_dynamics" => {
                    (generic.impulse_dynamics(&st, qd, contacts, restitution, mu)).map(pair)
                }
                _ => (generic.operational_space_inertia(&st, contacts, damping)).map(|m| vec![m]),
            }
        }
    }
    .map_err(status)
}
