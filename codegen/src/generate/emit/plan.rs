//! Which nodes a function computes and in what order, which additions absorb a product as one
//! multiply-add, and the statement that computes each value.

use super::constants::literal;
use super::lane_width::{lane_width, LaneWidth};
use super::leaves::Leaves;
use crate::generate::trace::SymbolicRobot;
use crate::symbolic::{Id, Node};
use proc_macro2::{Ident, Literal, TokenStream};
use quote::{format_ident, quote};
use std::collections::HashMap;

/// Whether a function computes one state in `f64`, or one state per SIMD lane of a generic
/// `L: Lanes` (the same statements; constants splatted, the few non-arithmetic nodes mapped
/// lane by lane).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Form {
    Scalar,
    Lanes,
}

impl Form {
    /// The type of every value.
    pub(super) fn value_type(self) -> TokenStream {
        match self {
            Form::Scalar => quote!(f64),
            Form::Lanes => quote!(L),
        }
    }
}

/// `a·b + c` with one rounding: an addition or subtraction whose product operand is used only
/// there. `negate_product` and `negate_addend` give `−a·b + c` and `a·b − c`.
#[derive(Clone, Copy, Debug)]
pub(super) struct MulAdd {
    pub(super) a: Id,
    pub(super) b: Id,
    pub(super) c: Id,
    pub(super) negate_product: bool,
    pub(super) negate_addend: bool,
}

/// The nodes a function computes, in order, and how their names are spelled.
pub(super) struct Plan<'a> {
    pub(super) robot: &'a SymbolicRobot,
    pub(super) leaves: &'a Leaves,
    pub(super) form: Form,
    /// Additions and subtractions emitted as one multiply-add (their products are not emitted).
    pub(super) fused: HashMap<Id, MulAdd>,
    /// Live computed nodes in topological order.
    pub(super) order: Vec<Id>,
    pub(super) names: HashMap<Id, Ident>,
    /// The width of its lane vectors, if it has any.
    pub(super) lanes: LaneWidth,
}

impl<'a> Plan<'a> {
    pub(super) fn new(robot: &'a SymbolicRobot, leaves: &'a Leaves, outputs: &[Id], form: Form) -> Plan<'a> {
        let g = &robot.graph;
        let topological: Vec<Id> = (g.live_nodes(outputs).into_iter())
            .filter(|id| !leaves.names.contains_key(id))
            .filter(|&id| !matches!(g.node(id), Node::Const(_) | Node::Input(_) | Node::LaneZero))
            .collect();
        assert!(
            form == Form::Scalar || topological.iter().all(|&id| !g.node(id).is_lanes()),
            "lane-vector nodes in a function generic over its lane type"
        );
        let lanes = lane_width(g, &topological);
        let (fused, products) = fuse_multiply_adds(g, outputs, &topological);
        let order: Vec<Id> = topological
            .into_iter()
            .filter(|id| !products.contains(id))
            .collect();
        // `x` is a prefix no input uses (q, qd, v, a, tau, theta, r, s, c), so a temporary never
        // shadows one.
        let names = order
            .iter()
            .enumerate()
            .map(|(k, &id)| (id, format_ident!("x{k}")))
            .collect();
        Plan {
            robot,
            leaves,
            form,
            fused,
            order,
            names,
            lanes,
        }
    }

    /// Moves what `stage` needs to the front of the order (each part keeping its order, so the
    /// order stays topological) and renames the values by their new positions; returns how
    /// many values the stage computes.
    pub(super) fn put_first(&mut self, stage: &[Id]) -> usize {
        let live = self.robot.graph.live(stage);
        let (first, rest): (Vec<Id>, Vec<Id>) = self.order.iter().partition(|id| live[id.0 as usize]);
        let end = first.len();
        self.order = first.into_iter().chain(rest).collect();
        self.names = (self.order.iter().enumerate())
            .map(|(k, &id)| (id, format_ident!("x{k}")))
            .collect();
        end
    }

    /// The statements that compute `ids` (a run of [`Plan::order`]): one declaration of every
    /// temporary, then one assignment per value, in creation order:
    /// `let [x0, x1]: [f64; 2]; x0 = a * b; x1 = x0 + c;`.
    ///
    /// Why not one `let` per value: every `let` opens a debug-info scope nested in the one
    /// before, and LLVM recurses once per scope, so a few thousand `let`s overflow rustc's stack
    /// in debug builds. A single declaration keeps the nesting flat at any size, so chunks can
    /// be as large as run time wants; creation order keeps values short-lived, which keeps
    /// register allocation (and so release compile time) cheap.
    pub(super) fn statements(&self, ids: &[Id], used_leaves: &mut Vec<Id>) -> Vec<TokenStream> {
        self.statements_writing(ids, used_leaves, &HashMap::new(), &HashMap::new())
    }

    /// [`Plan::statements`], each value followed by its writes to the slots `slots` (`*o3 =
    /// x17;`; a lane vector as its array, `*h3 = x17.to_array();`), and each value of `reads`
    /// (declared by the caller, computed in an earlier chunk) read by its statement right before
    /// the first statement that uses it. An output stored as soon as it is computed is not held
    /// in a register, or spilled and reloaded, until the function returns; a value read where it
    /// is first needed does not occupy one from the top of the chunk.
    pub(super) fn statements_writing(
        &self,
        ids: &[Id],
        used_leaves: &mut Vec<Id>,
        slots: &HashMap<Id, Vec<Ident>>,
        reads: &HashMap<Id, TokenStream>,
    ) -> Vec<TokenStream> {
        let g = &self.robot.graph;
        let ty = self.form.value_type();
        let writes = |id: Id| {
            let name = &self.names[&id];
            let slots = slots.get(&id).map(Vec::as_slice).unwrap_or_default();
            match (g.node(id).is_lanes(), self.form) {
                (true, _) => quote!(#(*#slots = #name.to_array();)*),
                (false, Form::Scalar) => quote!(#(*#slots = #name;)*),
                // Into the caller's lane type.
                (false, Form::Lanes) => {
                    quote!(#(*#slots = dyngen_runtime::__private::lane_out(arith, #name);)*)
                }
            }
        };
        let mut read = std::collections::HashSet::new();
        let mut reads_before = |id: Id, out: &mut Vec<TokenStream>| {
            for operand in self.operands(id) {
                if let Some(statement) = reads.get(&operand).filter(|_| read.insert(operand)) {
                    out.push(statement.clone());
                }
            }
        };
        let mut out = Vec::with_capacity(ids.len() + 2);
        // Lane vectors (`f64x8`) get a declaration of their own.
        let (lanes, scalars): (Vec<Id>, Vec<Id>) = ids.iter().partition(|&&id| g.node(id).is_lanes());
        if scalars.len() == 1 && lanes.is_empty() && !matches!(g.node(ids[0]), Node::Extract(..)) {
            let name = &self.names[&ids[0]];
            reads_before(ids[0], &mut out);
            let value = self.value(ids[0], used_leaves);
            out.push(quote!(let #name: #ty = #value;));
            out.push(writes(ids[0]));
            return out;
        }
        for (sort, ty) in [(&scalars, ty), (&lanes, self.lanes.vector_type())] {
            if !sort.is_empty() {
                let names = sort.iter().map(|id| &self.names[id]);
                let k = Literal::usize_unsuffixed(sort.len());
                out.push(quote!(let [#(#names),*]: [#ty; #k];));
            }
        }
        for &id in ids {
            let name = &self.names[&id];
            reads_before(id, &mut out);
            if let Node::Extract(v, k) = g.node(id) {
                // A lane of a vector, by destructuring (no indexing).
                let v = self.atom(v, used_leaves);
                let pattern = (0..self.lanes.lanes()).map(|j| match j == k as usize {
                    true => quote!(#name),
                    false => quote!(_),
                });
                out.push(quote!([#(#pattern),*] = #v.to_array();));
                out.push(writes(id));
                continue;
            }
            let value = self.value(id, used_leaves);
            out.push(quote!(#name = #value;));
            out.push(writes(id));
        }
        out
    }

    /// Whether computing `ids` takes a scalar multiply-add (`arith.mul_add`).
    pub(super) fn uses_arith(&self, ids: &[Id]) -> bool {
        ids.iter()
            .any(|id| self.fused.contains_key(id) && !self.robot.graph.node(*id).is_lanes())
            || self.uses_lanes(ids)
    }

    /// Whether any of `ids` is a lane vector: the function then makes its vectors through
    /// `arith` and runs through `dyngen_runtime::__private::dispatch_eight`.
    pub(super) fn uses_lanes(&self, ids: &[Id]) -> bool {
        ids.iter().any(|id| self.robot.graph.node(*id).is_lanes())
    }

    /// `id` as an operand, negated if `negate`: a constant as its negated literal (never `--x`).
    pub(super) fn maybe_negated(&self, id: Id, negate: bool, used_leaves: &mut Vec<Id>) -> TokenStream {
        match (negate, self.robot.graph.constant_value(id)) {
            (false, _) => self.atom(id, used_leaves),
            (true, Some(x)) => {
                let x = literal(-x);
                match self.form {
                    Form::Scalar => x,
                    Form::Lanes => quote!(L::splat_in(arith, #x)),
                }
            }
            (true, None) => {
                let a = self.atom(id, used_leaves);
                quote!(-#a)
            }
        }
    }

    /// What `id`'s statement reads: a fused multiply-add reads its product's factors.
    pub(super) fn operands(&self, id: Id) -> Vec<Id> {
        match self.fused.get(&id) {
            Some(f) => vec![f.a, f.b, f.c],
            None => self.robot.graph.operands(id),
        }
    }

    /// An operand: a literal, an input, or an earlier temporary. Records inputs it reads.
    pub(super) fn atom(&self, id: Id, used_leaves: &mut Vec<Id>) -> TokenStream {
        if self.robot.graph.node(id) == Node::LaneZero {
            return self.lanes.splat(quote!(0.0));
        }
        if let Some(x) = self.robot.graph.constant_value(id) {
            let x = literal(x);
            return match self.form {
                Form::Scalar => x,
                Form::Lanes => quote!(L::splat_in(arith, #x)),
            };
        }
        if let Some(name) = self.leaves.names.get(&id) {
            if !used_leaves.contains(&id) {
                used_leaves.push(id);
            }
            return quote!(#name);
        }
        let name = &self.names[&id];
        quote!(#name)
    }

    /// The expression computing `id` from its operands.
    pub(super) fn value(&self, id: Id, used_leaves: &mut Vec<Id>) -> TokenStream {
        if let Some(f) = self.fused.get(&id) {
            return self.multiply_add(id, f, used_leaves);
        }
        if let Some(mapped) = self.lane_by_lane(id, used_leaves) {
            return mapped;
        }
        self.operation(id, used_leaves)
    }

    /// `c ± a·b`, the fused multiply-add `f` that computes `id`.
    fn multiply_add(&self, id: Id, f: &MulAdd, used_leaves: &mut Vec<Id>) -> TokenStream {
        if self.robot.graph.node(id).is_lanes() {
            // On lane vectors: the lane types' multiply-adds, which negate for free.
            let (a, b, c) = (
                self.atom(f.a, used_leaves),
                self.atom(f.b, used_leaves),
                self.atom(f.c, used_leaves),
            );
            return match (f.negate_product, f.negate_addend) {
                (false, false) => quote!(#a.mul_add(#b, #c)),
                (true, false) => quote!(#a.mul_neg_add(#b, #c)),
                (false, true) => quote!(#a.mul_sub(#b, #c)),
                (true, true) => quote!(#a.mul_neg_sub(#b, #c)),
            };
        }
        let b = self.atom(f.b, used_leaves);
        let (a, c) = (
            self.maybe_negated(f.a, f.negate_product, used_leaves),
            self.maybe_negated(f.c, f.negate_addend, used_leaves),
        );
        match self.form {
            Form::Scalar => quote!(arith.mul_add(#a, #b, #c)),
            // `(-x).mul_add(..)`: a method call binds tighter than the minus.
            Form::Lanes => match f.negate_product && self.robot.graph.constant_value(f.a).is_none() {
                true => quote!((#a).mul_add(#b, #c)),
                false => quote!(#a.mul_add(#b, #c)),
            },
        }
    }

    /// In the lane form, a non-arithmetic node lane by lane, as the scalar code computes it.
    fn lane_by_lane(&self, id: Id, used_leaves: &mut Vec<Id>) -> Option<TokenStream> {
        if self.form != Form::Lanes {
            return None;
        }
        let (a, f) = match self.robot.graph.node(id) {
            Node::Sin(a) => (a, quote!(dyngen_runtime::__private::libm::sin)),
            Node::Cos(a) => (a, quote!(dyngen_runtime::__private::libm::cos)),
            Node::Tanh(a) => (a, quote!(dyngen_runtime::__private::libm::tanh)),
            Node::Sign(a) => (a, quote!(dyngen_runtime::__private::sign)),
            _ => return None,
        };
        let a = self.atom(a, used_leaves);
        Some(quote!(#a.map_in(arith, #f)))
    }

    /// The expression of operation node `id` (not a multiply-add).
    fn operation(&self, id: Id, used_leaves: &mut Vec<Id>) -> TokenStream {
        let mut atom = |x| self.atom(x, used_leaves);
        match self.robot.graph.node(id) {
            Node::Sin(a) => {
                let a = atom(a);
                quote!(dyngen_runtime::__private::libm::sin(#a))
            }
            Node::Cos(a) => {
                let a = atom(a);
                quote!(dyngen_runtime::__private::libm::cos(#a))
            }
            Node::Sign(a) => {
                // sign with 0 at 0 (and for NaN), without a panic path or a call.
                let a = atom(a);
                quote!(if #a > 0.0 { 1.0 } else if #a < 0.0 { -1.0 } else { 0.0 })
            }
            Node::Tanh(a) => {
                let a = atom(a);
                quote!(dyngen_runtime::__private::libm::tanh(#a))
            }
            Node::Neg(a) | Node::LaneNeg(a) => {
                let a = atom(a);
                quote!(-#a)
            }
            Node::Add(a, b) | Node::LaneAdd(a, b) => {
                let (a, b) = (atom(a), atom(b));
                quote!(#a + #b)
            }
            Node::Sub(a, b) | Node::LaneSub(a, b) => {
                let (a, b) = (atom(a), atom(b));
                quote!(#a - #b)
            }
            Node::Mul(a, b) | Node::LaneMul(a, b) => {
                let (a, b) = (atom(a), atom(b));
                quote!(#a * #b)
            }
            Node::Div(a, b) | Node::LaneDiv(a, b) => {
                let (a, b) = (atom(a), atom(b));
                quote!(#a / #b)
            }
            Node::Splat(a) => {
                let a = atom(a);
                self.lanes.splat(a)
            }
            Node::LaneBuild(k) => {
                let g = &self.robot.graph;
                let lanes = g.lane_list(k).map(|a| match g.constant_value(a) == Some(0.0) {
                    true => quote!(0.0),
                    false => atom(a),
                });
                let lanes = &lanes[..self.lanes.lanes()];
                self.lanes.build(quote!([#(#lanes),*]))
            }
            Node::Const(_) | Node::Input(_) | Node::LaneZero => unreachable!("leaves are not statements"),
            Node::Extract(..) => unreachable!("lane extractions are destructuring statements"),
        }
    }
}

/// The additions and subtractions of the computed nodes `computed` that become one multiply-add,
/// and the products they absorb: a product used once, by that addition or subtraction, and by no
/// output. One rounding instead of two, one instruction instead of two on processors with FMA
/// (`dyngen_runtime::__private::dispatch` runs `arith.mul_add` as that instruction).
fn fuse_multiply_adds(
    g: &crate::symbolic::Graph,
    outputs: &[Id],
    computed: &[Id],
) -> (HashMap<Id, MulAdd>, std::collections::HashSet<Id>) {
    let mut uses: HashMap<Id, usize> = HashMap::new();
    for &id in computed {
        for op in g.operands(id) {
            *uses.entry(op).or_default() += 1;
        }
    }
    for o in outputs {
        *uses.entry(*o).or_default() += 1;
    }
    let mut fused = HashMap::new();
    let mut products = std::collections::HashSet::new();
    // Scalar products into scalar sums, lane products into lane sums.
    let product = |id: Id, lanes: bool, products: &std::collections::HashSet<Id>| match g.node(id) {
        Node::Mul(a, b) | Node::LaneMul(a, b)
            if g.node(id).is_lanes() == lanes && uses.get(&id) == Some(&1) && !products.contains(&id) =>
        {
            Some((a, b))
        }
        _ => None,
    };
    for &id in computed {
        let (x, y, subtract) = match g.node(id) {
            Node::Add(x, y) | Node::LaneAdd(x, y) => (x, y, false),
            Node::Sub(x, y) | Node::LaneSub(x, y) => (x, y, true),
            _ => continue,
        };
        let lanes = g.node(id).is_lanes();
        let product = |id: Id, products: &std::collections::HashSet<Id>| product(id, lanes, products);
        // `x·… ± y`, else `x + y·…` / `x − y·…`.
        let choice = if let Some((a, b)) = product(x, &products) {
            Some((x, a, b, y, false, subtract))
        } else {
            product(y, &products).map(|(a, b)| (y, a, b, x, subtract, false))
        };
        if let Some((p, a, b, c, negate_product, negate_addend)) = choice {
            products.insert(p);
            fused.insert(
                id,
                MulAdd {
                    a,
                    b,
                    c,
                    negate_product,
                    negate_addend,
                },
            );
        }
    }
    (fused, products)
}
