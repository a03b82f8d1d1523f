//! Rust source from a traced robot: one flat, single-assignment function per quantity.
//!
//! Every live node becomes `let xK: f64 = a op b;` with atoms as operands (never nested
//! expressions, which overflow rustc's parser on large robots). Inputs are destructured once at
//! the top of a function; outputs are built with `from_array_storage`, so the generated code has
//! no indexing, no allocation and no panic path.

use super::trace::{Arg, Quantity, Shape, SymbolicRobot};
use crate::model::Model;
use crate::symbolic::{Id, Node, OpCounts};
use proc_macro2::{Ident, Literal, TokenStream};
use quote::{format_ident, quote};
use std::collections::HashMap;

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
    for part in robot.split(|c: char| !c.is_ascii_alphanumeric()).filter(|p| !p.is_empty()) {
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
}

impl Leaves {
    fn new(robot: &SymbolicRobot) -> Leaves {
        let g = &robot.graph;
        let mut names = HashMap::new();
        let inputs = &robot.inputs;
        for (prefix, ids) in [("q", &inputs.q), ("qd", &inputs.qd), ("v", &inputs.v), ("a", &inputs.a)] {
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
                    let prefix = if matches!(g.node(id), Node::Sin(_)) { "s" } else { "c" };
                    names.insert(id, format_ident!("{prefix}{k}"));
                }
                _ => {}
            }
        }
        Leaves { names }
    }
}

/// Lints that flattened numeric code trips by design (long literals, long functions, names
/// like `v12`/`v13`), to put on the `mod` item that holds a generated file.
pub const MODULE_ALLOWS: &str = "#[allow(clippy::approx_constant, clippy::excessive_precision, clippy::unreadable_literal, clippy::too_many_lines, clippy::many_single_char_names, clippy::similar_names, clippy::neg_multiply)]";

fn literal(x: f64) -> TokenStream {
    let lit = Literal::f64_suffixed(x.abs());
    if x.is_sign_negative() {
        quote!(-#lit)
    } else {
        quote!(#lit)
    }
}

/// The body of one generated function.
struct Body<'a> {
    robot: &'a SymbolicRobot,
    leaves: &'a Leaves,
    local: HashMap<Id, Ident>,
    used_leaves: Vec<Id>,
}

impl<'a> Body<'a> {
    fn atom(&mut self, id: Id) -> TokenStream {
        if let Some(x) = self.robot.graph.constant_value(id) {
            return literal(x);
        }
        if let Some(name) = self.leaves.names.get(&id) {
            if !self.used_leaves.contains(&id) {
                self.used_leaves.push(id);
            }
            return quote!(#name);
        }
        let name = &self.local[&id];
        quote!(#name)
    }

    fn statements(&mut self, outputs: &[Id]) -> Vec<TokenStream> {
        let g = &self.robot.graph;
        let live = g.live(outputs);
        let mut out = Vec::new();
        for (i, &is_live) in live.iter().enumerate() {
            let id = Id(i as u32);
            if !is_live || self.leaves.names.contains_key(&id) {
                continue;
            }
            let value = match g.node(id) {
                Node::Const(_) | Node::Input(_) => continue,
                Node::Sin(a) => {
                    let a = self.atom(a);
                    quote!(#a.sin())
                }
                Node::Cos(a) => {
                    let a = self.atom(a);
                    quote!(#a.cos())
                }
                Node::Neg(a) => {
                    let a = self.atom(a);
                    quote!(-#a)
                }
                Node::Add(a, b) => {
                    let (a, b) = (self.atom(a), self.atom(b));
                    quote!(#a + #b)
                }
                Node::Sub(a, b) => {
                    let (a, b) = (self.atom(a), self.atom(b));
                    quote!(#a - #b)
                }
                Node::Mul(a, b) => {
                    let (a, b) = (self.atom(a), self.atom(b));
                    quote!(#a * #b)
                }
                Node::Div(a, b) => {
                    let (a, b) = (self.atom(a), self.atom(b));
                    quote!(#a / #b)
                }
            };
            // `x` is a prefix no input uses (q, qd, v, a, s, c), so a temporary never shadows one.
            let name = format_ident!("x{}", self.local.len());
            out.push(quote!(let #name: f64 = #value;));
            self.local.insert(id, name);
        }
        out
    }

    /// `let [x0, _, x2] = <source>;` for the inputs this body reads.
    fn destructure(&self, ids: &[Id], source: TokenStream) -> Option<TokenStream> {
        if !ids.iter().any(|id| self.used_leaves.contains(id)) {
            return None;
        }
        let pattern = ids.iter().map(|id| match self.used_leaves.contains(id) {
            true => {
                let name = &self.leaves.names[id];
                quote!(#name)
            }
            false => quote!(_),
        });
        Some(quote!(let [#(#pattern),*] = #source;))
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
    s + " (joint sines and cosines come precomputed in `JointTrig`)."
}

fn arg_tokens(arg: Arg) -> (Ident, &'static str) {
    match arg {
        Arg::Qd => (format_ident!("qd"), "qd"),
        Arg::V => (format_ident!("v"), "v"),
        Arg::A => (format_ident!("a"), "a"),
    }
}

fn function(robot: &SymbolicRobot, leaves: &Leaves, q: &Quantity, n: usize) -> TokenStream {
    let n = Literal::usize_unsuffixed(n);
    let mut body = Body { robot, leaves, local: HashMap::new(), used_leaves: Vec::new() };
    let statements = body.statements(&q.outputs);
    let atoms: Vec<TokenStream> = q.outputs.iter().map(|&o| body.atom(o)).collect();
    let result = match q.shape {
        Shape::Vector(_) => quote!(SVector::from_array_storage(ArrayStorage([[#(#atoms),*]]))),
        Shape::Matrix(rows, _) => {
            let columns = atoms.chunks(rows).map(|c| quote!([#(#c),*]));
            quote!(SMatrix::from_array_storage(ArrayStorage([#(#columns),*])))
        }
        Shape::Pose => {
            let (r, p) = atoms.split_at(9);
            let columns = r.chunks(3).map(|c| quote!([#(#c),*]));
            quote!(Pose {
                rotation: Matrix3::from_array_storage(ArrayStorage([#(#columns),*])),
                translation: Vector3::new(#(#p),*),
            })
        }
    };
    let inputs = &robot.inputs;
    let mut prelude: Vec<TokenStream> = Vec::new();
    let sin_ids: Vec<Id> = trig_ids(robot, true);
    let cos_ids: Vec<Id> = trig_ids(robot, false);
    let t_used = [&inputs.q, &sin_ids, &cos_ids].iter().any(|ids| ids.iter().any(|id| body.used_leaves.contains(id)));
    prelude.extend(body.destructure(&inputs.q, quote!(t.q)));
    prelude.extend(body.destructure(&sin_ids, quote!(t.sin)));
    prelude.extend(body.destructure(&cos_ids, quote!(t.cos)));
    let mut params = vec![if t_used { quote!(t: &JointTrig<#n>) } else { quote!(_t: &JointTrig<#n>) }];
    for &arg in &q.args {
        let (name, _) = arg_tokens(arg);
        let ids = match arg {
            Arg::Qd => &inputs.qd,
            Arg::V => &inputs.v,
            Arg::A => &inputs.a,
        };
        match body.destructure(ids, quote!(#name.data.0[0])) {
            Some(d) => {
                prelude.push(d);
                params.push(quote!(#name: &SVector<f64, #n>));
            }
            None => {
                let unused = format_ident!("_{}", name);
                params.push(quote!(#unused: &SVector<f64, #n>));
            }
        }
    }
    let ret = match q.shape {
        Shape::Vector(len) => {
            let len = Literal::usize_unsuffixed(len);
            quote!(SVector<f64, #len>)
        }
        Shape::Matrix(r, c) => {
            let (r, c) = (Literal::usize_unsuffixed(r), Literal::usize_unsuffixed(c));
            quote!(SMatrix<f64, #r, #c>)
        }
        Shape::Pose => quote!(Pose),
    };
    let name = format_ident!("{}", q.name);
    let doc = doc_counts(&robot.graph.op_counts(&q.outputs));
    quote! {
        #[doc = #doc]
        #[inline(never)]
        fn #name(#(#params),*) -> #ret {
            #(#prelude)*
            #(#statements)*
            #result
        }
    }
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

/// The complete generated module for `model`, formatted. The module declaration that
/// includes it carries the lint allows of [`MODULE_ALLOWS`].
pub fn emit(model: &Model, robot: &SymbolicRobot, provenance: &Provenance) -> String {
    let n = model.dof();
    let p = crate::model::PARAMS_PER_BODY * n;
    let leaves = Leaves::new(robot);
    let ty = format_ident!("{}", provenance.type_name);
    let name = &model.name;
    let joint_names = model.joints.iter().map(|j| j.name.as_str());
    let param_names = model.parameter_names();
    let theta = model.parameters().into_iter().map(literal);
    let functions: Vec<TokenStream> = robot.quantities.iter().map(|q| function(robot, &leaves, q, n)).collect();
    let (n, p) = (Literal::usize_unsuffixed(n), Literal::usize_unsuffixed(p));
    let header = format!(
        "// Rigid-body dynamics of `{name}` ({n} joints, {p} inertial parameters).\n\
         // Generated by dyngen {} from `{}` (fnv1a64 {}).\n\
         // Do not edit by hand: regenerate with `{}`.\n\n",
        env!("CARGO_PKG_VERSION"),
        provenance.source,
        provenance.source_hash,
        provenance.regenerate
    );
    let type_doc = format!(" `{name}`: implements [`RobotDynamics`] with flattened, allocation-free code.");
    let tokens = quote! {
        use dyngen_runtime::nalgebra::{ArrayStorage, Matrix3, SMatrix, SVector, Vector3};
        use dyngen_runtime::{JointTrig, Pose, RobotDynamics};

        #[doc = #type_doc]
        #[derive(Clone, Copy, Debug, Default)]
        pub struct #ty;

        impl RobotDynamics<#n, #p> for #ty {
            const NAME: &'static str = #name;
            const JOINT_NAMES: [&'static str; #n] = [#(#joint_names),*];
            const PARAMETER_NAMES: [&'static str; #p] = [#(#param_names),*];

            fn parameters() -> SVector<f64, #p> {
                SVector::from_array_storage(ArrayStorage([[#(#theta),*]]))
            }

            #(#functions)*
        }
    };
    match syn::parse2::<syn::File>(tokens) {
        Ok(file) => header + &prettyplease::unparse(&file),
        // Only a bug in this emitter can get here; show the tokens so it can be found.
        Err(e) => panic!("dyngen emitted invalid Rust ({e}); this is a bug in dyngen"),
    }
}
