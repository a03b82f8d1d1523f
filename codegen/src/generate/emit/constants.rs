//! The module's constant items and the small functions written from numbers: literals, joint
//! limits, parameter kinds, and `θ_b = Φ θ`.

use crate::base_parameters::BaseParameterSet;
use crate::model::Model;
use proc_macro2::{Literal, TokenStream};
use quote::{format_ident, quote};

pub(super) fn literal(x: f64) -> TokenStream {
    let lit = Literal::f64_suffixed(x.abs());
    if x.is_sign_negative() {
        quote!(-#lit)
    } else {
        quote!(#lit)
    }
}

/// `fn base_parameters(theta) -> θ_b`: one sum per base parameter, with the cleaned folding
/// coefficients written out (only the non-zero ones; `±1` as a plain sum or difference).
pub(super) fn base_parameters_function(base: &BaseParameterSet) -> TokenStream {
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

/// A limit as a literal; an unset (infinite) one as `f64::INFINITY`.
fn limit(x: f64) -> TokenStream {
    match (x.is_finite(), x < 0.0) {
        (true, _) => literal(x),
        (false, false) => quote!(f64::INFINITY),
        (false, true) => quote!(f64::NEG_INFINITY),
    }
}

/// Limits of the joints that are coordinates (a mimic joint's range follows its master's).
/// The names of the joints in `q`: the coordinates (the joints that mimic nothing).
pub(super) fn joint_names(model: &Model) -> Vec<&str> {
    (model.coordinate_joints().into_iter())
        .map(|k| model.joints()[k].name.as_str())
        .collect()
}

pub(super) fn joint_limits(model: &Model) -> Vec<TokenStream> {
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

pub(super) fn parameter_kinds(model: &Model) -> Vec<TokenStream> {
    model
        .parameter_kinds()
        .iter()
        .map(|k| {
            let k = format_ident!("{k:?}");
            quote!(ParameterKind::#k)
        })
        .collect()
}
