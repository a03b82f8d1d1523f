//! Rust source from a traced robot: one flat, single-assignment function per quantity.
//!
//! Each function declares all its temporaries once (`let [x0, x1, …]: [f64; K];`), then assigns
//! every live node in creation order, `xK = a op b;`, with atoms (literals, inputs, earlier
//! temporaries) as operands: never nested expressions, which overflow rustc's parser on large
//! robots, and never one `let` per node, which nests debug-info scopes as deep as the function
//! is long (see `Plan::statements`). Functions of more than [`CHUNK`] values are split into
//! `<name>_partK` chunk functions that hand on the values later chunks read. Inputs are
//! destructured once at the top of a function; outputs are built with `from_array_storage`, so
//! the generated code has no indexing, no allocation and no panic path.

use super::trace::{Arg, Quantity, Shape, SymbolicRobot, BASE_FUNCTIONS};
use crate::base_parameters::BaseParameterSet;
use crate::model::Model;
use crate::symbolic::{Id, Node, OpCounts, LANES};
use proc_macro2::{Ident, Literal, TokenStream};
use quote::{format_ident, quote};
use std::collections::{BTreeSet, HashMap};

/// What the header of a generated file records.
#[derive(Clone, Debug)]
pub struct Provenance {
    /// The description as the user named it, e.g. `robots/arm7.yaml`.
    pub source: String,
    /// Content hash of every file the description read.
    pub source_hash: String,
    /// The command that regenerates the file.
    pub regenerate: String,
    /// Name of the generated robot type, e.g. `Arm7`.
    pub type_name: String,
}

/// Name of the generated robot type, e.g. `arm7` → `Arm7`, `ur5_robot` → `Ur5Robot`.
pub fn type_name(robot: &str) -> String {
    let mut out = String::new();
    for part in robot
        .split(|c: char| !c.is_ascii_alphanumeric())
        .filter(|p| !p.is_empty())
    {
        let mut chars = part.chars();
        if let Some(first) = chars.next() {
            out.push(first.to_ascii_uppercase());
            out.extend(chars);
        }
    }
    if out.is_empty() || out.starts_with(|c: char| c.is_ascii_digit()) {
        out.insert_str(0, "Robot");
    }
    out
}

/// How inputs of the graph are spelled in a function body.
struct Leaves {
    names: HashMap<Id, Ident>,
    /// Ids of `sin(q_i)` and `cos(q_i)` in joint order, found once (every chunk's signature
    /// needs them, and a scan per chunk made large robots' emission quadratic).
    sin_ids: Vec<Id>,
    cos_ids: Vec<Id>,
}

impl Leaves {
    fn new(robot: &SymbolicRobot) -> Leaves {
        let g = &robot.graph;
        let mut names = HashMap::new();
        let inputs = &robot.inputs;
        for (prefix, ids) in [
            ("q", &inputs.q),
            ("qd", &inputs.qd),
            ("v", &inputs.v),
            ("a", &inputs.a),
            ("tau", &inputs.tau),
            ("theta", &inputs.theta),
            ("r", &inputs.r),
        ] {
            for (i, id) in ids.iter().enumerate() {
                names.insert(*id, format_ident!("{prefix}{i}"));
            }
        }
        // sin and cos of a joint angle come precomputed in `JointTrig`.
        for i in 0..g.len() {
            let id = Id(i as u32);
            match g.node(id) {
                Node::Sin(a) | Node::Cos(a) if inputs.q.contains(&a) => {
                    let k = inputs.q.iter().position(|x| *x == a).unwrap_or(0);
                    let prefix = if matches!(g.node(id), Node::Sin(_)) {
                        "s"
                    } else {
                        "c"
                    };
                    names.insert(id, format_ident!("{prefix}{k}"));
                }
                _ => {}
            }
        }
        Leaves {
            names,
            sin_ids: trig_ids(robot, true),
            cos_ids: trig_ids(robot, false),
        }
    }
}

/// Attributes for the `mod` item that holds a generated file: the lints flattened numeric code
/// trips by design (long literals, long functions, names like `x12`/`x13`), and no rustfmt
/// (the file is already formatted, by prettyplease, and must stay byte-identical).
pub const MODULE_ATTRIBUTES: &str = "#[rustfmt::skip]\n#[allow(clippy::approx_constant, clippy::excessive_precision, clippy::unreadable_literal, clippy::too_many_lines, clippy::many_single_char_names, clippy::similar_names, clippy::neg_multiply)]";

fn literal(x: f64) -> TokenStream {
    let lit = Literal::f64_suffixed(x.abs());
    if x.is_sign_negative() {
        quote!(-#lit)
    } else {
        quote!(#lit)
    }
}

/// Values per chunk function. Larger functions run faster (nothing is copied between chunks:
/// the Panda's `C` and `Y` run 15–18% faster whole than in chunks of 1024, and every function of
/// a 7-DOF arm but the derivatives of the dynamics fits in one chunk), while chunks bound the
/// size of what LLVM optimises at once, whose cost grows faster than linearly, for very large
/// robots. (The Panda's derivatives, about 7,000 values, ran no faster whole, in chunks of 16384.)
/// Chunks do not shrink what a call runs: the Panda's `∂q̈/∂x`, 39 KB of machine code, is over a
/// 32 KiB level-1 instruction cache either way, and splitting it made the total larger and the
/// call 15% slower (`BENCHMARKS.md`).
const CHUNK: usize = 4096;

/// Whether a function computes one state in `f64`, or one state per SIMD lane of a generic
/// `L: Lanes` (the same statements; constants splatted, the few non-arithmetic nodes mapped
/// lane by lane).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Form {
    Scalar,
    Lanes,
}

impl Form {
    /// The type of every value.
    fn value_type(self) -> TokenStream {
        match self {
            Form::Scalar => quote!(f64),
            Form::Lanes => quote!(L),
        }
    }
}

/// The type of lane-vector values (the tangents of eight directions at once): the kernel's own
/// (`dyngen_runtime::__private::MulAdd::Eight`), so that
/// `dyngen_runtime::__private::dispatch_eight` chooses its registers; vectors are made through
/// `arith` (`arith.eight([..])`, `arith.splat_eight(x)`).
fn lane_type() -> TokenStream {
    quote!(M::Eight)
}

/// `a·b + c` with one rounding: an addition or subtraction whose product operand is used only
/// there. `negate_product` and `negate_addend` give `−a·b + c` and `a·b − c`.
#[derive(Clone, Copy, Debug)]
struct MulAdd {
    a: Id,
    b: Id,
    c: Id,
    negate_product: bool,
    negate_addend: bool,
}

/// The nodes a function computes, in order, and how their names are spelled.
struct Plan<'a> {
    robot: &'a SymbolicRobot,
    leaves: &'a Leaves,
    form: Form,
    /// Additions and subtractions emitted as one multiply-add (their products are not emitted).
    fused: HashMap<Id, MulAdd>,
    /// Live computed nodes in topological order.
    order: Vec<Id>,
    names: HashMap<Id, Ident>,
}

impl<'a> Plan<'a> {
    fn new(robot: &'a SymbolicRobot, leaves: &'a Leaves, outputs: &[Id], form: Form) -> Plan<'a> {
        let g = &robot.graph;
        let live = g.live(outputs);
        let topological: Vec<Id> = (0..g.len())
            .map(|i| Id(i as u32))
            .filter(|&id| live[id.0 as usize] && !leaves.names.contains_key(&id))
            .filter(|&id| !matches!(g.node(id), Node::Const(_) | Node::Input(_) | Node::LaneZero))
            .collect();
        assert!(
            form == Form::Scalar || topological.iter().all(|&id| !g.node(id).is_lanes()),
            "lane-vector nodes in a function generic over its lane type"
        );
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
        }
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
    fn statements(&self, ids: &[Id], used_leaves: &mut Vec<Id>) -> Vec<TokenStream> {
        self.statements_writing(ids, used_leaves, &HashMap::new())
    }

    /// [`Plan::statements`], each value followed by its writes to the output slots `slots`
    /// (`*o3 = x17;`): an output stored as soon as it is computed is not held in a register, or
    /// spilled and reloaded, until the function returns.
    fn statements_writing(
        &self,
        ids: &[Id],
        used_leaves: &mut Vec<Id>,
        slots: &HashMap<Id, Vec<Ident>>,
    ) -> Vec<TokenStream> {
        let g = &self.robot.graph;
        let ty = self.form.value_type();
        let writes = |id: Id| {
            let name = &self.names[&id];
            let slots = slots.get(&id).map(Vec::as_slice).unwrap_or_default();
            quote!(#(*#slots = #name;)*)
        };
        let mut out = Vec::with_capacity(ids.len() + 2);
        // Lane vectors (`f64x8`) get a declaration of their own.
        let (lanes, scalars): (Vec<Id>, Vec<Id>) = ids.iter().partition(|&&id| g.node(id).is_lanes());
        if scalars.len() == 1 && lanes.is_empty() && !matches!(g.node(ids[0]), Node::Extract(..)) {
            let name = &self.names[&ids[0]];
            let value = self.value(ids[0], used_leaves);
            out.push(quote!(let #name: #ty = #value;));
            out.push(writes(ids[0]));
            return out;
        }
        for (sort, ty) in [(&scalars, ty), (&lanes, lane_type())] {
            if !sort.is_empty() {
                let names = sort.iter().map(|id| &self.names[id]);
                let k = Literal::usize_unsuffixed(sort.len());
                out.push(quote!(let [#(#names),*]: [#ty; #k];));
            }
        }
        for &id in ids {
            let name = &self.names[&id];
            if let Node::Extract(v, k) = g.node(id) {
                // A lane of a vector, by destructuring (no indexing).
                let v = self.atom(v, used_leaves);
                let pattern = (0..LANES).map(|j| match j == k as usize {
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
    fn uses_arith(&self, ids: &[Id]) -> bool {
        ids.iter()
            .any(|id| self.fused.contains_key(id) && !self.robot.graph.node(*id).is_lanes())
            || self.uses_lanes(ids)
    }

    /// Whether any of `ids` is a lane vector: the function then makes its vectors through
    /// `arith` and runs through `dyngen_runtime::__private::dispatch_eight`.
    fn uses_lanes(&self, ids: &[Id]) -> bool {
        ids.iter().any(|id| self.robot.graph.node(*id).is_lanes())
    }

    /// `id` as an operand, negated if `negate`: a constant as its negated literal (never `--x`).
    fn maybe_negated(&self, id: Id, negate: bool, used_leaves: &mut Vec<Id>) -> TokenStream {
        match (negate, self.robot.graph.constant_value(id)) {
            (false, _) => self.atom(id, used_leaves),
            (true, Some(x)) => {
                let x = literal(-x);
                match self.form {
                    Form::Scalar => x,
                    Form::Lanes => quote!(L::splat(#x)),
                }
            }
            (true, None) => {
                let a = self.atom(id, used_leaves);
                quote!(-#a)
            }
        }
    }

    /// What `id`'s statement reads: a fused multiply-add reads its product's factors.
    fn operands(&self, id: Id) -> Vec<Id> {
        match self.fused.get(&id) {
            Some(f) => vec![f.a, f.b, f.c],
            None => self.robot.graph.operands(id),
        }
    }

    /// An operand: a literal, an input, or an earlier temporary. Records inputs it reads.
    fn atom(&self, id: Id, used_leaves: &mut Vec<Id>) -> TokenStream {
        if self.robot.graph.node(id) == Node::LaneZero {
            return quote!(arith.splat_eight(0.0));
        }
        if let Some(x) = self.robot.graph.constant_value(id) {
            let x = literal(x);
            return match self.form {
                Form::Scalar => x,
                Form::Lanes => quote!(L::splat(#x)),
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
    fn value(&self, id: Id, used_leaves: &mut Vec<Id>) -> TokenStream {
        if let Some(f) = self
            .fused
            .get(&id)
            .filter(|_| self.robot.graph.node(id).is_lanes())
        {
            // `c ± a·b` on lane vectors: the lane types' multiply-adds, which negate for free.
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
        let mut atom = |x| self.atom(x, used_leaves);
        if let Some(f) = self.fused.get(&id) {
            let b = atom(f.b);
            let (a, c) = (
                self.maybe_negated(f.a, f.negate_product, used_leaves),
                self.maybe_negated(f.c, f.negate_addend, used_leaves),
            );
            return match self.form {
                Form::Scalar => quote!(arith.mul_add(#a, #b, #c)),
                // `(-x).mul_add(..)`: a method call binds tighter than the minus.
                Form::Lanes => match f.negate_product && self.robot.graph.constant_value(f.a).is_none() {
                    true => quote!((#a).mul_add(#b, #c)),
                    false => quote!(#a.mul_add(#b, #c)),
                },
            };
        }
        if self.form == Form::Lanes {
            // The non-arithmetic nodes, lane by lane, as the scalar code computes them.
            let lane_function = match self.robot.graph.node(id) {
                Node::Sin(a) => Some((a, quote!(dyngen_runtime::__private::libm::sin))),
                Node::Cos(a) => Some((a, quote!(dyngen_runtime::__private::libm::cos))),
                Node::Tanh(a) => Some((a, quote!(dyngen_runtime::__private::libm::tanh))),
                Node::Sign(a) => Some((a, quote!(dyngen_runtime::__private::sign))),
                _ => None,
            };
            if let Some((a, f)) = lane_function {
                let a = atom(a);
                return quote!(#a.map(#f));
            }
        }
        let value = match self.robot.graph.node(id) {
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
                quote!(arith.splat_eight(#a))
            }
            Node::LaneUnit(k, a) => {
                let a = atom(a);
                let lanes = (0..LANES).map(|j| match j == k as usize {
                    true => a.clone(),
                    false => quote!(0.0),
                });
                quote!(arith.eight([#(#lanes),*]))
            }
            Node::Const(_) | Node::Input(_) | Node::LaneZero => unreachable!("leaves are not statements"),
            Node::Extract(..) => unreachable!("lane extractions are destructuring statements"),
        };
        value
    }
}

/// The parameters of a generated function and the destructuring of the inputs it reads.
struct Signature {
    params: Vec<Param>,
    prelude: Vec<TokenStream>,
}

/// One parameter of a generated function; an unused one is spelled `_name` where it is bound.
struct Param {
    name: Ident,
    ty: TokenStream,
    used: bool,
}

impl Param {
    fn used(name: Ident, ty: TokenStream) -> Param {
        Param { name, ty, used: true }
    }

    fn binding(&self) -> Ident {
        match self.used {
            true => self.name.clone(),
            false => format_ident!("_{}", self.name),
        }
    }

    /// `name: Type` as the function declares it.
    fn declared(&self) -> TokenStream {
        let (name, ty) = (self.binding(), &self.ty);
        quote!(#name: #ty)
    }
}

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

/// `let [x0, _, x2] = <source>;` for the inputs in `used`; `None` if it reads none of them.
fn destructure(leaves: &Leaves, ids: &[Id], used: &[Id], source: TokenStream) -> Option<TokenStream> {
    if !ids.iter().any(|id| used.contains(id)) {
        return None;
    }
    let pattern = ids.iter().map(|id| match used.contains(id) {
        true => {
            let name = &leaves.names[id];
            quote!(#name)
        }
        false => quote!(_),
    });
    Some(quote!(let [#(#pattern),*] = #source;))
}

/// The type of the joint sines and cosines, and of a joint-space vector argument.
fn argument_types(form: Form, n: &Literal) -> (TokenStream, TokenStream) {
    match form {
        Form::Scalar => (quote!(JointTrig<#n>), quote!(SVector<f64, #n>)),
        Form::Lanes => (quote!(JointTrigLanes<#n, L>), quote!([L; #n])),
    }
}

fn signature(
    robot: &SymbolicRobot,
    leaves: &Leaves,
    args: &[Arg],
    used: &[Id],
    n: &Literal,
    form: Form,
) -> Signature {
    let (trig_type, vector_type) = argument_types(form, n);
    let inputs = &robot.inputs;
    let (sin_ids, cos_ids) = (&leaves.sin_ids, &leaves.cos_ids);
    let mut prelude = Vec::new();
    prelude.extend(destructure(leaves, &inputs.q, used, quote!(t.q)));
    prelude.extend(destructure(leaves, sin_ids, used, quote!(t.sin)));
    prelude.extend(destructure(leaves, cos_ids, used, quote!(t.cos)));
    let mut params = vec![Param {
        name: format_ident!("t"),
        ty: quote!(&#trig_type),
        used: !prelude.is_empty(),
    }];
    for &arg in args {
        let (name, ids) = match arg {
            Arg::Qd => (format_ident!("qd"), &inputs.qd[..]),
            Arg::V => (format_ident!("v"), &inputs.v[..]),
            Arg::A => (format_ident!("a"), &inputs.a[..]),
            Arg::Tau => (format_ident!("tau"), &inputs.tau[..]),
            Arg::Theta(len) => (format_ident!("theta"), &inputs.theta[..len]),
            Arg::R => (format_ident!("r"), &inputs.r[..]),
        };
        let ty = argument_type(arg, &vector_type);
        let source = match form {
            Form::Scalar => quote!(#name.data.0[0]),
            Form::Lanes => quote!(*#name),
        };
        let destructured = destructure(leaves, ids, used, source);
        params.push(Param {
            name,
            ty: quote!(&#ty),
            used: destructured.is_some(),
        });
        prelude.extend(destructured);
    }
    Signature { params, prelude }
}

fn argument_names(args: &[Arg]) -> Vec<Ident> {
    let mut names = vec![format_ident!("t")];
    names.extend(args.iter().map(|a| match a {
        Arg::Qd => format_ident!("qd"),
        Arg::V => format_ident!("v"),
        Arg::A => format_ident!("a"),
        Arg::Tau => format_ident!("tau"),
        Arg::Theta(_) => format_ident!("theta"),
        Arg::R => format_ident!("r"),
    }));
    names
}

/// The type of a vector argument: a joint-space vector, or a parameter vector of its own length.
fn argument_type(arg: Arg, joint_vector: &TokenStream) -> TokenStream {
    match arg {
        Arg::Theta(len) => {
            let len = Literal::usize_unsuffixed(len);
            quote!(SVector<f64, #len>)
        }
        _ => joint_vector.clone(),
    }
}

/// `t: &JointTrig<N>, qd: &SVector<f64, N>, …`: every argument, used or not.
fn all_parameters(args: &[Arg], n: &Literal, form: Form) -> Vec<TokenStream> {
    let (trig_type, vector_type) = argument_types(form, n);
    let names = argument_names(args);
    let (t, vectors) = names.split_first().expect("t is always an argument");
    let mut params = vec![quote!(#t: &#trig_type)];
    params.extend(vectors.iter().zip(args).map(|(v, &arg)| {
        let ty = argument_type(arg, &vector_type);
        quote!(#v: &#ty)
    }));
    params
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
struct Emitted {
    method: TokenStream,
    chunks: Vec<TokenStream>,
}

/// Suffix of the lane form of a function's name: `inverse_dynamics_lanes`.
const LANES_SUFFIX: &str = "_lanes";

fn function(robot: &SymbolicRobot, leaves: &Leaves, q: &Quantity, n: usize, form: Form) -> Emitted {
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
    let name = format_ident!("{}{suffix}", q.name);
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
    if BASE_FUNCTIONS.contains(&q.name) {
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
        let chunk_name = format_ident!("{}{suffix}_part{}", q.name, k);
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
    let params = all_parameters(&q.args, &n, form);
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

/// A `Pose` from 12 atoms: the rotation column-major, then the translation.
fn pose_value(atoms: &[TokenStream]) -> TokenStream {
    let (r, p) = atoms.split_at(9);
    let columns = r.chunks(3).map(|c| quote!([#(#c),*]));
    quote!(Pose {
        rotation: Matrix3::from_array_storage(ArrayStorage([#(#columns),*])),
        translation: Vector3::new(#(#p),*),
    })
}

/// Ids of `sin(q_i)` (or `cos(q_i)`) in joint order; a fresh id where the graph has none.
fn trig_ids(robot: &SymbolicRobot, sin: bool) -> Vec<Id> {
    let g = &robot.graph;
    robot
        .inputs
        .q
        .iter()
        .map(|&q| {
            (0..g.len())
                .map(|i| Id(i as u32))
                .find(|&id| match g.node(id) {
                    Node::Sin(a) if sin => a == q,
                    Node::Cos(a) if !sin => a == q,
                    _ => false,
                })
                .unwrap_or(Id(u32::MAX))
        })
        .collect()
}

/// `fn base_parameters(theta) -> θ_b`: one sum per base parameter, with the cleaned folding
/// coefficients written out (only the non-zero ones; `±1` as a plain sum or difference).
fn base_parameters_function(base: &BaseParameterSet) -> TokenStream {
    let p = Literal::usize_unsuffixed(base.standard_count);
    let b = Literal::usize_unsuffixed(base.count());
    let used: Vec<bool> = (0..base.standard_count)
        .map(|i| base.terms.iter().flatten().any(|&(k, _)| k == i))
        .collect();
    let pattern = used.iter().enumerate().map(|(i, &u)| {
        if u {
            let name = format_ident!("p{i}");
            quote!(#name)
        } else {
            quote!(_)
        }
    });
    let (mut mul, mut add) = (0, 0);
    let sums: Vec<TokenStream> = base
        .terms
        .iter()
        .map(|terms| {
            let mut sum = TokenStream::new();
            for (k, &(i, c)) in terms.iter().enumerate() {
                let name = format_ident!("p{i}");
                let sign = match (k, c < 0.0) {
                    (0, false) => quote!(),
                    (0, true) => quote!(-),
                    (_, false) => quote!(+),
                    (_, true) => quote!(-),
                };
                add += usize::from(k > 0);
                if c.abs() == 1.0 {
                    sum.extend(quote!(#sign #name));
                } else {
                    mul += 1;
                    let lit = Literal::f64_suffixed(c.abs());
                    sum.extend(quote!(#sign #lit * #name));
                }
            }
            sum
        })
        .collect();
    let doc = format!(
        " `θ_b = Φ θ`: each base parameter is a standard parameter plus the ones folded into it \
         (names in `BASE_PARAMETER_NAMES`). Operations: {mul} mul, {add} add/sub."
    );
    quote! {
        #[doc = #doc]
        fn base_parameters(theta: &SVector<f64, #p>) -> SVector<f64, #b> {
            let [#(#pattern),*] = theta.data.0[0];
            SVector::from_array_storage(ArrayStorage([[#(#sums),*]]))
        }
    }
}

/// The functions that also have a lane form (several states per call, in
/// [`LaneDynamics`](dyngen_runtime::LaneDynamics)): what identification and batched roll-outs
/// evaluate in bulk.
const LANE_FUNCTIONS: [&str; 2] = ["inverse_dynamics", super::trace::BASE_TORQUE_REGRESSOR];

/// The generated functions that belong to [`Kinematics`](dyngen_runtime::Kinematics) (the rest
/// are [`RobotDynamics`](dyngen_runtime::RobotDynamics), and `Y_b` is
/// [`BaseParameters`](dyngen_runtime::BaseParameters)).
const KINEMATICS: [&str; 4] = ["forward_kinematics", "jacobian", "jacobian_dot", "kinematics"];

/// A limit as a literal; an unset (infinite) one as `f64::INFINITY`.
fn limit(x: f64) -> TokenStream {
    match (x.is_finite(), x < 0.0) {
        (true, _) => literal(x),
        (false, false) => quote!(f64::INFINITY),
        (false, true) => quote!(f64::NEG_INFINITY),
    }
}

/// Limits of the joints that are coordinates (a mimic joint's range follows its master's).
fn joint_limits(model: &Model) -> Vec<TokenStream> {
    model
        .coordinate_joints()
        .into_iter()
        .map(|k| &model.joints()[k])
        .map(|j| {
            let l = j.limits.map_or(
                [f64::NEG_INFINITY, f64::INFINITY, f64::INFINITY, f64::INFINITY],
                |l| [l.lower, l.upper, l.velocity, l.effort],
            );
            let [lower, upper, velocity, effort] = l.map(limit);
            quote!(JointLimits { lower: #lower, upper: #upper, velocity: #velocity, effort: #effort })
        })
        .collect()
}

fn parameter_kinds(model: &Model) -> Vec<TokenStream> {
    model
        .parameter_kinds()
        .iter()
        .map(|k| {
            let k = format_ident!("{k:?}");
            quote!(ParameterKind::#k)
        })
        .collect()
}

/// The complete generated module for `model`, formatted. The module declaration that
/// includes it carries the lint allows of [`MODULE_ATTRIBUTES`].
pub fn emit(model: &Model, robot: &SymbolicRobot, provenance: &Provenance) -> String {
    let n = model.dof();
    let p = model.parameter_count();
    let leaves = Leaves::new(robot);
    let ty = format_ident!("{}", provenance.type_name);
    let name = &model.name();
    let coordinates = model.coordinate_joints();
    let joint_names = coordinates.iter().map(|&k| model.joints()[k].name.as_str());
    let joint_limits = joint_limits(model);
    let end_effector_body = Literal::usize_unsuffixed(model.end_effector().parent);
    let param_names = model.parameter_names();
    let param_kinds = parameter_kinds(model);
    let theta = model.parameters().into_iter().map(literal);
    let emitted: Vec<(&str, Emitted)> = robot
        .quantities
        .iter()
        .map(|q| (q.name, function(robot, &leaves, q, n, Form::Scalar)))
        .collect();
    let lane_functions: Vec<Emitted> = robot
        .quantities
        .iter()
        .filter(|q| LANE_FUNCTIONS.contains(&q.name))
        .map(|q| function(robot, &leaves, q, n, Form::Lanes))
        .collect();
    let lane_methods = lane_functions.iter().map(|e| &e.method);
    let methods = |keep: fn(&str) -> bool| {
        emitted
            .iter()
            .filter(move |(name, _)| keep(name))
            .map(|(_, e)| &e.method)
    };
    let kinematics = methods(|name| KINEMATICS.contains(&name));
    let functions = methods(|name| !BASE_FUNCTIONS.contains(&name) && !KINEMATICS.contains(&name));
    let base_functions = methods(|name| BASE_FUNCTIONS.contains(&name));
    let chunks = emitted
        .iter()
        .map(|(_, e)| e)
        .chain(&lane_functions)
        .flat_map(|e| &e.chunks);
    let base = &robot.base;
    let base_names = base.names.iter().map(String::as_str);
    let base_parameters = base_parameters_function(base);
    let b = Literal::usize_unsuffixed(base.count());
    let count_doc = format!(
        " Number of base parameters of `{name}` (the `B` of [`BaseParameters`]): {} of {p}.",
        base.count()
    );
    // A robot without joint-level parameters keeps its header word for word.
    let parameters = match model.joint_terms().per_joint() {
        0 => format!("{p} inertial parameters"),
        k => {
            let kinds: Vec<&str> = model.joint_terms().kinds.iter().map(|k| k.keyword()).collect();
            format!(
                "{p} parameters: {} inertial, {} joint-level ({})",
                model.inertial_parameter_count(),
                k * n,
                kinds.join(", ")
            )
        }
    };
    // Mimic joints have bodies but no coordinate: say how many the robot has besides its `n`.
    let joints = match model.joints().len() - n {
        0 => format!("{n} joints"),
        m => format!("{n} joints and {m} mimic joints"),
    };
    let (n, p) = (Literal::usize_unsuffixed(n), Literal::usize_unsuffixed(p));
    let header = format!(
        "// Rigid-body dynamics of `{name}` ({joints}, {parameters}, {b} base parameters).\n\
         // Generated by dyngen {} from `{}` (fnv1a64 {}).\n\
         // Do not edit by hand: regenerate with `{}`.\n\n",
        env!("CARGO_PKG_VERSION"),
        provenance.source,
        provenance.source_hash,
        provenance.regenerate
    );
    let type_doc = format!(
        " `{name}`: implements [`Kinematics`], [`RobotDynamics`] and [`BaseParameters`] with flattened, allocation-free code."
    );
    // The generator's version: the runtime accepts it only if it is its own (`__private`, which
    // generated code calls, changes in any release).
    let generated_by = env!("CARGO_PKG_VERSION");
    let tokens = quote! {
        dyngen_runtime::__require_version!(#generated_by);

        use dyngen_runtime::nalgebra::{ArrayStorage, Matrix3, SMatrix, SVector, Vector3};
        use dyngen_runtime::{
            BaseParameters, JointLimits, JointTrig, JointTrigLanes, Kinematics, LaneDynamics, Lanes, ParameterKind,
            Pose, RobotDynamics,
        };

        /// Number of moving joints (the `N` of [`Kinematics`] and [`RobotDynamics`]).
        pub const DOF: usize = #n;
        /// Number of standard parameters, ten per body (the `P` of [`RobotDynamics`]).
        pub const PARAMETER_COUNT: usize = #p;
        #[doc = #count_doc]
        pub const BASE_PARAMETER_COUNT: usize = #b;
        /// Joint names, in the order of `q`.
        pub const JOINT_NAMES: [&str; DOF] = [#(#joint_names),*];
        /// Joint limits from the description (infinite where it sets none).
        pub const JOINT_LIMITS: [JointLimits; DOF] = [#(#joint_limits),*];
        /// Names of the standard parameters θ, e.g. `"mcx[link3]"`.
        pub const PARAMETER_NAMES: [&str; PARAMETER_COUNT] = [#(#param_names),*];
        /// The kind of each standard parameter.
        pub const PARAMETER_KINDS: [ParameterKind; PARAMETER_COUNT] = [#(#param_kinds),*];
        /// What each base parameter combines.
        pub const BASE_PARAMETER_NAMES: [&str; BASE_PARAMETER_COUNT] = [#(#base_names),*];

        /// The standard parameters, for generic code (`HybridController<Standard, DOF, PARAMETER_COUNT>`).
        pub type Standard = dyngen_runtime::Standard<#ty>;
        /// The base parameters, for generic code (`HybridController<Base, DOF, BASE_PARAMETER_COUNT>`).
        pub type Base = dyngen_runtime::Base<#ty, PARAMETER_COUNT>;
        /// Joint sines and cosines, the first argument of every function.
        pub type Trig = JointTrig<DOF>;
        /// A joint-space vector: `q`, `q̇`, `q̈`, `τ`.
        pub type JointVector = SVector<f64, DOF>;
        /// The 6 × DOF end-effector Jacobian.
        pub type Jacobian = SMatrix<f64, 6, DOF>;
        /// A DOF × DOF joint-space matrix: `D`, `C`.
        pub type JointMatrix = SMatrix<f64, DOF, DOF>;
        /// The standard parameters θ.
        pub type Parameters = SVector<f64, PARAMETER_COUNT>;
        /// The base parameters θ_b.
        pub type BaseParameterVector = SVector<f64, BASE_PARAMETER_COUNT>;
        /// The regressor `Y`.
        pub type Regressor = SMatrix<f64, DOF, PARAMETER_COUNT>;
        /// The base regressor `Y_b`.
        pub type BaseRegressor = SMatrix<f64, DOF, BASE_PARAMETER_COUNT>;

        #[doc = #type_doc]
        #[derive(Clone, Copy, Debug, Default)]
        pub struct #ty;

        impl Kinematics<#n> for #ty {
            const NAME: &'static str = #name;
            const JOINT_NAMES: [&'static str; #n] = JOINT_NAMES;
            const JOINT_LIMITS: [JointLimits; #n] = JOINT_LIMITS;
            const END_EFFECTOR_BODY: usize = #end_effector_body;

            #(#kinematics)*
        }

        impl RobotDynamics<#n, #p> for #ty {
            const PARAMETER_NAMES: [&'static str; #p] = PARAMETER_NAMES;
            const PARAMETER_KINDS: [ParameterKind; #p] = PARAMETER_KINDS;

            fn parameters() -> SVector<f64, #p> {
                SVector::from_array_storage(ArrayStorage([[#(#theta),*]]))
            }

            #(#functions)*
        }

        impl BaseParameters<#n, #p, #b> for #ty {
            const BASE_PARAMETER_NAMES: [&'static str; #b] = BASE_PARAMETER_NAMES;

            #base_parameters

            #(#base_functions)*
        }

        impl LaneDynamics<#n, #b> for #ty {
            #(#lane_methods)*
        }

        #(#chunks)*
    };
    match syn::parse2::<syn::File>(tokens) {
        Ok(file) => header + &prettyplease::unparse(&file),
        // Only a bug in this emitter can get here; show the tokens so it can be found.
        Err(e) => panic!("dyngen emitted invalid Rust ({e}); this is a bug in dyngen"),
    }
}
