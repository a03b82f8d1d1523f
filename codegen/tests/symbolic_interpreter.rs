//! The symbolic graph, evaluated by the interpreter, against the generic f64 dynamics: the
//! simplifier may reorder and fold, but never change a value.

use dyngen_testkit as common;

use common::random_model::{arb_model_and_state, deterministic_runner};
use common::{assert_close, fixture};
use dyngen_codegen::dynamics::NumericDynamics;
use dyngen_codegen::generate::{trace, Shape, SymbolicRobot};
use dyngen_codegen::model::Model;
use nalgebra::DMatrix;
use std::cell::Cell;

const TOL: f64 = 1e-10;

/// The interpreter's value of a quantity, in the shape the generic code returns.
fn interpreted(
    robot: &SymbolicRobot,
    name: &str,
    q: &[f64],
    qd: &[f64],
    v: &[f64],
    a: &[f64],
) -> DMatrix<f64> {
    let values = robot.evaluate(name, q, qd, v, a).expect("quantity exists");
    match robot.quantity(name).expect("quantity").shape {
        Shape::Vector(n) => DMatrix::from_column_slice(n, 1, &values),
        Shape::Matrix(r, c) => DMatrix::from_column_slice(r, c, &values),
        Shape::Pose => DMatrix::from_column_slice(12, 1, &values),
        // The two matrices side by side (both column-major, so one n × 2n matrix).
        Shape::MatrixPair(n) => DMatrix::from_column_slice(n, 2 * n, &values),
        // Pose, J and J̇ one after the other, as one column.
        Shape::Kinematics(_) => DMatrix::from_column_slice(values.len(), 1, &values),
    }
}

/// Compares every traced quantity with the generic implementation at one state.
fn check_state(model: &Model, robot: &SymbolicRobot, q: &[f64], qd: &[f64], v: &[f64], a: &[f64]) {
    let generic = NumericDynamics::new(model);
    let n = model.dof();
    let vec = |x: nalgebra::DVector<f64>| DMatrix::from_column_slice(n, 1, x.as_slice());
    let (rot, pos) = generic.end_effector_pose(q);
    let mut pose = rot.as_slice().to_vec();
    pose.extend(pos.iter());
    let expected = [
        ("forward_kinematics", DMatrix::from_column_slice(12, 1, &pose)),
        ("jacobian", generic.jacobian(q)),
        ("jacobian_dot", generic.jacobian_dot(q, qd)),
        ("mass_matrix", generic.mass_matrix(q)),
        ("coriolis_matrix", generic.coriolis_matrix(q, qd)),
        ("gravity", vec(generic.gravity_torque(q))),
        ("inverse_dynamics", vec(generic.inverse_dynamics(q, qd, a))),
        ("slotine_li", vec(generic.slotine_li(q, qd, v, a, true))),
        ("regressor", generic.regressor(q, qd, v, a)),
        (
            "base_regressor",
            robot.base.base_regressor(&generic.regressor(q, qd, v, a)),
        ),
        ("torque_regressor", generic.regressor(q, qd, qd, a)),
        (
            "base_torque_regressor",
            robot.base.base_regressor(&generic.regressor(q, qd, qd, a)),
        ),
        ("kinematics", {
            let mut all = pose.clone();
            all.extend(generic.jacobian(q).iter());
            all.extend(generic.jacobian_dot(q, qd).iter());
            DMatrix::from_column_slice(all.len(), 1, &all)
        }),
    ];
    for (name, want) in expected {
        assert_close(
            &format!("{} {name}", model.name()),
            &interpreted(robot, name, q, qd, v, a),
            &want,
            TOL,
        );
    }
}

#[test]
fn fixture_robots_interpreted_graph_matches_generic_dynamics() {
    for name in ["panda", "ur5"] {
        let fx = fixture::load(name);
        let model = fx.model();
        let robot = trace(&model);
        for s in &fx.states {
            check_state(&model, &robot, &s.q, &s.v, &s.vr, &s.ar);
        }
        for qn in &robot.quantities {
            let c = robot.graph.op_counts(&qn.outputs);
            eprintln!(
                "{name} {:<20} mul {:>5} add {:>5} neg {:>4} trig {}",
                qn.name, c.mul, c.add, c.neg, c.trig
            );
        }
    }
}

/// The whole pipeline's maths (trace, fold, share) on random trees: branches, prismatic
/// joints, skew axes, products of inertia, gravity in any direction.
#[test]
fn random_trees_interpreted_graph_matches_generic_dynamics() {
    let models = Cell::new(0);
    let result = deterministic_runner(200).run(&arb_model_and_state(10), |(model, s)| {
        let robot = trace(&model);
        check_state(&model, &robot, &s.q, &s.qd, &s.v, &s.a);
        models.set(models.get() + 1);
        Ok(())
    });
    if let Err(e) = result {
        panic!("{e}");
    }
    assert_eq!(models.get(), 200, "every random tree was checked");
}
