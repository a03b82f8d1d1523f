//! The group `contacts`: the `ContactDynamics` implementation of a robot with contacts. Its
//! traced functions (`J`, the drift, `M⁻¹ Jᵀ`, the derivatives' pieces) come emitted; this
//! file adds the contacts' description as constants and the methods that call functions the
//! robot already has (forward dynamics and `M⁻¹`, its frames' poses and local Jacobians).

use crate::frame_names::frame_identifiers;
use crate::model::Model;
use dyngen_runtime::{ContactKind, ReferenceFrame};
use proc_macro2::{Ident, Literal, TokenStream};
use quote::{format_ident, quote};

/// How the robot's other traits are named in the implementation: fixed or floating base.
pub(super) struct ContactTraits {
    /// `JointTrig<N>` or `FloatingTrig<N>`.
    pub(super) trig: TokenStream,
    /// The trait whose `forward_dynamics` and `mass_matrix_inverse` it calls.
    pub(super) forward_dynamics: TokenStream,
    /// The trait whose `frame_pose` and `frame_jacobian` it calls.
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
    // `match contact` over each contact's frame, `of(frame)` what the frame gives (`None`: no
    // frame, `otherwise`); past the last, the last's.
    let per_contact =
        |frames: &[Option<usize>], of: &dyn Fn(&Ident) -> TokenStream, otherwise: TokenStream| {
            let (last, others) = frames.split_last().expect("a robot with contacts");
            let arms: Vec<TokenStream> = (others.iter().enumerate())
                .map(|(k, f)| {
                    let k = Literal::usize_unsuffixed(k);
                    let value = match f {
                        Some(f) => of(&variants[*f]),
                        None => otherwise.clone(),
                    };
                    quote!(#k => #value,)
                })
                .collect();
            let last = match last {
                Some(f) => of(&variants[*f]),
                None => otherwise.clone(),
            };
            match (frames.iter().any(Option::is_some), arms.is_empty()) {
                (true, false) => quote! {
                    match contact {
                        #(#arms)*
                        _ => #last,
                    }
                },
                // One frame for every contact (a robot with one contact): no `match`.
                (true, true) => quote! {
                    let _ = contact;
                    #last
                },
                (false, _) => quote! {
                    let _ = (t, contact);
                    #otherwise
                },
            }
        };
    let pose = |variant: &Ident| quote!(<Self as #frames_trait>::frame_pose(Frame::#variant, t));
    let local_jacobian = |variant: &Ident| quote!(<Self as #frames_trait>::frame_jacobian(Frame::#variant, ReferenceFrame::Local, t));
    let held: Vec<Option<usize>> = contacts.iter().map(|c| Some(c.frame)).collect();
    let held_to: Vec<Option<usize>> = contacts.iter().map(|c| c.to).collect();
    let identity = quote!(Pose::identity());
    let contact_pose = per_contact(&held, &pose, identity.clone());
    let contact_to_pose = per_contact(&held_to, &pose, identity);
    let contact_local_jacobian = per_contact(&held, &local_jacobian, quote!(SMatrix::zeros()));
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
            fn torque_response(t: &#trig) -> SMatrix<f64, #nv, #nv> {
                <Self as #forward_dynamics>::mass_matrix_inverse(t)
            }

            #[inline]
            fn contact_local_jacobian(t: &#trig, contact: usize) -> SMatrix<f64, 6, #nv> {
                #contact_local_jacobian
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
