//! A function written composed (`code_shape: composed`): a method that calls the robot's own
//! smaller generated functions and finishes the work in the runtime
//! (`dyngen_runtime::__private::composed`), over the tree of its coordinates, a constant it
//! declares.

use super::header::Emitted;
use super::outputs::result_type;
use super::plan::Form;
use super::signature::all_parameters;
use crate::dynamics::tree_ldl::velocity_parents;
use crate::generate::quantities::QuantityKind;
use crate::generate::trace::Quantity;
use crate::model::Model;
use proc_macro2::{Literal, TokenStream};
use quote::{format_ident, quote};

/// The method of `q`, a row written composed, for `model` (`nv` velocity coordinates).
pub(super) fn composed(model: &Model, q: &Quantity) -> Emitted {
    let nv = model.nv();
    let n = Literal::usize_unsuffixed(nv);
    let floating_joints = model.floating_base().map(|_| model.dof());
    let params = all_parameters(&q.args, &n, Form::Scalar, floating_joints);
    let ret = result_type(q, Form::Scalar);
    let name = format_ident!("{}", q.kind.name());
    let (doc, body) = match q.kind {
        QuantityKind::ForwardDynamics => forward_dynamics(model, &n),
        QuantityKind::MassMatrixInverse => mass_matrix_inverse(model, &n),
        QuantityKind::ForwardDynamicsDerivatives => forward_dynamics_derivatives(model, &n),
        other => unreachable!("{other:?} has no composed form"),
    };
    let method = quote! {
        #[doc = #doc]
        #[inline(never)]
        fn #name(#(#params),*) -> #ret {
            #body
        }
    };
    Emitted {
        method,
        chunks: Vec::new(),
    }
}

/// `const TREE: Tree<NV> = Tree::new([None, Some(0), …]);`: the velocity coordinates' tree in
/// the factor of `D`, its lists of ancestors and descendants built at compile time.
fn tree(model: &Model, n: &Literal) -> TokenStream {
    let entries = velocity_parents(model).into_iter().map(|p| match p {
        Some(p) => {
            let p = Literal::usize_unsuffixed(p);
            quote!(Some(#p))
        }
        None => quote!(None),
    });
    quote! {
        const TREE: dyngen_runtime::__private::tree_factor::Tree<#n> =
            dyngen_runtime::__private::tree_factor::Tree::new([#(#entries),*]);
    }
}

/// `ν̇ = D⁻¹ (τ − ID(q, ν, 0))`: the doc and the body.
fn forward_dynamics(model: &Model, n: &Literal) -> (String, TokenStream) {
    let doc = " Composed (`code_shape: composed`): `D⁻¹ (τ − ID(q, ν, 0))` from `mass_matrix` and \
               `inverse_dynamics`, solved through the tree factor of `D`."
        .to_owned();
    let tree = tree(model, n);
    let body = quote! {
        #tree
        let bias = Self::inverse_dynamics(t, qd, &SVector::zeros());
        dyngen_runtime::__private::composed::forward_dynamics(&TREE, Self::mass_matrix(t), tau - bias)
    };
    (doc, body)
}

/// `D⁻¹` from `D`: the doc and the body.
fn mass_matrix_inverse(model: &Model, n: &Literal) -> (String, TokenStream) {
    let doc = " Composed (`code_shape: composed`): every column of the identity solved through \
               the tree factor of `mass_matrix`."
        .to_owned();
    let tree = tree(model, n);
    let body = quote! {
        #tree
        dyngen_runtime::__private::composed::mass_matrix_inverse(&TREE, Self::mass_matrix(t))
    };
    (doc, body)
}

/// `∂ν̇/∂x = −D⁻¹ ∂τ/∂x` at `ν̇ = D⁻¹ (τ − ID(q, ν, 0))`, from `D`, inverse dynamics and its
/// derivatives: the doc and the body.
fn forward_dynamics_derivatives(model: &Model, n: &Literal) -> (String, TokenStream) {
    let doc = " Composed (`code_shape: composed`): `∂τ/∂x` of `inverse_dynamics_derivatives` at \
               `ν̇ = D⁻¹ (τ − ID(q, ν, 0))`, solved as `−D⁻¹ ∂τ/∂x` through the tree factor of \
               `mass_matrix`."
        .to_owned();
    let tree = tree(model, n);
    let body = quote! {
        #tree
        let bias = Self::inverse_dynamics(t, qd, &SVector::zeros());
        dyngen_runtime::__private::composed::forward_dynamics_derivatives(
            &TREE,
            Self::mass_matrix(t),
            tau - bias,
            |a| Self::inverse_dynamics_derivatives(t, qd, a),
        )
    };
    (doc, body)
}
