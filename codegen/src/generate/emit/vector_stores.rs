//! Outputs stored a vector at a time: four lanes of one vector that land in four consecutive
//! entries of one column are written by one store (`*g7 = x12.to_array();`, `g7` a
//! `&mut [f64; 4]` bound by a rest pattern, `[o5, o6, g7 @ .., o11]`), not lane by lane.
//!
//! Why: stored lane by lane, the entries of neighbouring columns are a run of consecutive
//! scalar stores, which LLVM's SLP vectoriser joins into 512-bit stores wherever 512-bit
//! registers are legal and not discouraged: in the AVX-512 copy of a build that does not target
//! the processor (generic tuning), not in a native build (Intel's tuning prefers 256 bits). The
//! shuffles that gather those lanes and the 512-bit values they spill made the arms' regressors
//! slower by default than native on an Intel host; a vector store gives the vectoriser no run
//! to join (`BENCHMARKS.md`).

use super::lane_width::LaneWidth;
use super::outputs::OutputSlots;
use super::plan::{Form, Plan};
use crate::generate::quantities::Shape;
use crate::generate::trace::Quantity;
use crate::symbolic::{Id, Node};
use proc_macro2::TokenStream;
use quote::{format_ident, quote};
use std::collections::HashSet;

impl OutputSlots {
    /// Binds, in each column of a four-lane kernel's result, the first four consecutive entries
    /// that are lanes 0–3 of one vector as one slot of that vector (at most one per column: an
    /// array pattern has one rest). Returns the lane extractions nothing reads any more.
    pub(super) fn store_four_lanes_whole(&mut self, plan: &Plan, q: &Quantity, form: Form) -> HashSet<Id> {
        let g = &plan.robot.graph;
        let rows = match (form, q.shape) {
            (Form::Scalar, Shape::Vector(rows) | Shape::Matrix(rows, _)) => rows,
            _ => return HashSet::new(),
        };
        if plan.lanes != LaneWidth::Four || rows < 4 || !plan.uses_lanes(&plan.order) {
            return HashSet::new();
        }
        let mut grouped = HashSet::new();
        for (c, column) in q.outputs.chunks(rows).enumerate() {
            for r in 0..=rows - 4 {
                let k = c * rows + r;
                let vector = match g.node(column[r]) {
                    Node::Extract(v, 0) => v,
                    _ => continue,
                };
                let whole = (0..4).all(|lane| {
                    let slot = format_ident!("o{}", k + lane);
                    g.node(column[r + lane]) == Node::Extract(vector, lane as u32)
                        && self
                            .slots
                            .get(&column[r + lane])
                            .is_some_and(|s| s.contains(&slot))
                });
                if !whole {
                    continue;
                }
                for lane in 0..4 {
                    let slot = format_ident!("o{}", k + lane);
                    let id = column[r + lane];
                    let slots = self.slots.get_mut(&id).expect("checked above");
                    slots.retain(|s| *s != slot);
                    if slots.is_empty() {
                        self.slots.remove(&id);
                    }
                    grouped.insert(id);
                    self.pattern[k + lane] = TokenStream::new();
                }
                let group = format_ident!("g{k}");
                self.pattern[k] = quote!(#group @ ..);
                self.slots.entry(vector).or_default().push(group);
                break;
            }
        }
        let read: HashSet<Id> = plan.order.iter().flat_map(|&id| plan.operands(id)).collect();
        grouped
            .into_iter()
            .filter(|id| !self.slots.contains_key(id) && !read.contains(id))
            .collect()
    }
}
