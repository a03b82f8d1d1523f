//! The symbolic graph, evaluated by the interpreter, against the generic f64 dynamics: the
//! simplifier may reorder and fold, but never change a value.

use dyngen_testkit as common;

use common::random_model::{arb_model_and_state, deterministic_runner};
use common::{assert_close, fixture, traced};
use dyngen_codegen::dynamics::NumericDynamics;
use dyngen_codegen::generate::{trace, SymbolicRobot};
use dyngen_codegen::model::Model;
use std::cell::Cell;

const TOL: f64 = 1e-10;

/// Compares every traced quantity with the generic implementation at one state.
fn check_state(model: &Model, robot: &SymbolicRobot, q: &[f64], qd: &[f64], v: &[f64], a: &[f64]) {
    let generic = NumericDynamics::new(model);
    for (name, want) in traced::generic_values(robot, &generic, [q, qd, v, a]) {
        let values = robot.evaluate(name, q, qd, v, a).expect("quantity exists");
        assert_close(
            &format!("{} {name}", model.name()),
            &traced::shaped(robot, name, values),
            &want,
            TOL,
        );
    }
}

#[test]
fn fixture_robots_interpreted_graph_matches_generic_dynamics() {
    for name in ["panda", "panda_rounded", "ur5"] {
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
