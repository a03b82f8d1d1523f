//! A function in one piece: every statement in one kernel, the result written in place (each
//! output stored as soon as it is computed) or built from the outputs at the end, and with it
//! its `_into` form.

use super::header::{Emitted, Header};
use super::into_form::{has_into_form, one_piece_into, zero_pattern};
use super::kernel::{function_item, in_caller_type, KernelKind};
use super::outputs::{result_value, slots_pattern, slots_target, writes_in_place, zero_result, OutputSlots};
use super::plan::{Form, Plan};
use super::signature::signature;
use super::sizes::Sizes;
use crate::generate::trace::Quantity;
use crate::symbolic::Id;
use proc_macro2::TokenStream;
use quote::quote;
use std::collections::HashMap;

/// `q` as one function of `plan`'s statements (and its `_into` form where it has one). `atoms`
/// are the outputs as operands, `used` the inputs they read.
pub(super) fn whole(
    plan: &Plan,
    q: &Quantity,
    header: &Header,
    atoms: &[TokenStream],
    mut used: Vec<Id>,
    sizes: &Sizes,
) -> Emitted {
    let form = plan.form;
    // The statements writing the result in place, shared by the by-value and `_into` forms; the
    // lane extractions they store a vector at a time are not computed.
    let (writes, stored_whole) = match writes_in_place(q, form) {
        true => {
            let (writes, stored_whole) = writes_into_out(plan, q, form, atoms, &mut used);
            (Some(writes), stored_whole)
        }
        false => (None, 0),
    };
    let body = match &writes {
        Some(writes) => {
            let zero = zero_result(q, form, sizes);
            let out_type = in_caller_type(form, &header.ret);
            quote! {
                let mut out: #out_type = #zero;
                #writes
                out
            }
        }
        None => {
            let statements = plan.statements(&plan.order, &mut used);
            let result = result_value(q, form, atoms);
            quote!(#(#statements)* #result)
        }
    };
    let sig = signature(plan.robot, plan.leaves, &q.args, &used, &header.n, form);
    let (params, prelude) = (sig.params, sig.prelude);
    let kernel = KernelKind {
        uses_arith: plan.uses_arith(&plan.order),
        lanes: plan.uses_lanes(&plan.order).then_some(plan.lanes),
        many_registers: header.many_registers,
    };
    let doc = header.doc(stored_whole);
    let method = function_item(
        form,
        quote!(#(#[doc = #doc])* #[inline(never)]),
        &header.name,
        &params,
        &header.ret,
        kernel,
        quote!(#(#prelude)* #body),
    );
    let into = match (has_into_form(q, form), writes) {
        (true, Some(writes)) => one_piece_into(
            &header.name,
            &params,
            &header.ret,
            zero_pattern(q, &plan.robot.graph),
            kernel,
            quote!(#(#prelude)* #writes),
        ),
        _ => quote!(),
    };
    Emitted {
        method: quote!(#method #into),
        chunks: Vec::new(),
    }
}

/// `{ let [[o0, _, o2]] = &mut out…; x0 = …; *o0 = x0; … }`: every value computed and every
/// output that is not a structural zero written into `out` (a local result or a `&mut` to one),
/// which the block leaves as it found the structural zeros. Each output is stored as soon as it
/// is computed: returning the outputs at the end kept every one alive across the whole function
/// (the regressor's peak of live values was 260 instead of 103), so the register allocator
/// spilled them and reloaded them to store them. Also returns how many lane extractions the
/// block leaves out because it stores their vector whole.
fn writes_into_out(
    plan: &Plan,
    q: &Quantity,
    form: Form,
    atoms: &[TokenStream],
    used: &mut Vec<Id>,
) -> (TokenStream, usize) {
    let mut slots = OutputSlots::new(plan, q, atoms, |_| true);
    let unread = slots.store_four_lanes_whole(plan, q, form);
    let ids: Vec<Id> = plan
        .order
        .iter()
        .filter(|id| !unread.contains(id))
        .copied()
        .collect();
    let statements = plan.statements_writing(&ids, used, &slots.slots, &HashMap::new());
    let (pattern, target) = (
        slots_pattern(q, form, &slots.pattern),
        slots_target(q, form, quote!(out), false),
    );
    let immediate = &slots.immediate;
    let block = quote! {
        {
            let #pattern = #target;
            #(#immediate)*
            #(#statements)*
        }
    };
    (block, unread.len())
}
