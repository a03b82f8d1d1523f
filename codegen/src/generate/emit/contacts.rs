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
    let to = contacts.iter().map(|c| match c.to {
        Some(to) => {
            let name = model.frames()[to].name.as_str();
            quote!(Some(#name))
        }
        None => quote!(None),
    });
    let frames_trait = &traits.frames;
    // `match contact` over each contact's frame (`None`: no frame, the identity); past the
    // last, the last's.
    let pose = |frames: &[Option<usize>]| {
        let (last, others) = frames.split_last().expect("a robot with contacts");
        let arms = others.iter().enumerate().filter_map(|(k, f)| {
            let (k, variant) = (Literal::usize_unsuffixed(k), &variants[(*f)?]);
            Some(quote!(#k => <Self as #frames_trait>::frame_pose(Frame::#variant, t),))
        });
        let last = match last {
            Some(f) => {
                let variant = &variants[*f];
                quote!(<Self as #frames_trait>::frame_pose(Frame::#variant, t))
            }
            None => quote!(Pose::identity()),
        };
        match frames.iter().any(Option::is_some) {
            true => quote! {
                match contact {
                    #(#arms)*
                    _ => #last,
                }
            },
            false => quote! {
                let _ = (t, contact);
                Pose::identity()
            },
        }
    };
    let held: Vec<Option<usize>> = contacts.iter().map(|c| Some(c.frame)).collect();
    let held_to: Vec<Option<usize>> = contacts.iter().map(|c| c.to).collect();
    let (contact_pose, contact_to_pose) = (pose(&held), pose(&held_to));
    let (trig, forward_dynamics) = (&traits.trig, &traits.forward_dynamics);
    quote! {
        impl ContactDynamics<#nv, #nc> for #ty {
            type Trig = #trig;
            const CONTACT_FRAMES: &'static [&'static str] = &[#(#names),*];
            const CONTACT_KINDS: &'static [ContactKind] = &[#(#kinds),*];
            const CONTACT_REFERENCES: &'static [ReferenceFrame] = &[#(#references),*];
            const CONTACT_TO: &'static [Option<&'static str>] = &[#(#to),*];

            #(#methods)*

            #[inline]
            fn free_acceleration(t: &#trig, v: &SVector<f64, #nv>, tau: &SVector<f64, #nv>) -> SVector<f64, #nv> {
                <Self as #forward_dynamics>::forward_dynamics(t, v, tau)
            }

            #[inline]
            fn contact_pose(t: &#trig, contact: usize) -> Pose {
                #contact_pose
            }

            #[inline]
            fn contact_to_pose(t: &#trig, contact: usize) -> Pose {
                #contact_to_pose
            }
        }
    }
}
