//! How the graph's inputs are spelled in a function body: `q3`, `qd0`, the joint sines `s2` and
//! cosines `c2` that come precomputed in `JointTrig`.

use crate::generate::trace::SymbolicRobot;
use crate::symbolic::{Id, Node};
use proc_macro2::Ident;
use quote::format_ident;
use std::collections::HashMap;

/// How inputs of the graph are spelled in a function body.
pub(super) struct Leaves {
    pub(super) names: HashMap<Id, Ident>,
    /// Ids of `sin(q_i)` and `cos(q_i)` in joint order, found once (every chunk's signature
    /// needs them, and a scan per chunk made large robots' emission quadratic).
    pub(super) sin_ids: Vec<Id>,
    pub(super) cos_ids: Vec<Id>,
    /// The number of joints of a floating-base robot, whose functions take a `FloatingTrig`
    /// (the joints' `JointTrig` and the base pose); `None` for a fixed base.
    pub(super) floating_joints: Option<usize>,
}

impl Leaves {
    pub(super) fn new(robot: &SymbolicRobot) -> Leaves {
        let g = &robot.graph;
        let mut names = HashMap::new();
        let inputs = &robot.inputs;
        for (prefix, ids) in [
            ("q", &inputs.q),
            ("qd", &inputs.qd),
            ("v", &inputs.v),
            ("a", &inputs.a),
            ("tau", &inputs.tau),
            ("theta", &inputs.theta),
            ("r", &inputs.r),
            ("pos", &inputs.base_position),
            ("lambda", &robot.contact_inputs.forces),
            ("target", &robot.contact_inputs.target),
        ] {
            for (i, id) in ids.iter().enumerate() {
                names.insert(*id, format_ident!("{prefix}{i}"));
            }
        }
        for &(c, id) in &robot.contact_inputs.coefficients {
            names.insert(id, format_ident!("{}", c.name()));
        }
        for (k, id) in inputs.base_rotation.iter().enumerate() {
            names.insert(*id, format_ident!("rot{}{}", k / 3, k % 3));
        }
        // sin and cos of a joint angle come precomputed in `JointTrig`.
        for i in 0..g.len() {
            let id = Id(i as u32);
            match g.node(id) {
                Node::Sin(a) | Node::Cos(a) if inputs.q.contains(&a) => {
                    let k = inputs.q.iter().position(|x| *x == a).unwrap_or(0);
                    let prefix = if matches!(g.node(id), Node::Sin(_)) {
                        "s"
                    } else {
                        "c"
                    };
                    names.insert(id, format_ident!("{prefix}{k}"));
                }
                _ => {}
            }
        }
        Leaves {
            names,
            sin_ids: trig_ids(robot, true),
            cos_ids: trig_ids(robot, false),
            floating_joints: (!inputs.base_rotation.is_empty()).then_some(inputs.q.len()),
        }
    }
}

/// Ids of `sin(q_i)` (or `cos(q_i)`) in joint order; a fresh id where the graph has none.
fn trig_ids(robot: &SymbolicRobot, sin: bool) -> Vec<Id> {
    let g = &robot.graph;
    robot
        .inputs
        .q
        .iter()
        .map(|&q| {
            (0..g.len())
                .map(|i| Id(i as u32))
                .find(|&id| match g.node(id) {
                    Node::Sin(a) if sin => a == q,
                    Node::Cos(a) if !sin => a == q,
                    _ => false,
                })
                .unwrap_or(Id(u32::MAX))
        })
        .collect()
}
