//! How a generated function's body is wrapped: a scalar one as a `Kernel` run through one of
//! the runtime's dispatches (chosen by [`KernelKind`]), a lane one as a `LaneKernel` on the
//! caller's lane type.

use super::lane_width::LaneWidth;
use super::plan::Form;
use super::signature::Param;
use proc_macro2::{Ident, TokenStream};
use quote::{format_ident, quote};

/// A generated function. A scalar one runs its body as a `dyngen_runtime::__private::Kernel`
/// through `dyngen_runtime::__private::dispatch`: with the processor's fused multiply-adds even in
/// a build that does not target them (the body names its multiply-adds `arith.mul_add`), and
/// through `dyngen_runtime::__private::dispatch_eight` where it carries lane vectors (`lanes`: a
/// default build then runs it compiled for AVX-512 where the processor has it), and through
/// `dyngen_runtime::__private::dispatch_many` where it is scalar but holds far more values than
/// sixteen registers (`many_registers`, see `Sizes::many_values`: compiled for AVX-512, for the 32
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
