//! The `_into` form of a function (`torque_regressor_into(&t, &qd, &qdd, &mut y)`): the same
//! body, writing into a `dyngen_runtime::ResultBuffer` the caller keeps between calls. A buffer
//! that already holds the function's structural zeros (the entries it never writes) is not
//! filled again, and a function in chunks writes its result where the caller keeps it instead
//! of in a local it then copies out.
//!
//! A function in chunks gets it for the cost of a few lines: both methods call the same chunks.
//! A function in one piece gets a second copy of its statements ([`one_piece_into`]).

use super::kernel::{kernel_call, lane_methods, KernelKind};
use super::outputs::{is_structural_zero, writes_in_place};
use super::plan::Form;
use super::signature::Param;
use crate::generate::hash::fnv1a64;
use crate::generate::quantities::Shape;
use crate::generate::trace::Quantity;
use crate::symbolic::Graph;
use proc_macro2::{Ident, TokenStream};
use quote::{format_ident, quote};

/// Whether `q`, emitted in `form`, gets an `_into` method besides its by-value one.
pub(super) fn has_into_form(q: &Quantity, form: Form) -> bool {
    form == Form::Scalar && q.kind.has_into_form() && writes_in_place(q, form)
}

/// The id of `q`'s pattern of structural zeros, which a `ResultBuffer` records: two functions
/// (of any robots) with the same id leave the same entries zero, so one's buffer needs no fill
/// for the other. A hash of the shape and of which entries are zero; never `0` or `u64::MAX`,
/// which the buffer keeps for "all zero" and "written by value".
pub(super) fn zero_pattern(q: &Quantity, g: &Graph) -> u64 {
    let shape = match q.shape {
        // Square pairs keep the spelling they had before pairs had two sizes, and so their ids.
        Shape::MatrixPair(rows, cols) if rows == cols => format!("MatrixPair({rows})"),
        shape => format!("{shape:?}"),
    };
    let zeros: Vec<u8> = q
        .outputs
        .iter()
        .map(|&id| u8::from(is_structural_zero(g, id)))
        .collect();
    fnv1a64(&[shape.as_bytes(), &zeros]).clamp(1, u64::MAX - 1)
}

/// `name_into`.
fn into_name(name: &Ident) -> Ident {
    format_ident!("{name}_into")
}

/// The `_into` method, of parameters `outer` (`name: Type`) and the buffer: `out` claimed for
/// `pattern`, then `body`, which writes into it (a kernel of the function's statements, or its
/// chunks).
pub(super) fn into_method(
    name: &Ident,
    outer: &[TokenStream],
    ret: &TokenStream,
    pattern: u64,
    body: TokenStream,
) -> TokenStream {
    let into = into_name(name);
    quote! {
        #[inline(never)]
        fn #into(#(#outer,)* out: &mut dyngen_runtime::ResultBuffer<#ret>) {
            let out = dyngen_runtime::__private::claim(out, #pattern);
            #body
        }
    }
}

/// The `_into` method of a function in one piece: a kernel of its own running `body` (the
/// prelude and the statements the by-value method runs, writing into `out`) on the buffer.
///
/// The same statements again, not a function both methods call: the by-value method then lost
/// its result's placement in the caller's return slot (Solo-12's regressor ran slower, its
/// result held in registers and spills to the end and copied out). The copy costs compile time
/// (the arms' modules grow by a quarter to a half) and nothing at run time; without it an
/// `_into` would be the by-value function and a copy, slower than by value (`BENCHMARKS.md`).
pub(super) fn one_piece_into(
    name: &Ident,
    params: &[Param],
    ret: &TokenStream,
    pattern: u64,
    kernel: KernelKind,
    body: TokenStream,
) -> TokenStream {
    let outer: Vec<TokenStream> = params.iter().map(Param::passed_on).collect();
    let mut with_out = params.to_vec();
    with_out.push(Param::used(format_ident!("out"), quote!(&mut #ret)));
    let lane_methods = lane_methods(kernel.lanes);
    let call = kernel_call(
        &with_out,
        &TokenStream::new(),
        kernel,
        quote!(#lane_methods #body),
    );
    into_method(name, &outer, ret, pattern, call)
}
