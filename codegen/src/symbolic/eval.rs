//! The interpreter: evaluates a graph numerically, to test generation on any robot without
//! compiling the generated Rust.

use super::graph::{Graph, Id, Node, LANES};

/// Values of `outputs` for the given input values (in the order inputs were created).
pub fn evaluate(graph: &Graph, inputs: &[f64], outputs: &[Id]) -> Vec<f64> {
    assert_eq!(inputs.len(), graph.input_names().len(), "wrong number of inputs");
    let last = outputs.iter().map(|o| o.0 as usize + 1).max().unwrap_or(0);
    let mut value = vec![0.0; last];
    // Lane vectors, by node (empty for scalars).
    let mut lanes: Vec<[f64; LANES]> = vec![[0.0; LANES]; last];
    for i in 0..last {
        let node = graph.node(Id(i as u32));
        if node.is_lanes() {
            let l = |id: Id| lanes[id.0 as usize];
            let zip = |a: Id, b: Id, f: fn(f64, f64) -> f64| {
                let (a, b) = (l(a), l(b));
                std::array::from_fn(|k| f(a[k], b[k]))
            };
            lanes[i] = match node {
                Node::LaneZero => [0.0; LANES],
                Node::LaneBuild(k) => graph.lane_list(k).map(|a| value[a.0 as usize]),
                Node::Splat(a) => [value[a.0 as usize]; LANES],
                Node::LaneNeg(a) => l(a).map(|x| -x),
                Node::LaneAdd(a, b) => zip(a, b, |x, y| x + y),
                Node::LaneSub(a, b) => zip(a, b, |x, y| x - y),
                Node::LaneMul(a, b) => zip(a, b, |x, y| x * y),
                Node::LaneDiv(a, b) => zip(a, b, |x, y| x / y),
                _ => unreachable!("scalar node"),
            };
            continue;
        }
        let v = |id: Id| value[id.0 as usize];
        value[i] = match node {
            Node::Extract(a, k) => lanes[a.0 as usize][k as usize],
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
            _ => unreachable!("lane node"),
        };
    }
    outputs.iter().map(|o| value[o.0 as usize]).collect()
}
