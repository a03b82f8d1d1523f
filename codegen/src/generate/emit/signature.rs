//! The parameters of a generated function and the destructuring of the inputs it reads.

use super::leaves::Leaves;
use super::plan::Form;
use crate::generate::quantities::Arg;
use crate::generate::trace::SymbolicRobot;
use crate::symbolic::Id;
use proc_macro2::{Ident, Literal, TokenStream};
use quote::{format_ident, quote};

/// The parameters of a generated function and the destructuring of the inputs it reads.
pub(super) struct Signature {
    pub(super) params: Vec<Param>,
    pub(super) prelude: Vec<TokenStream>,
}

/// One parameter of a generated function; an unused one is spelled `_name` where it is bound.
#[derive(Clone)]
pub(super) struct Param {
    pub(super) name: Ident,
    pub(super) ty: TokenStream,
    pub(super) used: bool,
}

impl Param {
    pub(super) fn used(name: Ident, ty: TokenStream) -> Param {
        Param { name, ty, used: true }
    }

    pub(super) fn binding(&self) -> Ident {
        match self.used {
            true => self.name.clone(),
            false => format_ident!("_{}", self.name),
        }
    }

    /// `name: Type` where a function only passes it on (its kernel binds it).
    pub(super) fn passed_on(&self) -> TokenStream {
        let (name, ty) = (&self.name, &self.ty);
        quote!(#name: #ty)
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

/// The type of the joint sines and cosines (with a floating base's pose: `FloatingTrig` of
/// that many joints), and of a velocity-space vector argument (`n` entries).
fn argument_types(form: Form, n: &Literal, floating_joints: Option<usize>) -> (TokenStream, TokenStream) {
    match (form, floating_joints) {
        (Form::Scalar, Some(joints)) => {
            let joints = Literal::usize_unsuffixed(joints);
            (quote!(FloatingTrig<#joints>), quote!(SVector<f64, #n>))
        }
        (Form::Scalar, None) => (quote!(JointTrig<#n>), quote!(SVector<f64, #n>)),
        (Form::Lanes, _) => (quote!(JointTrigLanes<#n, L>), quote!([L; #n])),
    }
}

pub(super) fn signature(
    robot: &SymbolicRobot,
    leaves: &Leaves,
    args: &[Arg],
    used: &[Id],
    n: &Literal,
    form: Form,
) -> Signature {
    let (trig_type, vector_type) = argument_types(form, n, leaves.floating_joints);
    let inputs = &robot.inputs;
    let (sin_ids, cos_ids) = (&leaves.sin_ids, &leaves.cos_ids);
    let joints = match leaves.floating_joints {
        Some(_) => quote!(t.joints),
        None => quote!(t),
    };
    let mut prelude = Vec::new();
    prelude.extend(destructure(leaves, &inputs.q, used, quote!(#joints.q)));
    prelude.extend(destructure(leaves, sin_ids, used, quote!(#joints.sin)));
    prelude.extend(destructure(leaves, cos_ids, used, quote!(#joints.cos)));
    prelude.extend(destructure(
        leaves,
        &inputs.base_position,
        used,
        quote!(t.base.position.data.0[0]),
    ));
    prelude.extend(destructure_rotation(leaves, &inputs.base_rotation, used));
    let mut params = vec![Param {
        name: format_ident!("t"),
        ty: quote!(&#trig_type),
        used: !prelude.is_empty(),
    }];
    for &arg in args {
        if let Arg::Coefficient(c) = arg {
            // An `f64` of its own, spelled in the body as its parameter is named.
            let input = robot.contact_inputs.coefficient(c);
            params.push(Param {
                name: format_ident!("{}", c.name()),
                ty: quote!(f64),
                used: input.is_some_and(|id| used.contains(&id)),
            });
            continue;
        }
        let (name, ids) = match arg {
            Arg::Qd => (format_ident!("qd"), &inputs.qd[..]),
            Arg::V => (format_ident!("v"), &inputs.v[..]),
            Arg::A => (format_ident!("a"), &inputs.a[..]),
            Arg::Tau => (format_ident!("tau"), &inputs.tau[..]),
            Arg::Theta(len) => (format_ident!("theta"), &inputs.theta[..len]),
            Arg::R => (format_ident!("r"), &inputs.r[..]),
            Arg::Forces(len) => (format_ident!("lambda"), &robot.contact_inputs.forces[..len]),
            Arg::Target(len) => (format_ident!("target"), &robot.contact_inputs.target[..len]),
            Arg::Coefficient(_) => unreachable!("taken above"),
        };
        let ty = argument_type(arg, &vector_type);
        let source = match form {
            Form::Scalar => quote!(#name.data.0[0]),
            Form::Lanes => quote!(*#name),
        };
        let destructured = destructure(leaves, ids, used, source);
        params.push(Param {
            name,
            ty,
            used: destructured.is_some(),
        });
        prelude.extend(destructured);
    }
    Signature { params, prelude }
}

/// `let [[rot00, rot10, rot20], …] = t.base.rotation.data.0;` (nalgebra stores columns) for
/// the base rotation entries in `used`.
fn destructure_rotation(leaves: &Leaves, row_major: &[Id], used: &[Id]) -> Option<TokenStream> {
    if !row_major.iter().any(|id| used.contains(id)) {
        return None;
    }
    let columns = (0..3).map(|c| {
        let entries = (0..3).map(|r| {
            let id = &row_major[3 * r + c];
            match used.contains(id) {
                true => {
                    let name = &leaves.names[id];
                    quote!(#name)
                }
                false => quote!(_),
            }
        });
        quote!([#(#entries),*])
    });
    Some(quote!(let [#(#columns),*] = t.base.rotation.data.0;))
}

pub(super) fn argument_names(args: &[Arg]) -> Vec<Ident> {
    let mut names = vec![format_ident!("t")];
    names.extend(args.iter().map(|a| match a {
        Arg::Qd => format_ident!("qd"),
        Arg::V => format_ident!("v"),
        Arg::A => format_ident!("a"),
        Arg::Tau => format_ident!("tau"),
        Arg::Theta(_) => format_ident!("theta"),
        Arg::R => format_ident!("r"),
        Arg::Forces(_) => format_ident!("lambda"),
        Arg::Target(_) => format_ident!("target"),
        Arg::Coefficient(c) => format_ident!("{}", c.name()),
    }));
    names
}

/// The type of an argument: a reference to a joint-space vector or to a vector of its own
/// length, or a coefficient's `f64`.
fn argument_type(arg: Arg, joint_vector: &TokenStream) -> TokenStream {
    match arg {
        Arg::Theta(len) | Arg::Forces(len) | Arg::Target(len) => {
            let len = Literal::usize_unsuffixed(len);
            quote!(&SVector<f64, #len>)
        }
        Arg::Coefficient(_) => quote!(f64),
        _ => quote!(&#joint_vector),
    }
}

/// `t: &JointTrig<N>, qd: &SVector<f64, N>, …`: every argument, used or not.
pub(super) fn all_parameters(
    args: &[Arg],
    n: &Literal,
    form: Form,
    floating_joints: Option<usize>,
) -> Vec<TokenStream> {
    let (trig_type, vector_type) = argument_types(form, n, floating_joints);
    let names = argument_names(args);
    let (t, vectors) = names.split_first().expect("t is always an argument");
    let mut params = vec![quote!(#t: &#trig_type)];
    params.extend(vectors.iter().zip(args).map(|(v, &arg)| {
        let ty = argument_type(arg, &vector_type);
        quote!(#v: #ty)
    }));
    params
}
