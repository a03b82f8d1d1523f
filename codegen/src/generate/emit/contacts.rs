//! The group `contacts`: the `ContactDynamics` implementation of a robot with contacts. Its
//! three traced functions (`J`, the drift, `M⁻¹ Jᵀ`) come emitted; this file adds the
//! contacts' description as constants and the two methods that call functions the robot
//! already has (forward dynamics, and its frames' poses).

use crate::frame_names::frame_identifiers;
use crate::model::Model;
use dyngen_runtime::{ContactKind, ReferenceFrame};
use proc_macro2::{Ident, Literal, TokenStream};
use quote::{format_ident, quote};

/// How the robot's other traits are named in the implementation: fixed or floating base.
pub(super) struct ContactTraits {
    /// `JointTrig<N>` or `FloatingTrig<N>`.
    pub(super) trig: TokenStream,
    /// The trait whose `forward_dynamics` it calls.
    pub(super) forward_dynamics: TokenStream,
    /// The trait whose `frame_pose` it calls.
    pub(super) frames: TokenStream,
}

/// `impl ContactDynamics<NV, NC> for ty`, with the emitted `methods`.
pub(super) fn contact_implementation(
    model: &Model,
    ty: &Ident,
    traits: &ContactTraits,
    methods: impl Iterator<Item = TokenStream>,
) -> TokenStream {
    let contacts = model.contacts();
    let [nv, nc] = [model.nv(), model.contact_rows()].map(Literal::usize_unsuffixed);
    let variants: Vec<Ident> = frame_identifiers(model.frames().iter().map(|f| f.name.as_str()))
        .into_iter()
        .map(|id| format_ident!("{}", id.variant))
        .collect();
    let names = contacts.iter().map(|c| model.frames()[c.frame].name.as_str());
    let kinds = contacts.iter().map(|c| match c.kind {
        ContactKind::Point => quote!(ContactKind::Point),
        ContactKind::Frame => quote!(ContactKind::Frame),
    });
    let references = contacts.iter().map(|c| match c.reference {
        ReferenceFrame::Local => quote!(ReferenceFrame::Local),
        ReferenceFrame::World => quote!(ReferenceFrame::World),
        ReferenceFrame::LocalWorldAligned => quote!(ReferenceFrame::LocalWorldAligned),
    });
    let (last, arms) = contacts.split_last().expect("a robot with contacts");
    let arms = arms.iter().enumerate().map(|(k, c)| {
        let (k, variant) = (Literal::usize_unsuffixed(k), &variants[c.frame]);
        quote!(#k => Frame::#variant,)
    });
    let last = &variants[last.frame];
    let ContactTraits {
        trig,
        forward_dynamics,
        frames,
    } = traits;
    quote! {
        impl ContactDynamics<#nv, #nc> for #ty {
            type Trig = #trig;
            const CONTACT_FRAMES: &'static [&'static str] = &[#(#names),*];
            const CONTACT_KINDS: &'static [ContactKind] = &[#(#kinds),*];
            const CONTACT_REFERENCES: &'static [ReferenceFrame] = &[#(#references),*];

            #(#methods)*

            #[inline]
            fn free_acceleration(t: &#trig, v: &SVector<f64, #nv>, tau: &SVector<f64, #nv>) -> SVector<f64, #nv> {
                <Self as #forward_dynamics>::forward_dynamics(t, v, tau)
            }

            #[inline]
            fn contact_pose(t: &#trig, contact: usize) -> Pose {
                let frame = match contact {
                    #(#arms)*
                    _ => Frame::#last,
                };
                <Self as #frames>::frame_pose(frame, t)
            }
        }
    }
}
