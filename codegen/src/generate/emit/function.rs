//! One quantity as a generated function: its result type, its body (written in place or built
//! at the end), the kernel and dispatch around it, and its chunks when it is large.

use super::chunks::{chunked, Header};
use super::into_form::{has_into_form, is_structural_zero, one_piece_into, zero_pattern};
use super::lane_width::LaneWidth;
use super::leaves::Leaves;
use super::plan::{Form, Plan};
use super::signature::{signature, Param};
use crate::generate::quantities::QuantityKind;
use crate::generate::trace::{Quantity, Shape, SymbolicRobot};
use crate::symbolic::{Id, OpCounts};
use proc_macro2::{Ident, Literal, TokenStream};
use quote::{format_ident, quote};
use std::collections::HashMap;

/// A generated function. A scalar one runs its body as a `dyngen_runtime::__private::Kernel`
/// through `dyngen_runtime::__private::dispatch`: with the processor's fused multiply-adds even in
/// a build that does not target them (the body names its multiply-adds `arith.mul_add`), and
/// through `dyngen_runtime::__private::dispatch_eight` where it carries lane vectors (`lanes`: a
/// default build then runs it compiled for AVX-512 where the processor has it), and through
/// `dyngen_runtime::__private::dispatch_many` where it is scalar but holds far more values than
/// sixteen registers (`many_registers`, see [`MANY_VALUES`]: compiled for AVX-512, for the 32
/// registers of a native build, on processors where that does not slow scalar code). A lane
/// function (several states per call) is generic over the caller's lane type `C` and runs its
/// body as a `dyngen_runtime::__private::LaneKernel`, computing in the vector type `L` that
/// `dyngen_runtime::__private::dispatch_lanes` chooses for that width.
pub(super) fn function_item(
    form: Form,
    attributes: TokenStream,
    name: &Ident,
    params: &[Param],
    ret: &TokenStream,
    kernel: KernelKind,
    body: TokenStream,
) -> TokenStream {
    // A chunk returns nothing (it writes through its arguments): `()` without `-> ()`.
    let arrow = match ret.is_empty() {
        true => quote!(),
        false => quote!(-> #ret),
    };
    if form == Form::Lanes {
        return lane_kernel_item(attributes, name, params, ret, lane_body(params, body));
    }
    let outer = params.iter().map(Param::passed_on);
    let lane_methods = lane_methods(kernel.lanes);
    let body = quote!(#lane_methods #body);
    let call = kernel_call(params, ret, kernel, body);
    quote! {
        #attributes
        fn #name(#(#outer),*) #arrow {
            #call
        }
    }
}

/// A lane function, or a chunk of one: its body as a `dyngen_runtime::__private::LaneKernel`
/// computing in `L` (the vectors `dyngen_runtime::__private::dispatch_lanes` chooses) on the
/// caller's lanes of type `C` (`ret` and the parameters' types are written in `L` and renamed).
/// A chunk (`ret` empty) returns nothing: it writes through its arguments.
pub(super) fn lane_kernel_item(
    attributes: TokenStream,
    name: &Ident,
    params: &[Param],
    ret: &TokenStream,
    body: TokenStream,
) -> TokenStream {
    let ret = in_caller_type(Form::Lanes, ret);
    let types: Vec<TokenStream> = params
        .iter()
        .map(|p| in_caller_type(Form::Lanes, &p.ty))
        .collect();
    let names = params.iter().map(|p| &p.name);
    let outer = params.iter().zip(&types).map(|(p, ty)| {
        let name = &p.name;
        quote!(#name: #ty)
    });
    let bindings = params.iter().map(Param::binding);
    let (arrow, output) = match ret.is_empty() {
        true => (quote!(), quote!(())),
        false => (quote!(-> #ret), ret.clone()),
    };
    quote! {
        #attributes
        fn #name<C: Lanes>(#(#outer),*) #arrow {
            struct Body;
            impl<C: Lanes> dyngen_runtime::__private::LaneKernel<C, (#(#types,)*)> for Body {
                type Output = #output;
                #[inline(always)]
                fn run<M: dyngen_runtime::__private::MulAdd, L: dyngen_runtime::__private::LaneVector<M>>(
                    arith: M,
                    (#(#bindings,)*): (#(#types,)*),
                ) #arrow {
                    #body
                }
            }
            dyngen_runtime::__private::dispatch_lanes::<Body, C, _>((#(#names,)*))
        }
    }
}

/// `ty` as the caller sees it: a lane function's with the lane type `L` (what its statements
/// compute in) renamed `C` (the caller's lane type, which its parameters and result are in).
pub(super) fn in_caller_type(form: Form, ty: &TokenStream) -> TokenStream {
    use proc_macro2::{Group, TokenTree};
    if form == Form::Scalar {
        return ty.clone();
    }
    ty.clone()
        .into_iter()
        .map(|tree| match tree {
            TokenTree::Ident(i) if i == "L" => TokenTree::Ident(Ident::new("C", i.span())),
            TokenTree::Group(g) => {
                let mut renamed = Group::new(g.delimiter(), in_caller_type(form, &g.stream()));
                renamed.set_span(g.span());
                TokenTree::Group(renamed)
            }
            other => other,
        })
        .collect()
}

/// Whether `ty` names the identifier `name`.
fn names(ty: &TokenStream, name: &str) -> bool {
    ty.clone().into_iter().any(|tree| match tree {
        proc_macro2::TokenTree::Ident(i) => i == name,
        proc_macro2::TokenTree::Group(g) => names(&g.stream(), name),
        _ => false,
    })
}

/// The body of a lane function's kernel: the arguments it reads converted from the caller's
/// lanes into the kernel's vectors, then `body` (which writes its outputs, and a chunk the
/// values it hands on, back in the caller's lane type: `lane_out`).
pub(super) fn lane_body(params: &[Param], body: TokenStream) -> TokenStream {
    // The arguments are the parameters typed in `L` (a chunk's result and arrays are in `C`
    // already, and are read and written value by value).
    let conversions = params.iter().filter(|p| p.used && names(&p.ty, "L")).map(|p| {
        let name = &p.name;
        match names(&p.ty, "JointTrigLanes") {
            true => quote!(let #name = &dyngen_runtime::__private::trig_in::<M, C, L, _>(arith, #name);),
            false => quote!(let #name = &dyngen_runtime::__private::lanes_in::<M, C, L, _>(arith, #name);),
        }
    });
    quote! {
        #(#conversions)*
        #body
    }
}

/// What decides how a scalar function's kernel is written and dispatched.
#[derive(Clone, Copy)]
pub(super) struct KernelKind {
    /// Whether its body calls `arith` (else the strategy is bound as `_arith`).
    pub(super) uses_arith: bool,
    /// The lane width of its lane vectors, if it has any: run through `dispatch_eight`.
    pub(super) lanes: Option<LaneWidth>,
    /// Whether it holds far more values than registers: run through `dispatch_many`.
    pub(super) many_registers: bool,
}

/// The body of a scalar function: its kernel (`struct Body; impl Kernel<…> for Body`, running
/// `body` on the parameters, bound by pattern) and its dispatch on the parameters' values (a
/// body that calls lane methods brings their trait in itself, [`lane_methods`]).
pub(super) fn kernel_call(
    params: &[Param],
    ret: &TokenStream,
    kernel: KernelKind,
    body: TokenStream,
) -> TokenStream {
    let KernelKind {
        uses_arith,
        lanes,
        many_registers,
    } = kernel;
    let (arrow, output) = match ret.is_empty() {
        true => (quote!(), quote!(())),
        false => (quote!(-> #ret), ret.clone()),
    };
    let names = params.iter().map(|p| &p.name);
    let bindings = params.iter().map(Param::binding);
    let types: Vec<&TokenStream> = params.iter().map(|p| &p.ty).collect();
    let arith = match uses_arith {
        true => format_ident!("arith"),
        false => format_ident!("_arith"),
    };
    let dispatch = match (lanes.is_some(), many_registers) {
        (true, _) => quote!(dyngen_runtime::__private::dispatch_eight),
        (false, true) => quote!(dyngen_runtime::__private::dispatch_many),
        (false, false) => quote!(dyngen_runtime::__private::dispatch),
    };
    quote! {
        struct Body;
        impl dyngen_runtime::__private::Kernel<(#(#types,)*)> for Body {
            type Output = #output;
            #[inline(always)]
            fn run<M: dyngen_runtime::__private::MulAdd>(#arith: M, (#(#bindings,)*): (#(#types,)*)) #arrow {
                #body
            }
        }
        #dispatch::<Body, _>((#(#names,)*))
    }
}

/// A kernel with lane vectors calls their multiply-adds as methods of `M::Eight` (`M::Four`).
pub(super) fn lane_methods(lanes: Option<LaneWidth>) -> TokenStream {
    match lanes.map(LaneWidth::vector_trait) {
        Some(t) => quote!(
            use #t as _;
        ),
        None => quote!(),
    }
}

fn doc_counts(c: &OpCounts, lanes: LaneWidth) -> String {
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
        let (ty, count) = match lanes {
            LaneWidth::Four => ("f64x4", "four"),
            LaneWidth::Eight => ("f64x8", "eight"),
        };
        s += &format!(
            ", and {} lane ops ({ty}: each on {count} lanes at once; splats, seeds and lane \
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
    let mut plan = Plan::new(robot, leaves, &q.outputs, form);
    let stage_end = first_stage(robot, q, &plan).map(|stage| plan.put_first(&stage));
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
    let name = format_ident!("{}{suffix}", q.name());
    let mut main_used = Vec::new();
    let atoms: Vec<TokenStream> = q.outputs.iter().map(|&o| plan.atom(o, &mut main_used)).collect();
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
    let whole = plan.order.len() <= robot.chunk_values && stage_end.is_none();
    let mut used = main_used;
    let mut counts = robot.graph.op_counts(&q.outputs);
    // The statements writing the result in place, shared by the by-value and `_into` forms; the
    // lane extractions they store a vector at a time are not computed.
    let writes = (whole && writes_in_place(q, form)).then(|| {
        let (writes, stored_whole) = writes_into_out(&plan, q, form, &atoms, &mut used);
        counts.lanes -= stored_whole;
        writes
    });
    let mut doc = vec![doc_counts(&counts, plan.lanes)];
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
    let many_registers = matches!(q.shape, Shape::MatrixPair(_)) || plan.order.len() > MANY_VALUES;
    if whole {
        let body = match &writes {
            Some(writes) => {
                let zero = zero_result(q, form);
                let out_type = in_caller_type(form, &ret);
                quote! {
                    let mut out: #out_type = #zero;
                    #writes
                    out
                }
            }
            None => {
                let statements = plan.statements(&plan.order, &mut used);
                let result = result_value(q, form, &atoms);
                quote!(#(#statements)* #result)
            }
        };
        let sig = signature(robot, leaves, &q.args, &used, &n, form);
        let (params, prelude) = (sig.params, sig.prelude);
        let kernel = KernelKind {
            uses_arith: plan.uses_arith(&plan.order),
            lanes: plan.uses_lanes(&plan.order).then_some(plan.lanes),
            many_registers,
        };
        let method = function_item(
            form,
            quote!(#(#[doc = #doc])* #[inline(never)]),
            &name,
            &params,
            &ret,
            kernel,
            quote!(#(#prelude)* #body),
        );
        let into = match (has_into_form(q, form), writes) {
            (true, Some(writes)) => one_piece_into(
                &name,
                &params,
                &ret,
                zero_pattern(q, &robot.graph),
                kernel,
                quote!(#(#prelude)* #writes),
            ),
            _ => quote!(),
        };
        return Emitted {
            method: quote!(#method #into),
            chunks: Vec::new(),
        };
    }

    chunked(
        &plan,
        q,
        form,
        Header {
            name: &name,
            generics: &generics,
            ret: &ret,
            doc: &doc,
            n: &n,
            many_registers,
            suffix,
        },
        &atoms,
        used,
        stage_end,
    )
}

/// The values `q` computes in a first stage that is best compiled apart, if it has one: the
/// derivatives of forward dynamics first compute `q̈` (forward dynamics itself, the same nodes
/// as that function's outputs where both take the same form of the joint transforms), and only
/// then the tangents of inverse dynamics at that `q̈` and their solves. Compiled as one
/// function, LLVM interleaves the two, which made `∂q̈/∂x` slower than forward dynamics and
/// `∂τ/∂x` called one after the other. Only where the tangents are lane vectors (scalar
/// tangents run slower split) and the function would otherwise be whole (one already in chunks
/// runs slower with the stage as a chunk of its own); `docs/performance-notes.md`.
fn first_stage(robot: &SymbolicRobot, q: &Quantity, plan: &Plan) -> Option<Vec<Id>> {
    let g = &robot.graph;
    let in_lanes = plan.order.iter().any(|&id| g.node(id).is_lanes());
    let whole = plan.order.len() <= robot.chunk_values;
    if q.kind != QuantityKind::ForwardDynamicsDerivatives || plan.form != Form::Scalar || !in_lanes || !whole
    {
        return None;
    }
    let forward = robot
        .quantities
        .iter()
        .find(|f| f.kind == QuantityKind::ForwardDynamics)?;
    let computed = |id: &Id| plan.names.contains_key(id);
    forward
        .outputs
        .iter()
        .all(computed)
        .then(|| forward.outputs.clone())
}

/// The result built from its outputs `atoms` (a function not written in place).
pub(super) fn result_value(q: &Quantity, form: Form, atoms: &[TokenStream]) -> TokenStream {
    match (form, q.shape) {
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
            Shape::Pose => pose_value(atoms),
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
    }
}

/// Results larger than this, up to [`UNROLLED_FILL_BYTES`], start from
/// `dyngen_runtime::__private::fill_zero()` rather than a constant zero, whose fill the compiler
/// would make a call to `memset` (see that function). Smaller ones keep the constant: the
/// compiler fills them with at most sixteen inline stores (AVX2), or drops the fill when every
/// entry is written.
const LIBRARY_FILL_BYTES: usize = 512;

/// Results larger than this start from a constant zero again, filled by one `memset` into the
/// result itself. The compiler unrolls `fill_zero`'s fill into the result only up to about
/// 5 KiB; a larger one it fills in a temporary and copies into the result, three passes over
/// the memory where the library call makes one (`docs/performance-notes.md`).
const UNROLLED_FILL_BYTES: usize = 4096;

/// Functions that compute more values than this, and the derivatives of the dynamics, run through
/// `dyngen_runtime::__private::dispatch_eight` (lane kernels) or `dispatch_many` (scalar ones):
/// their values outnumber sixteen registers many times over, and in a default build those give
/// them the 32 of AVX-512 where the processor has it, as a native build does: fewer spills, so
/// close to native speed on AMD processors; on Intel's, scalar kernels run faster in the AVX2
/// function, which `dispatch_many` picks there. Small kernels stay in the AVX2 function: they
/// have no spills to save, and the 512-bit instructions LLVM forms in them slow them down
/// (`docs/performance-notes.md`).
const MANY_VALUES: usize = 1000;

/// Bytes of `q`'s result: `f64`s, or lane vectors of at least four.
fn result_bytes(q: &Quantity, form: Form) -> usize {
    q.outputs.len() * if form == Form::Lanes { 32 } else { 8 }
}

/// `{ let [[o0, _, o2]] = &mut out…; x0 = …; *o0 = x0; … }`: every value computed and every
/// output that is not a structural zero written into `out` (a local result or a `&mut` to one),
/// which the block leaves as it found the structural zeros. Each output is stored as soon as it
/// is computed: returning the outputs at the end kept every one alive across the whole function
/// (the regressor's peak of live values was 260 instead of 103), so the register allocator
/// spilled them and reloaded them to store them. Also returns how many lane extractions the
/// block leaves out because it stores their vector whole.
pub(super) fn writes_into_out(
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

/// Whether a function's result is written in place, each output stored as soon as it is
/// computed: vectors and matrices (and pairs of them), not poses and kinematics.
pub(super) fn writes_in_place(q: &Quantity, form: Form) -> bool {
    matches!(
        (form, q.shape),
        (_, Shape::Vector(_) | Shape::Matrix(..))
            | (Form::Scalar, Shape::VectorPair(..) | Shape::MatrixPair(_))
    )
}

/// Where outputs go in a result written in place: per output its slot (`o17`, bound as a
/// `&mut` to the entry) or `_` (a zero, left as filled); which computed value each slot
/// receives; and the writes of outputs that are inputs or constants (`*o0 = a0;`). Only the
/// outputs `here` accepts get slots (a chunk writes the ones it computes).
pub(super) struct OutputSlots {
    pub(super) pattern: Vec<TokenStream>,
    pub(super) slots: HashMap<Id, Vec<Ident>>,
    pub(super) immediate: Vec<TokenStream>,
}

impl OutputSlots {
    pub(super) fn new(
        plan: &Plan,
        q: &Quantity,
        atoms: &[TokenStream],
        here: impl Fn(Id) -> bool,
    ) -> OutputSlots {
        let g = &plan.robot.graph;
        let mut slots: HashMap<Id, Vec<Ident>> = HashMap::new();
        let mut immediate = Vec::new();
        let pattern = q
            .outputs
            .iter()
            .zip(atoms)
            .enumerate()
            .map(|(k, (&id, atom))| {
                let slot = format_ident!("o{k}");
                if is_structural_zero(g, id) || !here(id) {
                    return quote!(_);
                }
                match plan.names.contains_key(&id) {
                    true => slots.entry(id).or_default().push(slot.clone()),
                    false => immediate.push(match plan.form {
                        Form::Scalar => quote!(*#slot = #atom;),
                        Form::Lanes => quote!(*#slot = dyngen_runtime::__private::lane_out(arith, #atom);),
                    }),
                }
                quote!(#slot)
            })
            .collect();
        OutputSlots {
            pattern,
            slots,
            immediate,
        }
    }

    /// Whether any output has a slot.
    pub(super) fn any(&self) -> bool {
        !self.slots.is_empty() || !self.immediate.is_empty()
    }
}

/// The pattern binding the result's entries, nested as the result's storage is.
pub(super) fn slots_pattern(q: &Quantity, form: Form, pattern: &[TokenStream]) -> TokenStream {
    let nested = |entries: &[TokenStream], rows: usize| {
        // An entry stored with its column's vector ([`OutputSlots::store_four_lanes_whole`]) is
        // bound by the rest pattern before it, and left empty here.
        let columns = (entries.chunks(rows))
            .map(|c| c.iter().filter(|e| !e.is_empty()))
            .map(|c| quote!([#(#c),*]));
        quote!([#(#columns),*])
    };
    match (form, q.shape) {
        (Form::Scalar, Shape::Vector(rows) | Shape::Matrix(rows, _))
        | (Form::Lanes, Shape::Matrix(rows, _)) => nested(pattern, rows),
        (Form::Lanes, Shape::Vector(_)) => quote!([#(#pattern),*]),
        (Form::Scalar, Shape::VectorPair(n, _)) => {
            let (first, second) = pattern.split_at(n);
            quote!(([#(#first),*], [#(#second),*]))
        }
        (Form::Scalar, Shape::MatrixPair(rows)) => {
            let (first, second) = pattern.split_at(rows * rows);
            let (first, second) = (nested(first, rows), nested(second, rows));
            quote!((#first, #second))
        }
        _ => unreachable!("only vectors, matrices and their pairs are written in place"),
    }
}

/// The mutable place [`slots_pattern`] binds, of the result `out` (a local, or a `&mut` to the
/// result when `by_reference`).
pub(super) fn slots_target(q: &Quantity, form: Form, out: TokenStream, by_reference: bool) -> TokenStream {
    match (form, q.shape) {
        (Form::Scalar, Shape::Vector(_) | Shape::Matrix(..)) => quote!(&mut #out.data.0),
        (Form::Scalar, Shape::VectorPair(..)) => quote!((&mut #out.0.data.0[0], &mut #out.1.data.0[0])),
        (Form::Scalar, Shape::MatrixPair(_)) => quote!((&mut #out.0.data.0, &mut #out.1.data.0)),
        (Form::Lanes, Shape::Vector(_) | Shape::Matrix(..)) => match by_reference {
            true => out,
            false => quote!(&mut #out),
        },
        _ => unreachable!("only vectors, matrices and their pairs are written in place"),
    }
}

/// The zero a result written in place starts from; a lane result's in the caller's lane type
/// (`C`, in the lane kernel).
pub(super) fn zero_result(q: &Quantity, form: Form) -> TokenStream {
    let bytes = result_bytes(q, form);
    let (matrix, fill) = match bytes > LIBRARY_FILL_BYTES && bytes <= UNROLLED_FILL_BYTES {
        true => (
            quote!(SMatrix::from_element(dyngen_runtime::__private::fill_zero())),
            quote!(dyngen_runtime::__private::fill_zero()),
        ),
        false => (quote!(SMatrix::zeros()), quote!(0.0)),
    };
    match (form, q.shape) {
        (Form::Scalar, Shape::Vector(_) | Shape::Matrix(..)) => matrix,
        (Form::Scalar, Shape::VectorPair(..) | Shape::MatrixPair(_)) => quote!((#matrix, #matrix)),
        (Form::Lanes, shape) => {
            let splat = quote!(C::splat(#fill));
            match shape {
                Shape::Vector(len) => {
                    let len = Literal::usize_unsuffixed(len);
                    quote!([#splat; #len])
                }
                Shape::Matrix(rows, cols) => {
                    let (r, c) = (Literal::usize_unsuffixed(rows), Literal::usize_unsuffixed(cols));
                    quote!([[#splat; #r]; #c])
                }
                _ => unreachable!("only vectors and matrices have a lane form"),
            }
        }
        _ => unreachable!("only vectors, matrices and their pairs are written in place"),
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
