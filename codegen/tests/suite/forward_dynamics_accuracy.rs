//! Forward dynamics as accurate as the conditioning of `D` allows. Each `q̈` (the generic `f64`
//! algorithm, and the traced graph that generated code is emitted from, interpreted) is held to
//! `ACCURACY` units of `ε·(cond₂(D)‖q̈‖ + (‖τ‖ + ‖C q̇ + g‖)/σ_min(D))`, what a backward-stable
//! computation may lose, against the same problem solved in double-double precision
//! (`dyngen_testkit::reference_solve`): the committed robots, vendor URDFs, chains whose links
//! get lighter by four orders of magnitude towards the tool (with and without a heavy tool), and
//! random trees.

use dyngen_codegen::description::{load, load_yaml_str};
use dyngen_codegen::dynamics::NumericDynamics;
use dyngen_codegen::internals::generate::trace;
use dyngen_codegen::model::Model;
use dyngen_runtime::SplitMix64;
use dyngen_testkit::random_model::{arb_model_and_state, deterministic_runner};
use dyngen_testkit::reference_solve::error_in_stable_units;
use dyngen_testkit::workspace_root;
use std::cell::Cell;
use std::path::Path;

/// A backward-stable computation stays within a small multiple of the unit.
const ACCURACY: f64 = 10.0;

/// Both `q̈` of `model` at random states within ACCURACY; the worst ratio seen.
fn check(name: &str, model: &Model, states: usize, seed: u64) -> f64 {
    let n = model.dof();
    let theta = model.parameters();
    let numeric = NumericDynamics::new(model);
    let traced = trace(model);
    let mut rng = SplitMix64::new(seed);
    let mut worst: f64 = 0.0;
    for _ in 0..states {
        let mut vector = |r: f64| -> Vec<f64> { (0..n).map(|_| rng.uniform((-r, r))).collect() };
        let (q, qd, tau) = (vector(2.5), vector(1.5), vector(20.0));
        let generic: Vec<f64> = numeric.forward_dynamics(&q, &qd, &tau).iter().copied().collect();
        let interpreted = traced
            .evaluate_tau("forward_dynamics", &q, &qd, &tau)
            .expect("traced");
        for (what, got) in [("generic", &generic), ("traced", &interpreted)] {
            let ratio = error_in_stable_units(got, model, &theta, &q, &qd, &tau);
            assert!(
                ratio <= ACCURACY,
                "{name} ({what}): error {ratio:.1} units at q = {q:?}"
            );
            worst = worst.max(ratio);
        }
    }
    worst
}

#[test]
fn committed_robots_and_vendor_urdfs() {
    let root = workspace_root();
    for path in [
        "robots/arm7.yaml",
        "robots/arm7_friction.yaml",
        "robots/panda.yaml",
        "robots/ur5.yaml",
        "codegen/tests/data/example-robot-data/kinova_description/kinova.urdf",
        "codegen/tests/data/example-robot-data/xarm_description/xarm7.urdf",
        "codegen/tests/data/example-robot-data/allegro_hand_description/allegro_right_hand.urdf",
    ] {
        let model = load(&root.join(path)).unwrap_or_else(|e| panic!("{e}")).model;
        let worst = check(path, &model, 20, 3);
        println!("{path}: worst {worst:.3} units");
    }
}

/// A chain of `n` joints (axes alternating z, y, x) whose links go from 10 kg and 1 kg·m² at
/// the base to 1e-3 kg and 1e-4 kg·m² at the tool, plus a tool of `tool_mass` kg on the last.
fn light_chain(n: usize, tool_mass: f64) -> Model {
    let mut links = String::from("  - name: base\n");
    let mut joints = String::new();
    for i in 1..=n {
        let t = (i - 1) as f64 / (n - 1) as f64;
        let (mass, inertia) = (10.0 * 1e-4f64.powf(t), 1e-4f64.powf(t));
        let mass = if i == n { mass + tool_mass } else { mass };
        links += &format!(
            "  - name: l{i}\n    inertial:\n      mass: {mass}\n      origin: {{ xyz: [0.02, 0.01, 0.08] }}\n      \
             inertia: {{ ixx: {}, ixy: 0.0, ixz: 0.0, iyy: {}, iyz: 0.0, izz: {} }}\n",
            inertia,
            1.2 * inertia,
            0.7 * inertia
        );
        let parent = if i == 1 {
            "base".to_owned()
        } else {
            format!("l{}", i - 1)
        };
        let axis = ["[0, 0, 1]", "[0, 1, 0]", "[1, 0, 0]"][i % 3];
        let length = 0.3 * (1.0 - 0.8 * t);
        joints += &format!(
            "  - name: j{i}\n    type: revolute\n    parent: {parent}\n    child: l{i}\n    \
             origin: {{ xyz: [0, 0, {length}] }}\n    axis: {axis}\n    \
             limit: {{ lower: -3, upper: 3, velocity: 2, effort: 100 }}\n"
        );
    }
    let text = format!("name: light_chain\nlinks:\n{links}joints:\n{joints}");
    load_yaml_str(&text, Path::new("light_chain.yaml"))
        .unwrap_or_else(|e| panic!("{e}"))
        .model
}

#[test]
fn chains_with_links_down_to_a_ten_thousandth_of_the_base() {
    for (n, tool) in [(6, 0.0), (6, 25.0), (12, 0.0), (12, 5.0)] {
        let model = light_chain(n, tool);
        let worst = check(&format!("{n}-joint chain, tool {tool} kg"), &model, 10, 7);
        println!("{n}-joint light chain, tool {tool} kg: worst {worst:.3} units");
    }
}

#[test]
fn random_trees() {
    let trees = Cell::new(0);
    let result = deterministic_runner(60).run(&arb_model_and_state(8), |(model, _)| {
        check("random tree", &model, 2, trees.get());
        trees.set(trees.get() + 1);
        Ok(())
    });
    if let Err(e) = result {
        panic!("{e}");
    }
    assert_eq!(trees.get(), 60);
}
