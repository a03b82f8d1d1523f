//! A large function as a run of chunk functions (`<name>_partK`, of at most
//! [`Sizes::chunk_values`] values each) that hand values on through arrays the calling function
//! owns; a function with a first stage
//! best compiled apart (forward dynamics in its derivatives) also ends a chunk there.
//!
//! Each chunk writes the values later chunks read into an array of its own as soon as it
//! computes them (`*h3 = x17;`), and reads an earlier chunk's value from that chunk's array
//! right before its first use (`x17 = *x17_in;`); the outputs it computes go straight into the
//! result (`*o5 = x17;`). The calling function only owns the arrays and the result and calls
//! the chunks in order: nothing is copied between chunks, and its code stays a few calls long.
//! (Returning the handed-on values and passing them on as arguments made the caller copy every
//! one at every chunk, and kept them alive to the end of the chunk that computed them: the
//! Unitree G1's `∂τ/∂x` caller alone was 261 KB of moves.)

use super::header::{Emitted, Header};
use super::into_form::{has_into_form, into_method, zero_pattern};
use super::kernel::{function_item, in_caller_type, KernelKind};
use super::outputs::{result_value, slots_pattern, slots_target, writes_in_place, zero_result, OutputSlots};
use super::plan::{Form, Plan};
use super::signature::{all_parameters, argument_names, signature, Param};
use super::sizes::Sizes;
use crate::generate::trace::Quantity;
use crate::symbolic::Id;
use proc_macro2::{Ident, Literal, TokenStream};
use quote::{format_ident, quote};
use std::collections::{BTreeSet, HashMap};

/// Where each chunk of `len` values starts: a chunk ends at `stage_end` (a stage whose results
/// everything after it reads, such as forward dynamics before the derivatives taken at its
/// `q̈`), and none holds more than `chunk` values.
fn segment_starts(len: usize, chunk: usize, stage_end: Option<usize>) -> Vec<usize> {
    let split = stage_end.filter(|&e| e > 0 && e < len);
    let mut starts = Vec::new();
    for (from, to) in match split {
        Some(e) => vec![(0, e), (e, len)],
        None => vec![(0, len)],
    } {
        starts.extend((from..to).step_by(chunk.max(1)));
    }
    starts
}

/// The values one chunk hands on, scalars and lane vectors apart, each at its index in the
/// chunk's array of that kind.
struct HandedOn {
    scalars: Vec<Id>,
    lanes: Vec<Id>,
}

/// `q` as chunk functions and the method that calls them (see the module's docs). `atoms` are
/// the outputs as operands, `main_used` the inputs they read.
pub(super) fn chunked(
    plan: &Plan,
    q: &Quantity,
    header: &Header,
    atoms: &[TokenStream],
    main_used: Vec<Id>,
    stage_end: Option<usize>,
    sizes: &Sizes,
) -> Emitted {
    let form = plan.form;
    let g = &plan.robot.graph;
    let position: HashMap<Id, usize> = plan.order.iter().enumerate().map(|(k, &id)| (id, k)).collect();
    let starts = segment_starts(plan.order.len(), sizes.chunk_values, stage_end);
    let chunk_of = |id: &Id| position.get(id).map(|&k| starts.partition_point(|&s| s <= k) - 1);
    let n_chunks = starts.len();
    let in_place = writes_in_place(q, form);
    // What each chunk reads from earlier ones (the last entry: the method, which reads the
    // outputs it builds its result from when the result is not written in place), and what
    // each hands on. Sets, because a chunk of a large function carries thousands of values.
    let mut reads: Vec<BTreeSet<Id>> = vec![BTreeSet::new(); n_chunks + 1];
    let mut handed: Vec<BTreeSet<Id>> = vec![BTreeSet::new(); n_chunks];
    for &id in &plan.order {
        let here = chunk_of(&id).unwrap_or(0);
        for operand in plan.operands(id) {
            if let Some(there) = chunk_of(&operand).filter(|&c| c < here) {
                reads[here].insert(operand);
                handed[there].insert(operand);
            }
        }
    }
    if !in_place {
        for o in &q.outputs {
            if let Some(c) = chunk_of(o) {
                reads[n_chunks].insert(*o);
                handed[c].insert(*o);
            }
        }
    }
    let handed: Vec<HandedOn> = handed
        .into_iter()
        .map(|ids| {
            let (lanes, scalars) = ids.into_iter().partition(|&id| g.node(id).is_lanes());
            HandedOn { scalars, lanes }
        })
        .collect();
    let ty = form.value_type();
    // What the arrays between chunks hold: a lane function's values in the caller's lane type
    // `C`, as each chunk is a kernel of its own (converted on the way in and out).
    let (handed_ty, zero) = match form {
        Form::Scalar => (ty.clone(), quote!(0.0)),
        Form::Lanes => (quote!(C), quote!(C::splat(0.0))),
    };
    // The arrays chunk `c` hands on through: `h3: [f64; 120]`, `l3: [[f64; 8]; 40]`.
    let width = Literal::usize_unsuffixed(plan.lanes.lanes());
    let lane_array = quote!([f64; #width]);
    let array_names = |c: usize| (format_ident!("h{c}"), format_ident!("l{c}"));
    let args = argument_names(&q.args);
    let mut chunks = Vec::new();
    let mut calls = Vec::new();
    let mut into_calls = Vec::new();
    let mut arrays = Vec::new();
    let ends = starts.iter().skip(1).copied().chain([plan.order.len()]);
    for (k, ids) in starts
        .iter()
        .zip(ends)
        .map(|(&a, b)| &plan.order[a..b])
        .enumerate()
    {
        let chunk_name = format_ident!("{}{}_part{}", q.name(), header.suffix, k);
        let outputs = match in_place {
            true => OutputSlots::new(plan, q, atoms, |id| {
                chunk_of(&id) == Some(k) || (k == 0 && chunk_of(&id).is_none())
            }),
            false => OutputSlots::new(plan, q, atoms, |_| false),
        };
        let mut used = Vec::new();
        if in_place && k == 0 {
            // The outputs that are inputs, written by the first chunk.
            for o in q.outputs.iter().filter(|o| chunk_of(o).is_none()) {
                plan.atom(*o, &mut used);
            }
        }
        let mut unpack = Vec::new();
        let mut extra_params = Vec::new();
        let mut call_args: Vec<TokenStream> = args.iter().map(|a| quote!(#a)).collect();
        let mut out_at = None;
        if outputs.any() {
            let ret = in_caller_type(form, &header.ret);
            extra_params.push(Param::used(format_ident!("out"), quote!(&mut #ret)));
            out_at = Some(call_args.len());
            call_args.push(quote!(&mut out));
            let (pattern, target) = (
                slots_pattern(q, form, &outputs.pattern),
                slots_target(q, form, quote!(out), true),
            );
            unpack.push(quote!(let #pattern = #target;));
        }
        // Earlier chunks' values this one reads: bound by reference at the top, read right
        // before their first use.
        let mut read_statements: HashMap<Id, TokenStream> = HashMap::new();
        let (mut read_scalars, mut read_lanes) = (Vec::new(), Vec::new());
        for (c, from) in handed.iter().enumerate().take(k) {
            let (h, l) = array_names(c);
            for (list, lanes) in [(&from.scalars, false), (&from.lanes, true)] {
                if !list.iter().any(|id| reads[k].contains(id)) {
                    continue;
                }
                let pattern = list.iter().map(|id| match reads[k].contains(id) {
                    true => {
                        let r = format_ident!("{}_in", plan.names[id]);
                        quote!(#r)
                    }
                    false => quote!(_),
                });
                let (array, array_ty, len) = match lanes {
                    true => (&l, lane_array.clone(), list.len()),
                    false => (&h, handed_ty.clone(), list.len()),
                };
                let len = Literal::usize_unsuffixed(len);
                extra_params.push(Param::used(array.clone(), quote!(&[#array_ty; #len])));
                call_args.push(quote!(&#array));
                unpack.push(quote!(let [#(#pattern),*] = #array;));
                for id in list.iter().filter(|id| reads[k].contains(id)) {
                    let (name, r) = (&plan.names[id], format_ident!("{}_in", plan.names[id]));
                    let statement = match lanes {
                        true => {
                            let built = plan.lanes.build(quote!(*#r));
                            quote!(#name = #built;)
                        }
                        false => match form {
                            Form::Scalar => quote!(#name = *#r;),
                            Form::Lanes => quote!(#name = dyngen_runtime::__private::lane_out(arith, *#r);),
                        },
                    };
                    read_statements.insert(*id, statement);
                    match lanes {
                        true => read_lanes.push(name.clone()),
                        false => read_scalars.push(name.clone()),
                    }
                }
            }
        }
        for (names, ty) in [
            (&read_scalars, ty.clone()),
            (&read_lanes, plan.lanes.vector_type()),
        ] {
            if !names.is_empty() {
                let len = Literal::usize_unsuffixed(names.len());
                unpack.push(quote!(let [#(#names),*]: [#ty; #len];));
            }
        }
        // This chunk's own arrays: each value written as soon as it is computed.
        let mut slots = outputs.slots;
        let (h, l) = array_names(k);
        for (list, array, array_ty, fill) in [
            (&handed[k].scalars, &h, handed_ty.clone(), zero.clone()),
            (&handed[k].lanes, &l, lane_array.clone(), quote!([0.0; #width])),
        ] {
            if list.is_empty() {
                continue;
            }
            let writes: Vec<Ident> = list
                .iter()
                .map(|id| format_ident!("{}_out", plan.names[id]))
                .collect();
            for (id, w) in list.iter().zip(&writes) {
                slots.entry(*id).or_default().push(w.clone());
            }
            let len = Literal::usize_unsuffixed(list.len());
            extra_params.push(Param::used(array.clone(), quote!(&mut [#array_ty; #len])));
            call_args.push(quote!(&mut #array));
            unpack.push(quote!(let [#(#writes),*] = #array;));
            arrays.push(quote!(let mut #array: [#array_ty; #len] = [#fill; #len];));
        }
        let immediate = &outputs.immediate;
        let statements = plan.statements_writing(ids, &mut used, &slots, &read_statements);
        let sig = signature(plan.robot, plan.leaves, &q.args, &used, &header.n, form);
        let (mut params, prelude) = (sig.params, sig.prelude);
        params.extend(extra_params);
        let reads_lanes = !read_lanes.is_empty();
        chunks.push(function_item(
            form,
            quote!(#[inline(never)]),
            &chunk_name,
            &params,
            &TokenStream::new(),
            KernelKind {
                uses_arith: plan.uses_arith(ids) || reads_lanes,
                lanes: (plan.uses_lanes(ids) || reads_lanes).then_some(plan.lanes),
                many_registers: header.many_registers,
            },
            quote!(#(#prelude)* #(#unpack)* #(#immediate)* #(#statements)*),
        ));
        calls.push(quote!(#chunk_name(#(#call_args),*);));
        // The `_into` form passes on the buffer's `&mut` itself.
        if let Some(k) = out_at {
            call_args[k] = quote!(out);
        }
        into_calls.push(quote!(#chunk_name(#(#call_args),*);));
    }
    let (name, ret, doc) = (&header.name, &header.ret, header.doc(0));
    let params = all_parameters(&q.args, &header.n, form, plan.leaves.floating_joints);
    let body = match in_place {
        true => {
            let zero = zero_result(q, form, sizes);
            let out_type = in_caller_type(form, ret);
            quote! {
                let mut out: #out_type = #zero;
                #(#arrays)*
                #(#calls)*
                out
            }
        }
        false => {
            // The outputs come back through the chunks' arrays.
            let mut taken = Vec::new();
            for (c, from) in handed.iter().enumerate() {
                let (h, _) = array_names(c);
                if from.scalars.iter().any(|id| reads[n_chunks].contains(id)) {
                    let pattern = from.scalars.iter().map(|id| match reads[n_chunks].contains(id) {
                        true => {
                            let name = &plan.names[id];
                            quote!(#name)
                        }
                        false => quote!(_),
                    });
                    taken.push(quote!(let [#(#pattern),*] = #h;));
                }
            }
            let prelude = signature(plan.robot, plan.leaves, &q.args, &main_used, &header.n, form).prelude;
            let result = result_value(q, form, atoms);
            quote! {
                #(#prelude)*
                #(#arrays)*
                #(#calls)*
                #(#taken)*
                #result
            }
        }
    };
    // The `_into` form: the same chunks, writing into the caller's buffer.
    let into = match has_into_form(q, form) {
        true => into_method(
            name,
            &params,
            ret,
            zero_pattern(q, g),
            quote!(#(#arrays)* #(#into_calls)*),
        ),
        false => quote!(),
    };
    // A lane function's calling function is in the caller's lane type `C` throughout.
    let generics = match form {
        Form::Scalar => quote!(),
        Form::Lanes => quote!(<C: Lanes>),
    };
    let params: Vec<TokenStream> = params.iter().map(|p| in_caller_type(form, p)).collect();
    let ret = in_caller_type(form, ret);
    let method = quote! {
        #(#[doc = #doc])*
        #[inline(never)]
        fn #name #generics(#(#params),*) -> #ret {
            #body
        }

        #into
    };
    Emitted { method, chunks }
}

#[cfg(test)]
mod tests {
    use super::segment_starts;

    #[test]
    fn chunks_hold_at_most_the_chunk_size() {
        assert_eq!(segment_starts(10, 4, None), vec![0, 4, 8]);
        assert_eq!(segment_starts(8, 4, None), vec![0, 4]);
        assert_eq!(segment_starts(3, 4, None), vec![0]);
    }

    #[test]
    fn a_chunk_ends_where_the_first_stage_does() {
        assert_eq!(segment_starts(10, 100, Some(3)), vec![0, 3]);
        // Each stage in chunks of its own.
        assert_eq!(segment_starts(10, 4, Some(6)), vec![0, 4, 6]);
        assert_eq!(segment_starts(10, 4, Some(2)), vec![0, 2, 6]);
        // A stage of nothing, or of everything, splits nothing.
        assert_eq!(segment_starts(10, 100, Some(0)), vec![0]);
        assert_eq!(segment_starts(10, 100, Some(10)), vec![0]);
    }
}
