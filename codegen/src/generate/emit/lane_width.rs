//! How wide a function's lane vectors are: eight lanes (`M::Eight`) for the derivatives'
//! directions, four (`M::Four`, one AVX register) where no vector of the function can be nonzero
//! beyond lane 3 — the regressors, whose columns are computed four rows at a time. The graph
//! has one lane node type of [`LANES`] lanes; which lanes a vector can fill follows from how it
//! was built, so the width is read off the function's nodes rather than recorded.

use crate::symbolic::{Graph, Id, Node, LANES};
use proc_macro2::TokenStream;
use quote::quote;
use std::collections::HashMap;

/// The lane vector type of a function with lane nodes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum LaneWidth {
    Four,
    Eight,
}

impl LaneWidth {
    pub(super) fn lanes(self) -> usize {
        match self {
            LaneWidth::Four => 4,
            LaneWidth::Eight => LANES,
        }
    }

    /// The kernel's vector type (`dyngen_runtime::__private::MulAdd::Eight` or `::Four`), so
    /// that `dispatch_eight` chooses its registers.
    pub(super) fn vector_type(self) -> TokenStream {
        match self {
            LaneWidth::Four => quote!(M::Four),
            LaneWidth::Eight => quote!(M::Eight),
        }
    }

    /// The trait whose methods (the multiply-adds, `to_array`) the vectors are called with.
    pub(super) fn vector_trait(self) -> TokenStream {
        match self {
            LaneWidth::Four => quote!(dyngen_runtime::__private::FourLanes),
            LaneWidth::Eight => quote!(dyngen_runtime::__private::EightLanes),
        }
    }

    /// `arith.eight(lanes)` or `arith.four(lanes)`.
    pub(super) fn build(self, lanes: TokenStream) -> TokenStream {
        match self {
            LaneWidth::Four => quote!(arith.four(#lanes)),
            LaneWidth::Eight => quote!(arith.eight(#lanes)),
        }
    }

    /// `x` in every lane.
    pub(super) fn splat(self, x: TokenStream) -> TokenStream {
        match self {
            LaneWidth::Four => quote!(arith.splat_four(#x)),
            LaneWidth::Eight => quote!(arith.splat_eight(#x)),
        }
    }
}

/// [`LaneWidth::Four`] where every lane vector among `ids` (a function's computed nodes, in
/// topological order) is zero in lanes 4 to 7, whatever the inputs.
pub(super) fn lane_width(g: &Graph, ids: &[Id]) -> LaneWidth {
    // The lanes each vector can fill, as a bit mask; a splat fills whatever the vector it
    // multiplies fills (it is only ever a factor).
    const ALL: u8 = u8::MAX;
    let mut filled: HashMap<Id, u8> = HashMap::new();
    let mask = |filled: &HashMap<Id, u8>, id: Id| match g.node(id) {
        Node::LaneZero => 0,
        _ => filled.get(&id).copied().unwrap_or(ALL),
    };
    for &id in ids {
        let m = match g.node(id) {
            Node::LaneBuild(k) => g
                .lane_list(k)
                .iter()
                .enumerate()
                .filter(|(_, &a)| g.constant_value(a) != Some(0.0))
                .fold(0, |m, (j, _)| m | 1 << j),
            Node::Splat(_) => ALL,
            Node::LaneNeg(a) | Node::LaneDiv(a, _) => mask(&filled, a),
            Node::LaneAdd(a, b) | Node::LaneSub(a, b) => mask(&filled, a) | mask(&filled, b),
            Node::LaneMul(a, b) => mask(&filled, a) & mask(&filled, b),
            // A lane beyond the fourth read out: the function needs all eight.
            Node::Extract(_, k) if k >= 4 => return LaneWidth::Eight,
            _ => continue,
        };
        filled.insert(id, m);
    }
    let four = filled
        .iter()
        .all(|(&id, &m)| matches!(g.node(id), Node::Splat(_)) || m & 0xF0 == 0);
    match four {
        true => LaneWidth::Four,
        false => LaneWidth::Eight,
    }
}
