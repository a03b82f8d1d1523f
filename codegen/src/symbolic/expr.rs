//! `Expr`: a symbolic scalar, a handle to a node of the graph recorded on this thread.

use super::graph::{Graph, Id};
use crate::scalar::Scalar;
use crate::scalar_dual::{LaneScalar, LaneTangent, Tangent};
use std::cell::RefCell;
use std::ops::{Add, Div, Mul, Neg, Sub};

thread_local! {
    static RECORDING: RefCell<Option<Graph>> = const { RefCell::new(None) };
}

/// A symbolic scalar. Only meaningful inside [`record`], and afterwards as an index into the
/// graph that `record` returned.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Expr(pub Id);

fn with_graph<R>(f: impl FnOnce(&mut Graph) -> R) -> R {
    RECORDING.with(|g| {
        let mut g = g.borrow_mut();
        let graph = g
            .as_mut()
            .expect("symbolic arithmetic outside `symbolic::record`");
        f(graph)
    })
}

/// Runs `f`, recording every symbolic operation it performs, and returns the graph with `f`'s
/// result (whose `Expr`s index into that graph).
pub fn record<R>(f: impl FnOnce() -> R) -> (Graph, R) {
    RECORDING.with(|g| {
        let mut g = g.borrow_mut();
        assert!(g.is_none(), "symbolic recordings cannot be nested");
        *g = Some(Graph::new());
    });
    // Leave the thread clean even if `f` panics.
    struct Reset;
    impl Drop for Reset {
        fn drop(&mut self) {
            RECORDING.with(|g| g.borrow_mut().take());
        }
    }
    let reset = Reset;
    let result = f();
    let graph = RECORDING.with(|g| g.borrow_mut().take()).unwrap_or_default();
    drop(reset);
    (graph, result)
}

impl Expr {
    /// A new named input of the graph being recorded.
    pub fn input(name: &str) -> Expr {
        Expr(with_graph(|g| g.input(name)))
    }

    pub fn id(self) -> Id {
        self.0
    }
}

macro_rules! binary {
    ($trait:ident, $method:ident) => {
        impl $trait for Expr {
            type Output = Expr;
            fn $method(self, o: Expr) -> Expr {
                Expr(with_graph(|g| g.$method(self.0, o.0)))
            }
        }
    };
}
binary!(Add, add);
binary!(Sub, sub);
binary!(Mul, mul);
binary!(Div, div);

impl Neg for Expr {
    type Output = Expr;
    fn neg(self) -> Expr {
        Expr(with_graph(|g| g.neg(self.0)))
    }
}

impl Scalar for Expr {
    fn from_f64(x: f64) -> Self {
        Expr(with_graph(|g| g.constant(x)))
    }
    fn sin(self) -> Self {
        Expr(with_graph(|g| g.sin(self.0)))
    }
    fn cos(self) -> Self {
        Expr(with_graph(|g| g.cos(self.0)))
    }
    fn sign(self) -> Self {
        Expr(with_graph(|g| g.sign(self.0)))
    }
    fn tanh(self) -> Self {
        Expr(with_graph(|g| g.tanh(self.0)))
    }
}

/// A symbolic lane vector (`f64x8` in generated code): the tangents of up to
/// `LANES` directions of a dual number (`scalar_dual`) at once.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct LaneExpr(pub Id);

impl LaneExpr {
    pub fn id(self) -> Id {
        self.0
    }
}

impl Add for LaneExpr {
    type Output = LaneExpr;
    fn add(self, o: LaneExpr) -> LaneExpr {
        LaneExpr(with_graph(|g| g.lane_add(self.0, o.0)))
    }
}

impl Sub for LaneExpr {
    type Output = LaneExpr;
    fn sub(self, o: LaneExpr) -> LaneExpr {
        LaneExpr(with_graph(|g| g.lane_sub(self.0, o.0)))
    }
}

impl Neg for LaneExpr {
    type Output = LaneExpr;
    fn neg(self) -> LaneExpr {
        LaneExpr(with_graph(|g| g.lane_neg(self.0)))
    }
}

impl Tangent<Expr> for LaneExpr {
    fn zero() -> Self {
        LaneExpr(with_graph(|g| g.lane_zero()))
    }
    fn scale(self, s: Expr) -> Self {
        LaneExpr(with_graph(|g| g.lane_scale(s.0, self.0)))
    }
    fn divide(self, s: Expr) -> Self {
        LaneExpr(with_graph(|g| g.lane_div(self.0, s.0)))
    }
}

impl LaneTangent<Expr> for LaneExpr {
    fn unit(k: usize, s: Expr) -> Self {
        LaneExpr(with_graph(|g| g.lane_unit(k, s.0)))
    }
    fn lane(self, k: usize) -> Expr {
        Expr(with_graph(|g| g.extract(self.0, k)))
    }
}

impl LaneScalar for Expr {
    type Lanes = LaneExpr;
}
