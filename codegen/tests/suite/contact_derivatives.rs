//! The traced pieces of constrained forward dynamics' derivatives
//! (`contact_forward_dynamics_derivatives`, `contact_acceleration_derivatives`, with `J`,
//! `M⁻¹ Jᵀ` and `M⁻¹`), evaluated by the interpreter and assembled by the runtime's
//! `assemble_derivatives`, on every constrained fixture robot: against the generic dynamics'
//! derivatives (1e-12 relative, computed by another route: dual numbers one direction at a
//! time and a fresh solve per column) and Pinocchio 4.1's `computeConstraintDynamicsDerivatives`
//! (1e-9), Solo-12 on four point feet and the G1 on two flat feet (floating), two branches
//! held tip to tip as frames; a point loop against central differences of the constrained
//! forward dynamics solved from the traced rows; the four-bar's dependent rows refused as the
//! generic dynamics refuse them. Baumgarte terms are the runtime's (`generated_contacts.rs`).

use dyngen_testkit as common;

use common::assert_close;
use common::fixture::{matrix, vector};
use common::floating_fixture::{self, Order};
use dyngen_codegen::dynamics::{ConstrainedDerivatives, FloatingDynamics, NumericDynamics};
use dyngen_codegen::internals::generate::{trace, Arguments, SymbolicRobot};
use dyngen_codegen::model::Model;
use dyngen_runtime::{assemble_derivatives, solve_contacts, ContactError, ProximalSettings};
use nalgebra::{DMatrix, DVector};
use serde_json::Value;

const TOL_GENERIC: f64 = 1e-12;
const TOL_FIXTURE: f64 = 1e-9;

/// The derivatives assembled from the traced pieces at configuration `q` (a floating base's
/// whole configuration), velocity `v` and solution `(a, λ)`.
fn assembled(
    traced: &SymbolicRobot,
    q: &[f64],
    v: &[f64],
    a: &[f64],
    lambda: &[f64],
) -> Result<ConstrainedDerivatives, ContactError> {
    let (nv, nc) = (v.len(), lambda.len());
    let args = Arguments {
        q,
        qd: v,
        a,
        forces: lambda,
        ..Arguments::default()
    };
    let value = |name: &str| traced.evaluate_with(name, &args).expect(name);
    let matrix = |name: &str, rows: usize, cols: usize| DMatrix::from_column_slice(rows, cols, &value(name));
    let pair = |name: &str, rows: usize| {
        let values = value(name);
        let (first, second) = values.split_at(rows * nv);
        (
            DMatrix::from_column_slice(rows, nv, first),
            DMatrix::from_column_slice(rows, nv, second),
        )
    };
    assemble_derivatives(
        &matrix("contact_jacobian", nc, nv),
        &matrix("contact_response", nv, nc),
        matrix("mass_matrix_inverse", nv, nv),
        pair("contact_forward_dynamics_derivatives", nv),
        pair("contact_acceleration_derivatives", nc),
    )
}

/// The six matrices, named as Pinocchio's fixture names them.
fn fields(d: &ConstrainedDerivatives) -> [(&'static str, &DMatrix<f64>); 6] {
    [
        ("ddq_dq", &d.acceleration_q),
        ("ddq_dv", &d.acceleration_v),
        ("ddq_dtau", &d.acceleration_tau),
        ("dlambda_dq", &d.forces_q),
        ("dlambda_dv", &d.forces_v),
        ("dlambda_dtau", &d.forces_tau),
    ]
}

fn check_floating(robot: &str, urdf: &str) {
    let fx = floating_fixture::load_constrained(robot);
    let loaded = crate::constrained_reference::load(urdf, &fx);
    let contacts = floating_fixture::contacts(&loaded.model, &fx);
    let model = loaded.model.clone().with_contacts(contacts.clone()).unwrap();
    let order = Order::new(&model, &fx);
    let dynamics = FloatingDynamics::new(&model).unwrap();
    let traced = trace(&model);
    for (k, st) in fx["states"].as_array().unwrap().iter().enumerate() {
        let what = |q: &str| format!("{robot} state {k}: {q}");
        let q = order.configuration(&vector(&st["q"]));
        let [v, tau] = ["v", "tau"].map(|f| order.vector(&vector(&st[f])));
        let s = dynamics.state(&q).unwrap();
        let exact = ProximalSettings::default();
        let solved = (dynamics.constrained_forward_dynamics(&s, &v, &tau, &contacts, None, &exact)).unwrap();
        let ours = assembled(
            &traced,
            &q,
            &v,
            solved.acceleration.as_slice(),
            solved.forces.as_slice(),
        )
        .unwrap_or_else(|e| panic!("{}: {e}", what("assembled")));
        let generic =
            (dynamics.constrained_forward_dynamics_derivatives(&s, &v, &tau, &contacts, None)).unwrap();
        let expected = &st["forward"]["plain"];
        for ((field, mine), (_, theirs)) in fields(&ours).into_iter().zip(fields(&generic)) {
            assert_close(&what(&format!("{field} (generic)")), mine, theirs, TOL_GENERIC);
            let pinocchio = order.matrix(&matrix(&expected[field]), field.starts_with("ddq"), true);
            assert_close(
                &what(&format!("{field} (Pinocchio)")),
                mine,
                &pinocchio,
                TOL_FIXTURE,
            );
        }
    }
}

#[test]
fn solo12_on_four_point_feet_matches_the_generic_dynamics_and_pinocchio() {
    check_floating("solo12", "solo_description/solo12.urdf");
}

#[test]
fn g1_on_two_flat_feet_matches_the_generic_dynamics_and_pinocchio() {
    check_floating("g1", "g1_description/g1_29dof_rev_1_0.urdf");
}

fn loop_fixture(name: &str) -> Value {
    crate::loop_closures::fixture(name)
}

/// Mechanism `name` with every frame its fixture's sets name, and set `k`'s contacts.
fn loop_model(name: &str, fx: &Value, k: usize) -> Model {
    let loaded = crate::loop_closures::load(name, fx);
    let contacts = floating_fixture::contacts(&loaded.model, &fx["sets"][k]);
    loaded.model.with_contacts(contacts).unwrap()
}

#[test]
fn loops_held_as_frames_match_the_generic_dynamics_and_pinocchio() {
    let fx = loop_fixture("two_branches");
    let mut checked = 0;
    for (k, set) in fx["sets"].as_array().unwrap().iter().enumerate() {
        if set["states"][0]["forward"]["plain"]["ddq_dq"].is_null() {
            continue;
        }
        let model = loop_model("two_branches", &fx, k);
        let (dynamics, traced) = (NumericDynamics::new(&model), trace(&model));
        for (s, st) in set["states"].as_array().unwrap().iter().enumerate() {
            let what = |q: &str| format!("set {k} state {s}: {q}");
            let [q, v, tau] = ["q", "v", "tau"].map(|f| vector(&st[f]));
            let exact = ProximalSettings::default();
            let contacts = model.contacts();
            let solved = dynamics
                .constrained_forward_dynamics(&q, &v, &tau, contacts, None, &exact)
                .unwrap();
            let ours = assembled(
                &traced,
                &q,
                &v,
                solved.acceleration.as_slice(),
                solved.forces.as_slice(),
            )
            .unwrap();
            let generic =
                (dynamics.constrained_forward_dynamics_derivatives(&q, &v, &tau, contacts, None)).unwrap();
            for ((field, mine), (_, theirs)) in fields(&ours).into_iter().zip(fields(&generic)) {
                assert_close(&what(&format!("{field} (generic)")), mine, theirs, TOL_GENERIC);
                let pinocchio = matrix(&st["forward"]["plain"][field]);
                assert_close(
                    &what(&format!("{field} (Pinocchio)")),
                    mine,
                    &pinocchio,
                    TOL_FIXTURE,
                );
            }
            checked += 1;
        }
    }
    assert!(checked >= 2, "the fixture's frame loops were not found");
}

/// The constrained forward dynamics of the traced rows (`J`, drift, `M⁻¹ Jᵀ`, forward
/// dynamics) at `(q, v, τ)`, solved exactly: `(a, λ)` stacked.
fn traced_solution(traced: &SymbolicRobot, nc: usize, q: &[f64], v: &[f64], tau: &[f64]) -> DVector<f64> {
    let nv = v.len();
    let args = Arguments {
        q,
        qd: v,
        tau,
        ..Arguments::default()
    };
    let value = |name: &str| DVector::from_vec(traced.evaluate_with(name, &args).unwrap());
    let jacobian = DMatrix::from_column_slice(nc, nv, value("contact_jacobian").as_slice());
    let response = DMatrix::from_column_slice(nv, nc, value("contact_response").as_slice());
    let solved = solve_contacts(
        &jacobian,
        &response,
        &value("forward_dynamics"),
        &-value("contact_drift"),
        &ProximalSettings::default(),
        None,
    )
    .unwrap();
    let mut out = solved.acceleration.as_slice().to_vec();
    out.extend_from_slice(solved.forces.as_slice());
    DVector::from_vec(out)
}

#[test]
fn a_point_loop_changes_as_its_traced_solution_does() {
    let fx = loop_fixture("two_branches");
    // Set 0: the branches' tips held together as points in local axes.
    assert_eq!(fx["sets"][0]["contacts"][0]["kind"], "point");
    let model = loop_model("two_branches", &fx, 0);
    let traced = trace(&model);
    let (nv, nc) = (model.nv(), model.contact_rows());
    for st in fx["sets"][0]["states"].as_array().unwrap() {
        let [q, v, tau] = ["q", "v", "tau"].map(|f| vector(&st[f]));
        let at = traced_solution(&traced, nc, &q, &v, &tau);
        let ours = assembled(&traced, &q, &v, &at.as_slice()[..nv], &at.as_slice()[nv..]).unwrap();
        let h = 1e-6;
        for (x, acceleration, forces) in [
            (0, &ours.acceleration_q, &ours.forces_q),
            (1, &ours.acceleration_v, &ours.forces_v),
            (2, &ours.acceleration_tau, &ours.forces_tau),
        ] {
            let mut differences = DMatrix::zeros(nv + nc, nv);
            for c in 0..nv {
                let moved = |sign: f64| {
                    let mut state = [q.clone(), v.clone(), tau.clone()];
                    state[x][c] += sign * h;
                    traced_solution(&traced, nc, &state[0], &state[1], &state[2])
                };
                differences.set_column(c, &((moved(1.0) - moved(-1.0)) / (2.0 * h)));
            }
            let mut derivative = DMatrix::zeros(nv + nc, nv);
            derivative.rows_mut(0, nv).copy_from(acceleration);
            derivative.rows_mut(nv, nc).copy_from(forces);
            assert_close(&format!("direction {x}"), &derivative, &differences, 1e-6);
        }
    }
}

#[test]
fn dependent_rows_are_refused_as_the_generic_dynamics_refuse_them() {
    let fx = loop_fixture("four_bar");
    let model = loop_model("four_bar", &fx, 0);
    let (dynamics, traced) = (NumericDynamics::new(&model), trace(&model));
    let st = &fx["sets"][0]["states"][0];
    let [q, v, tau] = ["q", "v", "tau"].map(|f| vector(&st[f]));
    let lambda = vec![0.0; model.contact_rows()];
    let ours = assembled(&traced, &q, &v, &vec![0.0; v.len()], &lambda).unwrap_err();
    assert!(matches!(ours, ContactError::Redundant { .. }), "{ours}");
    let generic = dynamics.constrained_forward_dynamics_derivatives(&q, &v, &tau, model.contacts(), None);
    assert_eq!(generic.unwrap_err().to_string(), ours.to_string());
}
