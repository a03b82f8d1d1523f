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

/// How a function's values flow between its chunks: which chunk computes each, what each reads
/// from earlier ones, and what each hands on.
struct Flow<'p, 'a> {
    plan: &'p Plan<'a>,
    /// Where each chunk starts in the plan's order.
    starts: Vec<usize>,
    /// Each computed value's place in the plan's order.
    position: HashMap<Id, usize>,
    /// What each chunk reads from earlier ones; the last entry is the calling method, which
    /// reads the outputs it builds its result from when the result is not written in place.
    /// Sets, because a chunk of a large function carries thousands of values.
    reads: Vec<BTreeSet<Id>>,
    handed: Vec<HandedOn>,
    /// Whether the result is written in place (each chunk writes the outputs it computes).
    in_place: bool,
}

impl<'p, 'a> Flow<'p, 'a> {
    fn new(plan: &'p Plan<'a>, q: &Quantity, stage_end: Option<usize>, sizes: &Sizes) -> Self {
        let mut flow = Flow {
            plan,
            starts: segment_starts(plan.order.len(), sizes.chunk_values, stage_end),
            position: plan.order.iter().enumerate().map(|(k, &id)| (id, k)).collect(),
            reads: Vec::new(),
            handed: Vec::new(),
            in_place: writes_in_place(q, plan.form),
        };
        let n_chunks = flow.starts.len();
        let mut reads: Vec<BTreeSet<Id>> = vec![BTreeSet::new(); n_chunks + 1];
        let mut handed: Vec<BTreeSet<Id>> = vec![BTreeSet::new(); n_chunks];
        for &id in &plan.order {
            let here = flow.chunk_of(&id).unwrap_or(0);
            for operand in plan.operands(id) {
                if let Some(there) = flow.chunk_of(&operand).filter(|&c| c < here) {
                    reads[here].insert(operand);
                    handed[there].insert(operand);
                }
            }
        }
        if !flow.in_place {
            for o in &q.outputs {
                if let Some(c) = flow.chunk_of(o) {
                    reads[n_chunks].insert(*o);
                    handed[c].insert(*o);
                }
            }
        }
        let g = &plan.robot.graph;
        flow.reads = reads;
        flow.handed = (handed.into_iter())
            .map(|ids| {
                let (lanes, scalars) = ids.into_iter().partition(|&id| g.node(id).is_lanes());
                HandedOn { scalars, lanes }
            })
            .collect();
        flow
    }

    /// The chunk that computes `id`; `None` for an input or a constant.
    fn chunk_of(&self, id: &Id) -> Option<usize> {
        (self.position.get(id)).map(|&k| self.starts.partition_point(|&s| s <= k) - 1)
    }

    /// The values each chunk computes, in order.
    fn chunks(&self) -> impl Iterator<Item = &[Id]> {
        let order = &self.plan.order;
        let ends = self.starts.iter().skip(1).copied().chain([order.len()]);
        self.starts.iter().zip(ends).map(|(&a, b)| &order[a..b])
    }

    /// Where chunk `k` writes outputs: the ones it computes (the first chunk also those that
    /// are inputs), when the result is written in place; none when the method builds it.
    fn output_slots(&self, q: &Quantity, atoms: &[TokenStream], k: usize) -> OutputSlots {
        match self.in_place {
            true => OutputSlots::new(self.plan, q, atoms, |id| {
                self.chunk_of(&id) == Some(k) || (k == 0 && self.chunk_of(&id).is_none())
            }),
            false => OutputSlots::new(self.plan, q, atoms, |_| false),
        }
    }
}

/// The arrays chunk `c` hands on through: `h3: [f64; 120]` of scalars, `l3: [[f64; 8]; 40]` of
/// lane vectors.
fn array_names(c: usize) -> (Ident, Ident) {
    (format_ident!("h{c}"), format_ident!("l{c}"))
}

/// What the arrays between chunks hold, and what they start as. A lane function's scalars are
/// in the caller's lane type `C`, as each chunk is a kernel of its own (converted on the way in
/// and out).
struct ArrayTypes {
    scalar: TokenStream,
    scalar_zero: TokenStream,
    lanes: TokenStream,
    lanes_zero: TokenStream,
}

impl ArrayTypes {
    fn new(plan: &Plan) -> ArrayTypes {
        let (scalar, scalar_zero) = match plan.form {
            Form::Scalar => (plan.form.value_type(), quote!(0.0)),
            Form::Lanes => (quote!(C), quote!(C::splat(0.0))),
        };
        let width = Literal::usize_unsuffixed(plan.lanes.lanes());
        ArrayTypes {
            scalar,
            scalar_zero,
            lanes: quote!([f64; #width]),
            lanes_zero: quote!([0.0; #width]),
        }
    }
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
    let flow = Flow::new(plan, q, stage_end, sizes);
    let types = ArrayTypes::new(plan);
    let chunks: Vec<Chunk> = (flow.chunks().enumerate())
        .map(|(k, ids)| chunk(&flow, &types, q, header, atoms, k, ids))
        .collect();
    let method = calling_method(&flow, q, header, atoms, &main_used, &chunks, sizes);
    Emitted {
        method,
        chunks: chunks.into_iter().map(|c| c.item).collect(),
    }
}

/// One chunk: its function, how the method calls it (by value, and in the `_into` form), and
/// the arrays it hands on through, which the calling method declares.
struct Chunk {
    item: TokenStream,
    call: TokenStream,
    into_call: TokenStream,
    arrays: Vec<TokenStream>,
}

/// What a chunk takes besides the function's arguments, as it is added: its parameters, the
/// call's arguments, and the statements that unpack them.
struct ChunkParts {
    params: Vec<Param>,
    args: Vec<TokenStream>,
    unpack: Vec<TokenStream>,
    /// Where the call passes the result (`&mut out`), if the chunk writes outputs.
    out_at: Option<usize>,
}

impl ChunkParts {
    /// `param`, passed as `arg`, unpacked by `unpack`.
    fn pass(&mut self, param: Param, arg: TokenStream, unpack: TokenStream) {
        self.params.push(param);
        self.args.push(arg);
        self.unpack.push(unpack);
    }
}

/// The earlier chunks' values a chunk reads: bound by reference at its top, each read by its
/// statement right before its first use.
struct Reads {
    statements: HashMap<Id, TokenStream>,
    lanes: bool,
}

/// Chunk `k` of the values `ids`.
fn chunk(
    flow: &Flow,
    types: &ArrayTypes,
    q: &Quantity,
    header: &Header,
    atoms: &[TokenStream],
    k: usize,
    ids: &[Id],
) -> Chunk {
    let (plan, form) = (flow.plan, flow.plan.form);
    let outputs = flow.output_slots(q, atoms, k);
    let mut used = Vec::new();
    if flow.in_place && k == 0 {
        // The outputs that are inputs, written by the first chunk.
        for o in q.outputs.iter().filter(|o| flow.chunk_of(o).is_none()) {
            plan.atom(*o, &mut used);
        }
    }
    let names = argument_names(&q.args);
    let mut parts = ChunkParts {
        params: Vec::new(),
        args: names.iter().map(|a| quote!(#a)).collect(),
        unpack: Vec::new(),
        out_at: None,
    };
    if outputs.any() {
        let ret = in_caller_type(form, &header.ret);
        parts.out_at = Some(parts.args.len());
        let (pattern, target) = (
            slots_pattern(q, form, &outputs.pattern),
            slots_target(q, form, quote!(out), true),
        );
        parts.pass(
            Param::used(format_ident!("out"), quote!(&mut #ret)),
            quote!(&mut out),
            quote!(let #pattern = #target;),
        );
    }
    let reads = read_earlier(flow, types, k, &mut parts);
    let mut slots = outputs.slots;
    let arrays = hand_on(flow, types, k, &mut parts, &mut slots);
    let statements = plan.statements_writing(ids, &mut used, &slots, &reads.statements);
    let sig = signature(plan.robot, plan.leaves, &q.args, &used, &header.n, form);
    let mut params = sig.params;
    params.extend(parts.params);
    let (prelude, unpack, immediate) = (sig.prelude, parts.unpack, outputs.immediate);
    let name = format_ident!("{}{}_part{}", q.name(), header.suffix, k);
    // A chunk of a large kernel takes each earlier chunk's arrays it reads: more than clippy's
    // seven arguments is the design, not a smell, in code nobody edits.
    let attributes = match params.len() > 7 {
        true => quote!(#[inline(never)] #[allow(clippy::too_many_arguments)]),
        false => quote!(#[inline(never)]),
    };
    let item = function_item(
        form,
        attributes,
        &name,
        &params,
        &TokenStream::new(),
        KernelKind {
            uses_arith: plan.uses_arith(ids) || reads.lanes,
            lanes: (plan.uses_lanes(ids) || reads.lanes).then_some(plan.lanes),
            many_registers: header.many_registers,
        },
        quote!(#(#prelude)* #(#unpack)* #(#immediate)* #(#statements)*),
    );
    let mut args = parts.args;
    let call = quote!(#name(#(#args),*););
    // The `_into` form passes on the buffer's `&mut` itself.
    if let Some(k) = parts.out_at {
        args[k] = quote!(out);
    }
    Chunk {
        item,
        call,
        into_call: quote!(#name(#(#args),*);),
        arrays,
    }
}

/// Passes chunk `k` the arrays of the earlier chunks' values it reads, and declares those
/// values.
fn read_earlier(flow: &Flow, types: &ArrayTypes, k: usize, parts: &mut ChunkParts) -> Reads {
    let plan = flow.plan;
    let reads = &flow.reads[k];
    let mut statements: HashMap<Id, TokenStream> = HashMap::new();
    let (mut read_scalars, mut read_lanes) = (Vec::new(), Vec::new());
    for (c, from) in flow.handed.iter().enumerate().take(k) {
        let (h, l) = array_names(c);
        for (list, lanes) in [(&from.scalars, false), (&from.lanes, true)] {
            if !list.iter().any(|id| reads.contains(id)) {
                continue;
            }
            let pattern = list.iter().map(|id| match reads.contains(id) {
                true => {
                    let r = format_ident!("{}_in", plan.names[id]);
                    quote!(#r)
                }
                false => quote!(_),
            });
            let (array, array_ty) = match lanes {
                true => (&l, &types.lanes),
                false => (&h, &types.scalar),
            };
            let len = Literal::usize_unsuffixed(list.len());
            parts.pass(
                Param::used(array.clone(), quote!(&[#array_ty; #len])),
                quote!(&#array),
                quote!(let [#(#pattern),*] = #array;),
            );
            for id in list.iter().filter(|id| reads.contains(id)) {
                let (name, r) = (&plan.names[id], format_ident!("{}_in", plan.names[id]));
                let statement = match (lanes, plan.form) {
                    (true, _) => {
                        let built = plan.lanes.build(quote!(*#r));
                        quote!(#name = #built;)
                    }
                    (false, Form::Scalar) => quote!(#name = *#r;),
                    (false, Form::Lanes) => quote!(#name = dyngen_runtime::__private::lane_out(arith, *#r);),
                };
                statements.insert(*id, statement);
                match lanes {
                    true => read_lanes.push(name.clone()),
                    false => read_scalars.push(name.clone()),
                }
            }
        }
    }
    for (names, ty) in [
        (&read_scalars, plan.form.value_type()),
        (&read_lanes, plan.lanes.vector_type()),
    ] {
        if !names.is_empty() {
            let len = Literal::usize_unsuffixed(names.len());
            parts.unpack.push(quote!(let [#(#names),*]: [#ty; #len];));
        }
    }
    Reads {
        statements,
        lanes: !read_lanes.is_empty(),
    }
}

/// Passes chunk `k` its own arrays, each value it hands on written as soon as it is computed
/// (a slot in `slots`); returns the arrays' declarations.
fn hand_on(
    flow: &Flow,
    types: &ArrayTypes,
    k: usize,
    parts: &mut ChunkParts,
    slots: &mut HashMap<Id, Vec<Ident>>,
) -> Vec<TokenStream> {
    let (h, l) = array_names(k);
    let handed = &flow.handed[k];
    let mut arrays = Vec::new();
    for (list, array, array_ty, fill) in [
        (&handed.scalars, &h, &types.scalar, &types.scalar_zero),
        (&handed.lanes, &l, &types.lanes, &types.lanes_zero),
    ] {
        if list.is_empty() {
            continue;
        }
        let writes: Vec<Ident> = (list.iter())
            .map(|id| format_ident!("{}_out", flow.plan.names[id]))
            .collect();
        for (id, w) in list.iter().zip(&writes) {
            slots.entry(*id).or_default().push(w.clone());
        }
        let len = Literal::usize_unsuffixed(list.len());
        parts.pass(
            Param::used(array.clone(), quote!(&mut [#array_ty; #len])),
            quote!(&mut #array),
            quote!(let [#(#writes),*] = #array;),
        );
        arrays.push(quote!(let mut #array: [#array_ty; #len] = [#fill; #len];));
    }
    arrays
}

/// The method that owns the arrays and the result and calls the chunks in order, and its
/// `_into` form, which calls the same chunks on the caller's buffer.
fn calling_method(
    flow: &Flow,
    q: &Quantity,
    header: &Header,
    atoms: &[TokenStream],
    main_used: &[Id],
    chunks: &[Chunk],
    sizes: &Sizes,
) -> TokenStream {
    let (plan, form) = (flow.plan, flow.plan.form);
    let (name, ret, doc) = (&header.name, &header.ret, header.doc(0));
    let arrays = chunks.iter().flat_map(|c| &c.arrays);
    let calls = chunks.iter().map(|c| &c.call);
    let body = match flow.in_place {
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
            let taken = taken_outputs(flow);
            let prelude = signature(plan.robot, plan.leaves, &q.args, main_used, &header.n, form).prelude;
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
    let params = all_parameters(&q.args, &header.n, form, plan.leaves.floating_joints);
    let into = match has_into_form(q, form) {
        true => {
            let (arrays, into_calls) = (
                chunks.iter().flat_map(|c| &c.arrays),
                chunks.iter().map(|c| &c.into_call),
            );
            let pattern = zero_pattern(q, &plan.robot.graph);
            into_method(name, &params, ret, pattern, quote!(#(#arrays)* #(#into_calls)*))
        }
        false => quote!(),
    };
    // A lane function's calling function is in the caller's lane type `C` throughout.
    let generics = match form {
        Form::Scalar => quote!(),
        Form::Lanes => quote!(<C: Lanes>),
    };
    let params: Vec<TokenStream> = params.iter().map(|p| in_caller_type(form, p)).collect();
    let ret = in_caller_type(form, ret);
    quote! {
        #(#[doc = #doc])*
        #[inline(never)]
        fn #name #generics(#(#params),*) -> #ret {
            #body
        }

        #into
    }
}

/// The outputs a method that builds its result takes back from the chunks' arrays.
fn taken_outputs(flow: &Flow) -> Vec<TokenStream> {
    let reads = flow.reads.last().expect("the method's reads");
    let mut taken = Vec::new();
    for (c, from) in flow.handed.iter().enumerate() {
        let (h, _) = array_names(c);
        if from.scalars.iter().any(|id| reads.contains(id)) {
            let pattern = from.scalars.iter().map(|id| match reads.contains(id) {
                true => {
                    let name = &flow.plan.names[id];
                    quote!(#name)
                }
                false => quote!(_),
            });
            taken.push(quote!(let [#(#pattern),*] = #h;));
        }
    }
    taken
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
