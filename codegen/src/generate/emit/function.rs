//! One quantity as a generated function: its result type, its body (written in place or built
//! at the end), the kernel and dispatch around it, and its chunks when it is large.

use super::leaves::Leaves;
use super::plan::{Form, Plan};
use super::signature::{all_parameters, argument_names, signature, Param};
use crate::generate::trace::{Quantity, Shape, SymbolicRobot};
use crate::symbolic::{Id, Node, OpCounts};
use proc_macro2::{Ident, Literal, TokenStream};
use quote::{format_ident, quote};
use std::collections::{BTreeSet, HashMap};

/// Values per chunk function. Larger functions run faster (nothing is copied between chunks:
/// the Panda's `C` and `Y` run 15–18% faster whole than in chunks of 1024, and every function of
/// a 7-DOF arm but the derivatives of the dynamics fits in one chunk), while chunks bound the
/// size of what LLVM optimises at once, whose cost grows faster than linearly, for very large
/// robots. (The Panda's derivatives, about 7,000 values, ran no faster whole, in chunks of 16384.)
/// Chunks do not shrink what a call runs: the Panda's `∂q̈/∂x`, 39 KB of machine code, is over a
/// 32 KiB level-1 instruction cache either way, and splitting it made the total larger and the
/// call 15% slower (`BENCHMARKS.md`).
const CHUNK: usize = 4096;

/// A generated function. A scalar one runs its body as a `dyngen_runtime::__private::Kernel`
/// through `dyngen_runtime::__private::dispatch`: with the processor's fused multiply-adds even in
/// a build that does not target them (the body names its multiply-adds `arith.mul_add`), and
/// through `dyngen_runtime::__private::dispatch_eight` where it carries lane vectors (`uses_lanes`)
/// or holds far more values than sixteen registers (`many_registers`, see [`MANY_VALUES`]: a
/// default build then runs it compiled for AVX-512 where the processor has it, with the 32
/// registers of a native build). A lane function is generic over its lane type instead, and aligns
/// its stack frame for its spills (`dyngen_runtime::__private::align_stack_frame`).
#[allow(clippy::too_many_arguments)]
fn function_item(
    form: Form,
    attributes: TokenStream,
    name: &Ident,
    params: &[Param],
    ret: &TokenStream,
    uses_arith: bool,
    uses_lanes: bool,
    many_registers: bool,
    body: TokenStream,
) -> TokenStream {
    if form == Form::Lanes {
        let params = params.iter().map(Param::declared);
        // Its lane vectors spill whole to 64-byte-aligned slots (see the function's docs).
        return quote! {
            #attributes
            fn #name<L: Lanes>(#(#params),*) -> #ret {
                dyngen_runtime::__private::align_stack_frame();
                #body
            }
        };
    }
    let outer = params.iter().map(|p| {
        let (name, ty) = (&p.name, &p.ty);
        quote!(#name: #ty)
    });
    let names = params.iter().map(|p| &p.name);
    let bindings = params.iter().map(Param::binding);
    let types: Vec<&TokenStream> = params.iter().map(|p| &p.ty).collect();
    let arith = match uses_arith {
        true => format_ident!("arith"),
        false => format_ident!("_arith"),
    };
    let dispatch = match uses_lanes || many_registers {
        true => quote!(dyngen_runtime::__private::dispatch_eight),
        false => quote!(dyngen_runtime::__private::dispatch),
    };
    // A kernel with lane vectors calls their multiply-adds as methods of `M::Eight`.
    let lane_methods = match uses_lanes {
        true => quote!(
            use dyngen_runtime::__private::EightLanes as _;
        ),
        false => quote!(),
    };
    quote! {
        #attributes
        fn #name(#(#outer),*) -> #ret {
            struct Body;
            impl dyngen_runtime::__private::Kernel<(#(#types,)*)> for Body {
                type Output = #ret;
                #[inline(always)]
                fn run<M: dyngen_runtime::__private::MulAdd>(#arith: M, (#(#bindings,)*): (#(#types,)*)) -> #ret {
                    #lane_methods
                    #body
                }
            }
            #dispatch::<Body, _>((#(#names,)*))
        }
    }
}

fn doc_counts(c: &OpCounts) -> String {
    let mut s = format!("Operations: {} mul, {} add/sub, {} neg", c.mul, c.add, c.neg);
    if c.div > 0 {
        s += &format!(", {} div", c.div);
    }
    if c.trig > 0 {
        s += &format!(", {} sin/cos", c.trig);
    }
    if c.friction > 0 {
        s += &format!(", {} sign/tanh", c.friction);
    }
    if c.lanes > 0 {
        s += &format!(
            ", and {} lane ops (f64x8: each on eight lanes at once; splats, seeds and lane \
             extractions included)",
            c.lanes
        );
    }
    s + " (joint sines and cosines come precomputed in `JointTrig`)."
}

/// A generated function: its trait method, and the chunk functions it calls (if it is large).
pub(super) struct Emitted {
    pub(super) method: TokenStream,
    pub(super) chunks: Vec<TokenStream>,
}

/// Suffix of the lane form of a function's name: `inverse_dynamics_lanes`.
const LANES_SUFFIX: &str = "_lanes";

pub(super) fn function(
    robot: &SymbolicRobot,
    leaves: &Leaves,
    q: &Quantity,
    n: usize,
    form: Form,
) -> Emitted {
    let n = Literal::usize_unsuffixed(n);
    let plan = Plan::new(robot, leaves, &q.outputs, form);
    let ty = form.value_type();
    // Lane functions are generic over the lane type, so they cost nothing until a user calls
    // them (then once per lane type).
    let generics = match form {
        Form::Scalar => quote!(),
        Form::Lanes => quote!(<L: Lanes>),
    };
    let suffix = match form {
        Form::Scalar => "",
        Form::Lanes => LANES_SUFFIX,
    };
    let position: HashMap<Id, usize> = plan.order.iter().enumerate().map(|(k, &id)| (id, k)).collect();
    let chunk_of = |id: &Id| position.get(id).map(|k| k / CHUNK);
    let n_chunks = plan.order.len().div_ceil(CHUNK).max(1);
    // Values each chunk needs from earlier chunks, and values each chunk hands on; sets, because
    // a chunk of a large function carries thousands of values (a linear `contains` per operand
    // made emitting a 30-DOF chain's derivatives take over a minute).
    let mut carried_in: Vec<BTreeSet<Id>> = vec![BTreeSet::new(); n_chunks];
    let mut handed_on: Vec<BTreeSet<Id>> = vec![BTreeSet::new(); n_chunks];
    for &id in &plan.order {
        let here = chunk_of(&id).unwrap_or(0);
        for operand in plan.operands(id) {
            if let Some(there) = chunk_of(&operand).filter(|&c| c < here) {
                carried_in[here].insert(operand);
                handed_on[there].insert(operand);
            }
        }
    }
    for o in &q.outputs {
        if let Some(c) = chunk_of(o) {
            if n_chunks > 1 {
                handed_on[c].insert(*o);
            }
        }
    }
    let sorted = |sets: Vec<BTreeSet<Id>>| -> Vec<Vec<Id>> {
        sets.into_iter().map(|s| s.into_iter().collect()).collect()
    };
    let (carried_in, handed_on) = (sorted(carried_in), sorted(handed_on));
    let name = format_ident!("{}{suffix}", q.name());
    let mut main_used = Vec::new();
    let atoms: Vec<TokenStream> = q.outputs.iter().map(|&o| plan.atom(o, &mut main_used)).collect();
    let result = match (form, q.shape) {
        (Form::Lanes, Shape::Vector(_)) => quote!([#(#atoms),*]),
        (Form::Lanes, Shape::Matrix(rows, _)) => {
            let columns = atoms.chunks(rows).map(|c| quote!([#(#c),*]));
            quote!([#(#columns),*])
        }
        (Form::Lanes, _) => unreachable!("only vectors and matrices have a lane form"),
        (Form::Scalar, shape) => match shape {
            Shape::Vector(_) => quote!(SVector::from_array_storage(ArrayStorage([[#(#atoms),*]]))),
            Shape::Matrix(rows, _) => {
                let columns = atoms.chunks(rows).map(|c| quote!([#(#c),*]));
                quote!(SMatrix::from_array_storage(ArrayStorage([#(#columns),*])))
            }
            Shape::Pose => pose_value(&atoms),
            Shape::Kinematics(_) => {
                let (pose, jacobians) = atoms.split_at(12);
                let (j, jd) = jacobians.split_at(jacobians.len() / 2);
                let pose = pose_value(pose);
                let matrix = |m: &[TokenStream]| {
                    let c: Vec<TokenStream> = m.chunks(6).map(|c| quote!([#(#c),*])).collect();
                    quote!(SMatrix::from_array_storage(ArrayStorage([#(#c),*])))
                };
                let (j, jd) = (matrix(j), matrix(jd));
                quote!((#pose, #j, #jd))
            }
            Shape::VectorPair(n, _) => {
                let (first, second) = atoms.split_at(n);
                quote!((
                    SVector::from_array_storage(ArrayStorage([[#(#first),*]])),
                    SVector::from_array_storage(ArrayStorage([[#(#second),*]])),
                ))
            }
            Shape::MatrixPair(rows) => {
                let (first, second) = atoms.split_at(rows * rows);
                let columns = |m: &[TokenStream]| {
                    let c: Vec<TokenStream> = m.chunks(rows).map(|c| quote!([#(#c),*])).collect();
                    quote!(SMatrix::from_array_storage(ArrayStorage([#(#c),*])))
                };
                let (first, second) = (columns(first), columns(second));
                quote!((#first, #second))
            }
        },
    };
    let ret = match (form, q.shape) {
        (Form::Lanes, Shape::Vector(len)) => {
            let len = Literal::usize_unsuffixed(len);
            quote!([L; #len])
        }
        (Form::Lanes, Shape::Matrix(r, c)) => {
            let (r, c) = (Literal::usize_unsuffixed(r), Literal::usize_unsuffixed(c));
            quote!([[L; #r]; #c])
        }
        (Form::Lanes, _) => unreachable!("only vectors and matrices have a lane form"),
        (Form::Scalar, shape) => match shape {
            Shape::Vector(len) => {
                let len = Literal::usize_unsuffixed(len);
                quote!(SVector<f64, #len>)
            }
            Shape::Matrix(r, c) => {
                let (r, c) = (Literal::usize_unsuffixed(r), Literal::usize_unsuffixed(c));
                quote!(SMatrix<f64, #r, #c>)
            }
            Shape::Pose => quote!(Pose),
            Shape::Kinematics(n) => {
                let n = Literal::usize_unsuffixed(n);
                quote!((Pose, SMatrix<f64, 6, #n>, SMatrix<f64, 6, #n>))
            }
            Shape::MatrixPair(r) => {
                let r = Literal::usize_unsuffixed(r);
                quote!((SMatrix<f64, #r, #r>, SMatrix<f64, #r, #r>))
            }
            Shape::VectorPair(n, m) => {
                let (n, m) = (Literal::usize_unsuffixed(n), Literal::usize_unsuffixed(m));
                quote!((SVector<f64, #n>, SVector<f64, #m>))
            }
        },
    };
    let mut doc = vec![doc_counts(&robot.graph.op_counts(&q.outputs))];
    if q.kind.uses_base_columns() {
        let columns: Vec<String> = robot.base.columns.iter().map(|c| c.to_string()).collect();
        doc.insert(
            0,
            format!(
                " `Y_b`: columns {} of `Y` (the base parameters'), computed without the others.",
                columns.join(", ")
            ),
        );
    }
    let names_of = |ids: &[Id]| -> Vec<Ident> { ids.iter().map(|id| plan.names[id].clone()).collect() };

    let many_registers = matches!(q.shape, Shape::MatrixPair(_)) || plan.order.len() > MANY_VALUES;
    if n_chunks == 1 {
        let mut used = main_used;
        let body = match q.shape {
            Shape::Vector(_) | Shape::Matrix(..) | Shape::VectorPair(..) => {
                written_in_place(&plan, q, form, &ret, &atoms, &mut used)
            }
            _ => {
                let statements = plan.statements(&plan.order, &mut used);
                quote!(#(#statements)* #result)
            }
        };
        let sig = signature(robot, leaves, &q.args, &used, &n, form);
        let (params, prelude) = (sig.params, sig.prelude);
        let method = function_item(
            form,
            quote!(#(#[doc = #doc])* #[inline(never)]),
            &name,
            &params,
            &ret,
            plan.uses_arith(&plan.order),
            plan.uses_lanes(&plan.order),
            many_registers,
            quote!(#(#prelude)* #body),
        );
        return Emitted {
            method,
            chunks: Vec::new(),
        };
    }

    let args = argument_names(&q.args);
    let mut chunks = Vec::new();
    let mut calls = Vec::new();
    for (k, ids) in plan.order.chunks(CHUNK).enumerate() {
        let chunk_name = format_ident!("{}{suffix}_part{}", q.name(), k);
        let mut used = Vec::new();
        let statements = plan.statements(ids, &mut used);
        let sig = signature(robot, leaves, &q.args, &used, &n, form);
        let (mut params, prelude) = (sig.params, sig.prelude);
        // Values carried between chunks, scalars and lane vectors apart (each an array).
        let split = |ids: &[Id]| -> (Vec<Ident>, Vec<Ident>) {
            let (lanes, scalars): (Vec<Id>, Vec<Id>) =
                ids.iter().partition(|&&id| plan.robot.graph.node(id).is_lanes());
            (names_of(&scalars), names_of(&lanes))
        };
        let ((inputs, lane_inputs), (outputs, lane_outputs)) = (split(&carried_in[k]), split(&handed_on[k]));
        // Lane vectors cross chunks as plain arrays: each chunk is a kernel of its own, whose
        // lane type its own dispatch chooses.
        let lane_ty = quote!([f64; 8]);
        let (n_in, n_out, n_lane_in, n_lane_out) = (
            Literal::usize_unsuffixed(inputs.len()),
            Literal::usize_unsuffixed(outputs.len()),
            Literal::usize_unsuffixed(lane_inputs.len()),
            Literal::usize_unsuffixed(lane_outputs.len()),
        );
        let mut call_args: Vec<TokenStream> = args.iter().map(|a| quote!(#a)).collect();
        let mut unpack = Vec::new();
        if !inputs.is_empty() {
            params.push(Param::used(format_ident!("carried"), quote!([#ty; #n_in])));
            call_args.push(quote!([#(#inputs),*]));
            unpack.push(quote!(let [#(#inputs),*] = carried;));
        }
        if !lane_inputs.is_empty() {
            params.push(Param::used(
                format_ident!("carried_lanes"),
                quote!([#lane_ty; #n_lane_in]),
            ));
            call_args.push(quote!([#(#lane_inputs),*]));
            unpack.push(quote!(let [#(#lane_inputs),*] = carried_lanes.map(|lanes| arith.eight(lanes));));
        }
        let (ret, returned, bound) = match lane_outputs.is_empty() {
            true => (
                quote!([#ty; #n_out]),
                quote!([#(#outputs),*]),
                quote!([#(#outputs),*]),
            ),
            false => (
                quote!(([#ty; #n_out], [#lane_ty; #n_lane_out])),
                quote!(([#(#outputs),*], [#(#lane_outputs.to_array()),*])),
                quote!(([#(#outputs),*], [#(#lane_outputs),*])),
            ),
        };
        chunks.push(function_item(
            form,
            quote!(#[inline(never)]),
            &chunk_name,
            &params,
            &ret,
            plan.uses_arith(ids) || !lane_inputs.is_empty(),
            plan.uses_lanes(ids) || !lane_inputs.is_empty(),
            many_registers,
            quote!(#(#prelude)* #(#unpack)* #(#statements)* #returned),
        ));
        calls.push(quote!(let #bound = #chunk_name(#(#call_args),*);));
    }
    // Chunks read the arguments; the method itself reads only what its result needs.
    let prelude = signature(robot, leaves, &q.args, &main_used, &n, form).prelude;
    let params = all_parameters(&q.args, &n, form, leaves.floating_joints);
    let method = quote! {
        #(#[doc = #doc])*
        #[inline(never)]
        fn #name #generics(#(#params),*) -> #ret {
            #(#prelude)*
            #(#calls)*
            #result
        }
    };
    Emitted { method, chunks }
}

/// Results larger than this start from `dyngen_runtime::__private::fill_zero()` rather than a
/// constant zero, whose fill the compiler would make a call to `memset` (see that function).
/// Smaller ones keep the constant: the compiler fills them with at most sixteen inline stores
/// (AVX2), or drops the fill when every entry is written.
const LIBRARY_FILL_BYTES: usize = 512;

/// Functions that compute more values than this, and the derivatives of the dynamics, run through
/// `dyngen_runtime::__private::dispatch_eight`: their values outnumber sixteen registers many times
/// over, and in a default build that function gives them the 32 of AVX-512 where the processor has
/// it, as a native build does. Measured on `C`, the regressors and their products (arm7, Panda,
/// UR5): as fast as native or within a few percent, where the AVX2 function was up to 1.3× slower
/// (`BENCHMARKS.md`). Small kernels stay in the AVX2 function (`fk` was 20% slower in an AVX-512
/// one, in an earlier experiment).
const MANY_VALUES: usize = 1000;

/// Bytes of `q`'s result: `f64`s, or lane vectors of at least four.
fn result_bytes(q: &Quantity, form: Form) -> usize {
    q.outputs.len() * if form == Form::Lanes { 32 } else { 8 }
}

/// The body of a one-chunk vector or matrix function that writes each output into the result
/// as soon as it is computed: `let mut out: R = zeros; { let [[o0, _, o2]] = &mut out…;
/// x0 = …; *o0 = x0; … } out`. Returning them all at the end kept every output alive across the
/// whole function (the regressor's peak of live values was 260 instead of 103), so the
/// register allocator spilled them and reloaded them to store them.
fn written_in_place(
    plan: &Plan,
    q: &Quantity,
    form: Form,
    ret: &TokenStream,
    atoms: &[TokenStream],
    used: &mut Vec<Id>,
) -> TokenStream {
    let g = &plan.robot.graph;
    let mut slots: HashMap<Id, Vec<Ident>> = HashMap::new();
    let mut immediate = Vec::new();
    let pattern: Vec<TokenStream> = q
        .outputs
        .iter()
        .zip(atoms)
        .enumerate()
        .map(|(k, (&id, atom))| {
            let slot = format_ident!("o{k}");
            if g.constant_value(id) == Some(0.0) || g.node(id) == Node::LaneZero {
                return quote!(_);
            }
            match plan.names.contains_key(&id) {
                true => slots.entry(id).or_default().push(slot.clone()),
                false => immediate.push(quote!(*#slot = #atom;)),
            }
            quote!(#slot)
        })
        .collect();
    let statements = plan.statements_writing(&plan.order, used, &slots);
    let nested = |rows: usize| {
        let columns = pattern.chunks(rows).map(|c| quote!([#(#c),*]));
        quote!([#(#columns),*])
    };
    let (matrix, fill) = match result_bytes(q, form) > LIBRARY_FILL_BYTES {
        true => (
            quote!(SMatrix::from_element(dyngen_runtime::__private::fill_zero())),
            quote!(dyngen_runtime::__private::fill_zero()),
        ),
        false => (quote!(SMatrix::zeros()), quote!(0.0)),
    };
    let (slots_pattern, target, zero) = match (form, q.shape) {
        (Form::Scalar, Shape::Vector(rows) | Shape::Matrix(rows, _)) => {
            (nested(rows), quote!(&mut out.data.0), matrix)
        }
        (Form::Scalar, Shape::VectorPair(n, _)) => {
            let (first, second) = pattern.split_at(n);
            (
                quote!(([#(#first),*], [#(#second),*])),
                quote!((&mut out.0.data.0[0], &mut out.1.data.0[0])),
                quote!((#matrix, #matrix)),
            )
        }
        (Form::Lanes, Shape::Vector(len)) => {
            let len = Literal::usize_unsuffixed(len);
            (
                quote!([#(#pattern),*]),
                quote!(&mut out),
                quote!([L::splat(#fill); #len]),
            )
        }
        (Form::Lanes, Shape::Matrix(rows, cols)) => {
            let (r, c) = (Literal::usize_unsuffixed(rows), Literal::usize_unsuffixed(cols));
            (
                nested(rows),
                quote!(&mut out),
                quote!([[L::splat(#fill); #r]; #c]),
            )
        }
        _ => unreachable!("only vectors, matrices and vector pairs are written in place"),
    };
    quote! {
        let mut out: #ret = #zero;
        {
            let #slots_pattern = #target;
            #(#immediate)*
            #(#statements)*
        }
        out
    }
}

/// A `Pose` from 12 atoms: the rotation column-major, then the translation.
fn pose_value(atoms: &[TokenStream]) -> TokenStream {
    let (r, p) = atoms.split_at(9);
    let columns = r.chunks(3).map(|c| quote!([#(#c),*]));
    quote!(Pose {
        rotation: Matrix3::from_array_storage(ArrayStorage([#(#columns),*])),
        translation: Vector3::new(#(#p),*),
    })
}
