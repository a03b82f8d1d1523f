//! The expression graph: an append-only arena of hash-consed nodes.
//!
//! Nodes are created after their operands, so the creation order is a topological order,
//! and it is deterministic (the hash map is only used to find existing nodes).

use std::collections::HashMap;

/// Index of a node in its [`Graph`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Id(pub u32);

/// One operation. Constants are stored as bits so that nodes can be hashed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Node {
    Const(u64),
    /// The `k`-th input of the graph.
    Input(u32),
    Sin(Id),
    Cos(Id),
    /// `sign(a)`, 0 at 0 (Coulomb friction).
    Sign(Id),
    /// `tanh(a)` (smoothed Coulomb friction).
    Tanh(Id),
    Neg(Id),
    Add(Id, Id),
    Sub(Id, Id),
    Mul(Id, Id),
    Div(Id, Id),
    // Lane vectors (`f64x8` in generated code): eight tangents at once, one per lane (the
    // directions of a derivative). The scalar nodes above never take one as an operand, except
    // `Extract`.
    /// The zero vector.
    LaneZero,
    /// A vector built lane by lane from scalars: entry `k` of the graph's lane lists (see
    /// [`Graph::lane_list`]; a lane that is zero holds the constant zero). A seed, a tangent
    /// along one direction, or the sum of such tangents along different directions.
    LaneBuild(u32),
    /// Scalar `a` in every lane.
    Splat(Id),
    LaneNeg(Id),
    LaneAdd(Id, Id),
    LaneSub(Id, Id),
    LaneMul(Id, Id),
    LaneDiv(Id, Id),
    /// Lane `k` of vector `a`: a scalar.
    Extract(Id, u32),
}

/// Lanes of a lane vector node: the directions a dual number's lane tangent carries.
pub use crate::scalar_dual::LANES;

impl Node {
    /// Whether the node's value is a lane vector (else a scalar).
    pub fn is_lanes(self) -> bool {
        matches!(
            self,
            Node::LaneZero
                | Node::LaneBuild(_)
                | Node::Splat(_)
                | Node::LaneNeg(_)
                | Node::LaneAdd(..)
                | Node::LaneSub(..)
                | Node::LaneMul(..)
                | Node::LaneDiv(..)
        )
    }
}

/// Operation counts of the live part of a graph, as printed in generated headers.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct OpCounts {
    pub mul: usize,
    /// Additions and subtractions.
    pub add: usize,
    pub neg: usize,
    pub div: usize,
    /// Sines and cosines taken inside the function (joint angles' ones come precomputed).
    pub trig: usize,
    /// Signs and hyperbolic tangents (Coulomb friction of joint-level parameters).
    pub friction: usize,
    /// Operations on lane vectors (`f64x8`; splats, seeds and lane extractions included): one
    /// vector instruction each where the target has 512-bit vectors.
    pub lanes: usize,
}

#[derive(Clone, Debug, Default)]
pub struct Graph {
    nodes: Vec<Node>,
    index: HashMap<Node, Id>,
    input_names: Vec<String>,
    /// The lanes of each [`Node::LaneBuild`], kept aside so that a node stays two words.
    lane_lists: Vec<[Id; LANES]>,
    lane_list_index: HashMap<[Id; LANES], u32>,
}

impl Graph {
    pub fn new() -> Graph {
        Graph::default()
    }

    pub fn node(&self, id: Id) -> Node {
        self.nodes[id.0 as usize]
    }

    pub fn len(&self) -> usize {
        self.nodes.len()
    }

    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    pub fn input_names(&self) -> &[String] {
        &self.input_names
    }

    pub fn constant_value(&self, id: Id) -> Option<f64> {
        match self.node(id) {
            Node::Const(bits) => Some(f64::from_bits(bits)),
            _ => None,
        }
    }

    fn intern(&mut self, node: Node) -> Id {
        if let Some(&id) = self.index.get(&node) {
            return id;
        }
        let id = Id(u32::try_from(self.nodes.len()).expect("expression graph larger than 2³² nodes"));
        self.nodes.push(node);
        self.index.insert(node, id);
        id
    }

    /// A new input; names are for messages and generated code.
    pub fn input(&mut self, name: &str) -> Id {
        let k = self.input_names.len() as u32;
        self.input_names.push(name.to_owned());
        self.intern(Node::Input(k))
    }

    pub fn constant(&mut self, x: f64) -> Id {
        // One zero: −0.0 and 0.0 are the same constant for every use here.
        let x = if x == 0.0 { 0.0 } else { x };
        self.intern(Node::Const(x.to_bits()))
    }

    fn is_const(&self, id: Id, value: f64) -> bool {
        self.constant_value(id) == Some(value)
    }

    pub fn neg(&mut self, a: Id) -> Id {
        match self.node(a) {
            Node::Const(_) => self.constant(-self.constant_value(a).unwrap_or(0.0)),
            Node::Neg(x) => x,
            Node::Sub(x, y) => self.sub(y, x),
            _ => self.intern(Node::Neg(a)),
        }
    }

    pub fn add(&mut self, a: Id, b: Id) -> Id {
        if let (Some(x), Some(y)) = (self.constant_value(a), self.constant_value(b)) {
            return self.constant(x + y);
        }
        if self.is_const(a, 0.0) {
            return b;
        }
        if self.is_const(b, 0.0) {
            return a;
        }
        if let Node::Neg(y) = self.node(b) {
            return self.sub(a, y);
        }
        if let Node::Neg(x) = self.node(a) {
            return self.sub(b, x);
        }
        if self.is_sin2_cos2(a, b) || self.is_sin2_cos2(b, a) {
            return self.constant(1.0);
        }
        let (a, b) = if a <= b { (a, b) } else { (b, a) };
        self.intern(Node::Add(a, b))
    }

    /// `a = sin(x)²` and `b = cos(x)²` for the same `x`.
    fn is_sin2_cos2(&self, a: Id, b: Id) -> bool {
        match (self.node(a), self.node(b)) {
            (Node::Mul(s1, s2), Node::Mul(c1, c2)) if s1 == s2 && c1 == c2 => {
                matches!((self.node(s1), self.node(c1)), (Node::Sin(x), Node::Cos(y)) if x == y)
            }
            _ => false,
        }
    }

    pub fn sub(&mut self, a: Id, b: Id) -> Id {
        if let (Some(x), Some(y)) = (self.constant_value(a), self.constant_value(b)) {
            return self.constant(x - y);
        }
        if a == b {
            return self.constant(0.0);
        }
        if self.is_const(b, 0.0) {
            return a;
        }
        if self.is_const(a, 0.0) {
            return self.neg(b);
        }
        if let Node::Neg(y) = self.node(b) {
            return self.add(a, y);
        }
        if let Node::Neg(x) = self.node(a) {
            let s = self.add(x, b);
            return self.neg(s);
        }
        self.intern(Node::Sub(a, b))
    }

    pub fn mul(&mut self, a: Id, b: Id) -> Id {
        // Constants first, so that `c·x` has one shape.
        let (a, b) = match (self.constant_value(a), self.constant_value(b)) {
            (Some(x), Some(y)) => return self.constant(x * y),
            (None, Some(_)) => (b, a),
            _ => (a, b),
        };
        if let Some(c) = self.constant_value(a) {
            if c == 0.0 {
                return a;
            }
            if c == 1.0 {
                return b;
            }
            if c == -1.0 {
                return self.neg(b);
            }
            // c·(d·x) = (c·d)·x
            if let Node::Mul(d, x) = self.node(b) {
                if let Some(d) = self.constant_value(d) {
                    let cd = self.constant(c * d);
                    return self.mul(cd, x);
                }
            }
            if let Node::Neg(x) = self.node(b) {
                let mc = self.constant(-c);
                return self.mul(mc, x);
            }
        }
        match (self.node(a), self.node(b)) {
            (Node::Neg(x), Node::Neg(y)) => self.mul(x, y),
            (Node::Neg(x), _) => {
                let p = self.mul(x, b);
                self.neg(p)
            }
            (_, Node::Neg(y)) => {
                let p = self.mul(a, y);
                self.neg(p)
            }
            _ => {
                let (a, b) = if self.constant_value(a).is_some() || a <= b {
                    (a, b)
                } else {
                    (b, a)
                };
                self.intern(Node::Mul(a, b))
            }
        }
    }

    pub fn div(&mut self, a: Id, b: Id) -> Id {
        if let (Some(x), Some(y)) = (self.constant_value(a), self.constant_value(b)) {
            if y != 0.0 {
                return self.constant(x / y);
            }
        }
        if self.is_const(a, 0.0) || self.is_const(b, 1.0) {
            return a;
        }
        if let Some(y) = self.constant_value(b) {
            if y != 0.0 {
                let inv = self.constant(1.0 / y);
                return self.mul(inv, a);
            }
        }
        self.intern(Node::Div(a, b))
    }

    pub fn sin(&mut self, a: Id) -> Id {
        match self.constant_value(a) {
            Some(x) => self.constant(crate::model::exact_sin_cos(x).0),
            None => self.intern(Node::Sin(a)),
        }
    }

    pub fn cos(&mut self, a: Id) -> Id {
        match self.constant_value(a) {
            Some(x) => self.constant(crate::model::exact_sin_cos(x).1),
            None => self.intern(Node::Cos(a)),
        }
    }

    pub fn sign(&mut self, a: Id) -> Id {
        match self.constant_value(a) {
            Some(x) => self.constant(crate::scalar::sign(x)),
            None => self.intern(Node::Sign(a)),
        }
    }

    pub fn tanh(&mut self, a: Id) -> Id {
        match self.constant_value(a) {
            Some(x) => self.constant(x.tanh()),
            None => self.intern(Node::Tanh(a)),
        }
    }

    pub fn lane_zero(&mut self) -> Id {
        self.intern(Node::LaneZero)
    }

    fn is_lane_zero(&self, v: Id) -> bool {
        self.node(v) == Node::LaneZero
    }

    /// `a` in lane `k`, zero elsewhere.
    pub fn lane_unit(&mut self, k: usize, a: Id) -> Id {
        assert!(k < LANES, "lane {k} of {LANES}");
        let zero = self.constant(0.0);
        let mut lanes = [zero; LANES];
        lanes[k] = a;
        self.lane_build(lanes)
    }

    /// The vector whose lane `k` is the scalar `lanes[k]`.
    fn lane_build(&mut self, lanes: [Id; LANES]) -> Id {
        if lanes.iter().all(|&a| self.is_const(a, 0.0)) {
            return self.lane_zero();
        }
        let k = match self.lane_list_index.get(&lanes) {
            Some(&k) => k,
            None => {
                let k = u32::try_from(self.lane_lists.len()).expect("more than 2³² lane lists");
                self.lane_lists.push(lanes);
                self.lane_list_index.insert(lanes, k);
                k
            }
        };
        self.intern(Node::LaneBuild(k))
    }

    /// The scalars of a [`Node::LaneBuild`]'s lanes.
    pub fn lane_list(&self, k: u32) -> [Id; LANES] {
        self.lane_lists[k as usize]
    }

    /// `v`'s lanes when it is built from scalars (or zero).
    fn built_lanes(&mut self, v: Id) -> Option<[Id; LANES]> {
        match self.node(v) {
            Node::LaneBuild(k) => Some(self.lane_list(k)),
            Node::LaneZero => Some([self.constant(0.0); LANES]),
            _ => None,
        }
    }

    /// `f` lane by lane on two built vectors, where that costs at most one scalar operation
    /// (on constants none): lanes that are zero on one side need no operation (a negation of a
    /// constant is a constant), so tangents along different directions merge into one vector
    /// instead of a vector operation on two.
    fn lane_wise(&mut self, a: Id, b: Id, subtract: bool) -> Option<Id> {
        let (x, y) = (self.built_lanes(a)?, self.built_lanes(b)?);
        let cost = (0..LANES)
            .filter(|&k| {
                let (zx, zy) = (self.is_const(x[k], 0.0), self.is_const(y[k], 0.0));
                let constants = self.constant_value(x[k]).is_some() && self.constant_value(y[k]).is_some();
                !constants && !zy && (!zx || subtract)
            })
            .count();
        if cost > 1 {
            return None;
        }
        let lanes = std::array::from_fn(|k| match subtract {
            true => self.sub(x[k], y[k]),
            false => self.add(x[k], y[k]),
        });
        Some(self.lane_build(lanes))
    }

    /// The one non-zero lane of a built vector.
    fn single_lane(&self, v: Id) -> Option<(usize, Id)> {
        let Node::LaneBuild(k) = self.node(v) else {
            return None;
        };
        let lanes = self.lane_list(k);
        let mut nonzero = (0..LANES).filter(|&j| !self.is_const(lanes[j], 0.0));
        let j = nonzero.next()?;
        nonzero.next().is_none().then_some((j, lanes[j]))
    }

    /// `a` in every lane.
    pub fn splat(&mut self, a: Id) -> Id {
        self.intern(Node::Splat(a))
    }

    /// Scalar `s` times vector `v`; a vector with one non-zero lane stays a scalar product.
    pub fn lane_scale(&mut self, s: Id, v: Id) -> Id {
        if self.is_lane_zero(v) || self.is_const(s, 0.0) {
            return self.lane_zero();
        }
        if self.is_const(s, 1.0) {
            return v;
        }
        if self.is_const(s, -1.0) {
            return self.lane_neg(v);
        }
        if let Some((k, a)) = self.single_lane(v) {
            let p = self.mul(s, a);
            return self.lane_unit(k, p);
        }
        match self.node(v) {
            Node::LaneNeg(x) => {
                let p = self.lane_scale(s, x);
                return self.lane_neg(p);
            }
            Node::LaneMul(d, x) => {
                if let (Some(c), Node::Splat(d)) = (self.constant_value(s), self.node(d)) {
                    if let Some(d) = self.constant_value(d) {
                        let cd = self.constant(c * d);
                        return self.lane_scale(cd, x);
                    }
                }
            }
            _ => {}
        }
        if let Node::Neg(x) = self.node(s) {
            let p = self.lane_scale(x, v);
            return self.lane_neg(p);
        }
        let s = self.splat(s);
        self.intern(Node::LaneMul(s, v))
    }

    pub fn lane_neg(&mut self, v: Id) -> Id {
        if let Some((k, a)) = self.single_lane(v) {
            let m = self.neg(a);
            return self.lane_unit(k, m);
        }
        match self.node(v) {
            Node::LaneZero => v,
            Node::LaneNeg(x) => x,
            Node::LaneSub(x, y) => self.lane_sub(y, x),
            _ => self.intern(Node::LaneNeg(v)),
        }
    }

    pub fn lane_add(&mut self, a: Id, b: Id) -> Id {
        if self.is_lane_zero(a) {
            return b;
        }
        if self.is_lane_zero(b) {
            return a;
        }
        if let Some(sum) = self.lane_wise(a, b, false) {
            return sum;
        }
        if let Node::LaneNeg(y) = self.node(b) {
            return self.lane_sub(a, y);
        }
        if let Node::LaneNeg(x) = self.node(a) {
            return self.lane_sub(b, x);
        }
        let (a, b) = if a <= b { (a, b) } else { (b, a) };
        self.intern(Node::LaneAdd(a, b))
    }

    pub fn lane_sub(&mut self, a: Id, b: Id) -> Id {
        if a == b {
            return self.lane_zero();
        }
        if self.is_lane_zero(b) {
            return a;
        }
        if self.is_lane_zero(a) {
            return self.lane_neg(b);
        }
        if let Some(difference) = self.lane_wise(a, b, true) {
            return difference;
        }
        if let Node::LaneNeg(y) = self.node(b) {
            return self.lane_add(a, y);
        }
        if let Node::LaneNeg(x) = self.node(a) {
            let s = self.lane_add(x, b);
            return self.lane_neg(s);
        }
        self.intern(Node::LaneSub(a, b))
    }

    /// Vector `v` divided by scalar `s`.
    pub fn lane_div(&mut self, v: Id, s: Id) -> Id {
        if self.is_lane_zero(v) || self.is_const(s, 1.0) {
            return v;
        }
        if let Some(y) = self.constant_value(s) {
            if y != 0.0 {
                let inv = self.constant(1.0 / y);
                return self.lane_scale(inv, v);
            }
        }
        if let Some((k, a)) = self.single_lane(v) {
            let q = self.div(a, s);
            return self.lane_unit(k, q);
        }
        let s = self.splat(s);
        self.intern(Node::LaneDiv(v, s))
    }

    /// Lane `k` of `v`.
    pub fn extract(&mut self, v: Id, k: usize) -> Id {
        match self.node(v) {
            Node::LaneZero => self.constant(0.0),
            Node::LaneBuild(j) => self.lane_list(j)[k],
            Node::Splat(a) => a,
            _ => self.intern(Node::Extract(v, k as u32)),
        }
    }

    /// Which nodes the `outputs` depend on (dead-code elimination), indexed by node.
    pub fn live(&self, outputs: &[Id]) -> Vec<bool> {
        let mut live = vec![false; self.nodes.len()];
        for id in self.live_nodes(outputs) {
            live[id.0 as usize] = true;
        }
        live
    }

    /// The nodes `outputs` need, themselves included, in creation (so topological) order.
    /// Found from the outputs down, so the work is the function's, not the graph's: a module
    /// of many small functions (one per frame) over one large graph asks this once per
    /// function, and build scripts run it unoptimised.
    pub fn live_nodes(&self, outputs: &[Id]) -> Vec<Id> {
        let mut seen = vec![false; self.nodes.len()];
        let mut stack: Vec<Id> = Vec::new();
        let mut found: Vec<Id> = Vec::new();
        for &o in outputs {
            if !seen[o.0 as usize] {
                seen[o.0 as usize] = true;
                stack.push(o);
            }
        }
        while let Some(id) = stack.pop() {
            found.push(id);
            self.for_each_operand(id, |a| {
                if !seen[a.0 as usize] {
                    seen[a.0 as usize] = true;
                    stack.push(a);
                }
            });
        }
        found.sort_unstable();
        found
    }

    pub fn operands(&self, id: Id) -> Vec<Id> {
        let mut out = Vec::with_capacity(2);
        self.for_each_operand(id, |a| out.push(a));
        out
    }

    /// Calls `f` on each operand of `id` (a lane list's non-constant entries), allocating
    /// nothing.
    pub fn for_each_operand(&self, id: Id, mut f: impl FnMut(Id)) {
        match self.node(id) {
            Node::Const(_) | Node::Input(_) | Node::LaneZero => {}
            Node::Sin(a) | Node::Cos(a) | Node::Sign(a) | Node::Tanh(a) | Node::Neg(a) => f(a),
            Node::Splat(a) | Node::LaneNeg(a) | Node::Extract(a, _) => f(a),
            Node::LaneBuild(k) => {
                for a in self.lane_list(k) {
                    if !matches!(self.node(a), Node::Const(_)) {
                        f(a);
                    }
                }
            }
            Node::Add(a, b) | Node::Sub(a, b) | Node::Mul(a, b) | Node::Div(a, b) => {
                f(a);
                f(b);
            }
            Node::LaneAdd(a, b) | Node::LaneSub(a, b) | Node::LaneMul(a, b) | Node::LaneDiv(a, b) => {
                f(a);
                f(b);
            }
        }
    }

    /// Operation counts of what `outputs` need; sin/cos of inputs are not counted (they are
    /// precomputed once per control tick and shared).
    pub fn op_counts(&self, outputs: &[Id]) -> OpCounts {
        let mut c = OpCounts::default();
        for id in self.live_nodes(outputs) {
            match self.node(id) {
                Node::Add(..) | Node::Sub(..) => c.add += 1,
                Node::Mul(..) => c.mul += 1,
                Node::Div(..) => c.div += 1,
                Node::Neg(_) => c.neg += 1,
                Node::Sin(a) | Node::Cos(a) if !matches!(self.node(a), Node::Input(_)) => c.trig += 1,
                Node::Sign(_) | Node::Tanh(_) => c.friction += 1,
                Node::LaneZero => {}
                n if n.is_lanes() || matches!(n, Node::Extract(..)) => c.lanes += 1,
                _ => {}
            }
        }
        c
    }
}

#[cfg(test)]
mod tests {
    use super::{Graph, Node};
    use crate::symbolic::evaluate;

    #[test]
    fn tangents_along_different_directions_merge_into_one_vector() {
        let mut g = Graph::new();
        let (a, b) = (g.input("a"), g.input("b"));
        let (u, w) = (g.lane_unit(0, a), g.lane_unit(3, b));
        let sum = g.lane_add(u, w);
        let difference = g.lane_sub(u, w);
        assert!(matches!(g.node(sum), Node::LaneBuild(_)));
        assert!(matches!(g.node(difference), Node::LaneBuild(_)));
        // One vector each, no vector operation; the difference negates `b` once.
        let sum_counts = g.op_counts(&[sum]);
        assert_eq!((sum_counts.lanes, sum_counts.add, sum_counts.neg), (1, 0, 0));
        let difference_counts = g.op_counts(&[difference]);
        assert_eq!((difference_counts.lanes, difference_counts.neg), (1, 1));
        let lanes: Vec<_> = (0..4)
            .flat_map(|k| [g.extract(sum, k), g.extract(difference, k)])
            .collect();
        let values = evaluate(&g, &[2.0, 5.0], &lanes);
        assert_eq!(values, [2.0, 2.0, 0.0, 0.0, 0.0, 0.0, 5.0, -5.0]);
    }

    #[test]
    fn vectors_that_overlap_in_several_lanes_stay_one_vector_operation() {
        let mut g = Graph::new();
        let x: Vec<_> = ["a", "b", "c", "d"].map(|n| g.input(n)).into();
        let ab = {
            let (u, w) = (g.lane_unit(0, x[0]), g.lane_unit(1, x[1]));
            g.lane_add(u, w)
        };
        let cd = {
            let (u, w) = (g.lane_unit(0, x[2]), g.lane_unit(1, x[3]));
            g.lane_add(u, w)
        };
        // Lane by lane this would take two scalar additions: one vector addition instead.
        let sum = g.lane_add(ab, cd);
        assert!(matches!(g.node(sum), Node::LaneAdd(..)));
        let lanes = [g.extract(sum, 0), g.extract(sum, 1), g.extract(sum, 2)];
        assert_eq!(evaluate(&g, &[1.0, 2.0, 3.0, 4.0], &lanes), [4.0, 6.0, 0.0]);
    }
}
