//! The interpreter: evaluates a graph numerically, to test generation on any robot without
//! compiling the generated Rust.

use super::graph::{Graph, Id, Node};

/// Values of `outputs` for the given input values (in the order inputs were created).
pub fn evaluate(graph: &Graph, inputs: &[f64], outputs: &[Id]) -> Vec<f64> {
    assert_eq!(inputs.len(), graph.input_names().len(), "wrong number of inputs");
    let last = outputs.iter().map(|o| o.0 as usize + 1).max().unwrap_or(0);
    let mut value = vec![0.0; last];
    for i in 0..last {
        let v = |id: Id| value[id.0 as usize];
        value[i] = match graph.node(Id(i as u32)) {
            Node::Const(bits) => f64::from_bits(bits),
            Node::Input(k) => inputs[k as usize],
            Node::Sin(a) => v(a).sin(),
            Node::Cos(a) => v(a).cos(),
            Node::Sign(a) => crate::scalar::sign(v(a)),
            Node::Tanh(a) => v(a).tanh(),
            Node::Neg(a) => -v(a),
            Node::Add(a, b) => v(a) + v(b),
            Node::Sub(a, b) => v(a) - v(b),
            Node::Mul(a, b) => v(a) * v(b),
            Node::Div(a, b) => v(a) / v(b),
        };
    }
    outputs.iter().map(|o| value[o.0 as usize]).collect()
}
