//! The symbolic graph, evaluated by the interpreter, against the generic f64 dynamics: the
//! simplifier may reorder and fold, but never change a value.

use dyngen_testkit as common;

use common::random_model::{arb_model_and_state, deterministic_runner};
use common::{assert_close, fixture, traced};
use dyngen_codegen::dynamics::NumericDynamics;
use dyngen_codegen::internals::generate::{trace, Arguments, QuantityKind, SymbolicRobot};
use dyngen_codegen::model::Model;
use nalgebra::{DMatrix, DVector};
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
    // The regressor products (inputs θ and r of their own) against the products of `Y`.
    let y = generic.regressor(q, qd, v, a);
    let all: Vec<usize> = (0..y.ncols()).collect();
    for (name, cols) in [
        ("regressor_products", &all),
        (QuantityKind::BaseRegressorProducts.name(), &robot.base.columns),
    ] {
        let theta: Vec<f64> = (0..cols.len())
            .map(|k| ((k * 7 % 11) as f64 - 5.0) / 5.0)
            .collect();
        let r: Vec<f64> = (0..qd.len()).map(|k| ((k * 3 % 5) as f64 - 2.0) / 2.0).collect();
        let args = Arguments {
            q,
            qd,
            v,
            a,
            theta: &theta,
            r: &r,
            ..Arguments::default()
        };
        let values = robot.evaluate_with(name, &args).expect("quantity exists");
        let y_cols = y.select_columns(cols);
        let mut want = (&y_cols * DVector::from_column_slice(&theta)).as_slice().to_vec();
        want.extend(y_cols.tr_mul(&DVector::from_column_slice(&r)).iter());
        let column = |x: &[f64]| DMatrix::from_column_slice(x.len(), 1, x);
        assert_close(
            &format!("{} {name}", model.name()),
            &column(&values),
            &column(&want),
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
                qn.name(),
                c.mul,
                c.add,
                c.neg,
                c.trig
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
