//! The group `frames`: the robot's `Frame` enum and names, one straight-line function per frame
//! quantity, and the `FrameKinematics` implementation that chooses among them with a `match`.
//!
//! A frame function whose values another function already computes with the same arguments
//! (the end-effector's pose, `J` and `J̇` at its origin in base axes are `Kinematics`'
//! functions; two frames at one place share their Jacobians) is not emitted again: its arm
//! calls the function that exists.

use super::function::function;
use super::header::Emitted;
use super::leaves::Leaves;
use super::plan::Form;
use super::sizes::Sizes;
use crate::frame_names::frame_identifiers;
use crate::generate::quantities::{Arg, QuantityKind, Shape};
use crate::generate::trace::SymbolicRobot;
use crate::model::Model;
use crate::symbolic::Id;
use dyngen_runtime::ReferenceFrame;
use proc_macro2::{Ident, Literal, TokenStream};
use quote::{format_ident, quote};
use std::collections::HashMap;

/// The `Kinematics` functions a frame function may turn out to equal.
const KINEMATICS: [QuantityKind; 4] = [
    QuantityKind::ForwardKinematics,
    QuantityKind::Jacobian,
    QuantityKind::JacobianDot,
    QuantityKind::Kinematics,
];

/// The frame trait a robot implements: `FrameKinematics<N>` on `JointTrig<N>` with `N`
/// columns, or on a floating base `FloatingFrameKinematics<N, NV>` on `FloatingTrig<N>` with
/// `NV` columns.
pub(super) struct FrameTrait {
    pub(super) name: TokenStream,
    /// The doc of the `Frame` enum, which links the trait.
    pub(super) enum_doc: &'static str,
    pub(super) trig: TokenStream,
    /// Columns of a Jacobian (velocity coordinates).
    pub(super) width: usize,
}

impl FrameTrait {
    pub(super) fn fixed(model: &Model) -> FrameTrait {
        let n = Literal::usize_unsuffixed(model.dof());
        FrameTrait {
            name: quote!(FrameKinematics<#n>),
            enum_doc: " The robot's named frames: the argument of every [`FrameKinematics`] method.",
            trig: quote!(JointTrig<#n>),
            width: model.dof(),
        }
    }

    pub(super) fn floating(model: &Model) -> FrameTrait {
        let (n, nv) = (
            Literal::usize_unsuffixed(model.dof()),
            Literal::usize_unsuffixed(model.nv()),
        );
        FrameTrait {
            name: quote!(FloatingFrameKinematics<#n, #nv>),
            enum_doc: " The robot's named frames: the argument of every [`FloatingFrameKinematics`] method.",
            trig: quote!(FloatingTrig<#n>),
            width: model.nv(),
        }
    }
}

/// The frame items of the module: enum, constants, functions, trait implementation.
pub(super) fn frame_items(
    model: &Model,
    robot: &SymbolicRobot,
    leaves: &Leaves,
    ty: &Ident,
    frame_trait: &FrameTrait,
    sizes: &Sizes,
) -> TokenStream {
    let variants: Vec<Ident> = frame_identifiers(model.frames().iter().map(|f| f.name.as_str()))
        .into_iter()
        .map(|id| format_ident!("{}", id.variant))
        .collect();
    let enum_items = frame_enum(model, &variants, frame_trait.enum_doc);
    let (functions, calls) = frame_functions(robot, leaves, frame_trait.width, sizes);
    let implementation = frame_trait_impl(frame_trait, ty, &variants, &calls);
    let methods = functions.iter().map(|e| &e.method);
    let chunks = functions.iter().flat_map(|e| &e.chunks);
    quote! {
        #enum_items

        #implementation

        #(#methods)*

        #(#chunks)*
    }
}

/// `FRAME_COUNT`, `FRAME_NAMES`, the `Frame` enum (`variants`, documented `enum_doc`) and its
/// `RobotFrame` implementation.
fn frame_enum(model: &Model, variants: &[Ident], enum_doc: &str) -> TokenStream {
    let frames = model.frames();
    let names: Vec<&str> = frames.iter().map(|f| f.name.as_str()).collect();
    let docs = frames.iter().enumerate().map(|(k, f)| {
        let body = match (f.parent, model.floating_base()) {
            (Some(p), _) => &model.bodies()[p].name,
            (None, Some(base)) => &base.name,
            (None, None) => unreachable!("Model::new refuses a frame on a fixed base"),
        };
        match k {
            0 => format!(" `{}`, the end-effector (on body `{body}`).", f.name),
            _ => format!(" `{}` (on body `{body}`).", f.name),
        }
    });
    let count = Literal::usize_unsuffixed(frames.len());
    quote! {
        /// Number of named frames (the end-effector and the description's `frames`).
        pub const FRAME_COUNT: usize = #count;
        /// Frame names, in the order of [`Frame`]'s variants.
        pub const FRAME_NAMES: [&str; FRAME_COUNT] = [#(#names),*];

        #[doc = #enum_doc]
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
        pub enum Frame {
            #(#[doc = #docs] #variants,)*
        }

        impl RobotFrame for Frame {
            const ALL: &'static [Frame] = &[#(Frame::#variants),*];

            fn name(self) -> &'static str {
                match self {
                    #(Frame::#variants => #names,)*
                }
            }
        }
    }
}

/// Which function computes each frame quantity (by kind, frame index and reference frame), and
/// the Jacobian columns each frame's joints fill: the others are zero in every reference frame,
/// and a conversion at run time skips them.
#[derive(Default)]
struct FrameCalls {
    by_quantity: HashMap<(QuantityKind, usize, Option<ReferenceFrame>), TokenStream>,
    columns: HashMap<usize, Vec<usize>>,
}

/// The frame functions to emit (of Jacobians `width` columns wide), and which function computes
/// each frame quantity: an existing one, or one emitted here.
fn frame_functions(
    robot: &SymbolicRobot,
    leaves: &Leaves,
    width: usize,
    sizes: &Sizes,
) -> (Vec<Emitted>, FrameCalls) {
    let mut existing: HashMap<(Vec<Id>, Vec<Arg>, Shape), TokenStream> = HashMap::new();
    for q in robot.quantities.iter().filter(|q| KINEMATICS.contains(&q.kind)) {
        let name = format_ident!("{}", q.kind.name());
        existing.insert((q.outputs.clone(), q.args.clone(), q.shape), quote!(Self::#name));
    }
    let mut functions: Vec<Emitted> = Vec::new();
    let mut calls = FrameCalls::default();
    for q in robot.quantities.iter().filter(|q| q.kind.is_per_frame()) {
        let frame = q.frame.as_ref().expect("a frame quantity names its frame");
        let key = (q.outputs.clone(), q.args.clone(), q.shape);
        let call = match existing.get(&key) {
            Some(call) => call.clone(),
            None => {
                let name = format_ident!("{}", q.name());
                functions.push(function(robot, leaves, q, width, Form::Scalar, sizes));
                existing.insert(key, quote!(#name));
                quote!(#name)
            }
        };
        if (q.kind, frame.reference)
            == (
                QuantityKind::FrameJacobian,
                Some(ReferenceFrame::LocalWorldAligned),
            )
        {
            calls
                .columns
                .insert(frame.index, filled_columns(robot, &q.outputs));
        }
        calls
            .by_quantity
            .insert((q.kind, frame.index, frame.reference), call);
    }
    (functions, calls)
}

/// The columns of a 6-row Jacobian (`outputs` column-major) not all zero constants.
fn filled_columns(robot: &SymbolicRobot, outputs: &[Id]) -> Vec<usize> {
    let zero = |id: &Id| robot.graph.constant_value(*id) == Some(0.0);
    (outputs.chunks(6).enumerate())
        .filter(|(_, column)| !column.iter().all(zero))
        .map(|(c, _)| c)
        .collect()
}

/// The arms of the `match` of the trait method of `kind`: per frame (and reference frame), the
/// call of the function that computes it, with `args`. A reference frame without a function of
/// its own (`frame_references: aligned`) is converted from `local_world_aligned`
/// ([`converted`]).
fn frame_arms(
    variants: &[Ident],
    calls: &FrameCalls,
    kind: QuantityKind,
    args: TokenStream,
) -> Vec<TokenStream> {
    let mut arms = Vec::new();
    for (k, variant) in variants.iter().enumerate() {
        if let Some(call) = calls.by_quantity.get(&(kind, k, None)) {
            arms.push(quote!(Frame::#variant => #call(#args),));
        }
        let mut missing = false;
        for r in ReferenceFrame::ALL {
            match calls.by_quantity.get(&(kind, k, Some(r))) {
                Some(call) => {
                    let reference = format_ident!("{r:?}");
                    arms.push(quote!((Frame::#variant, ReferenceFrame::#reference) => #call(#args),));
                }
                None => missing = kind.has_reference_frame(),
            }
        }
        if missing {
            let value = converted(calls, kind, k);
            arms.push(quote!((Frame::#variant, reference) => #value,));
        }
    }
    arms
}

/// Frame `k`'s `kind` in the method's `reference`, converted at run time from the functions in
/// base axes: the pose and `J`, and `J̇` with them, the pose and the velocity, and the
/// acceleration with them. (`frame_kinematics` gives the pose, `J` and `J̇` in one call, but
/// writing its three results costs more than the three functions computing them apart.)
fn converted(calls: &FrameCalls, kind: QuantityKind, k: usize) -> TokenStream {
    let aligned = Some(ReferenceFrame::LocalWorldAligned);
    let call = |kind, reference| {
        calls
            .by_quantity
            .get(&(kind, k, reference))
            .unwrap_or_else(|| panic!("frame {k}: no {kind:?} in {reference:?} to convert from"))
    };
    let pose = call(QuantityKind::FramePose, None);
    let convert = quote!(dyngen_runtime::__private::frame_references);
    let columns = (calls
        .columns
        .get(&k)
        .map(Vec::as_slice)
        .unwrap_or_default()
        .iter())
    .map(|&c| Literal::usize_unsuffixed(c));
    let columns = quote!(&[#(#columns),*]);
    match kind {
        QuantityKind::FrameJacobian => {
            let jacobian = call(kind, aligned);
            quote!(#convert::jacobian(reference, &#pose(t), #jacobian(t), #columns))
        }
        QuantityKind::FrameJacobianTimeVariation => {
            let (jacobian, rate) = (call(QuantityKind::FrameJacobian, aligned), call(kind, aligned));
            quote!(#convert::jacobian_time_variation(reference, &#pose(t), &#jacobian(t), #rate(t, qd), qd, #columns))
        }
        QuantityKind::FrameVelocity => {
            let velocity = call(kind, aligned);
            quote!(#convert::velocity(reference, &#pose(t), #velocity(t, qd)))
        }
        QuantityKind::FrameClassicalAcceleration => {
            let velocity = call(QuantityKind::FrameVelocity, aligned);
            let acceleration = call(kind, aligned);
            quote!(#convert::classical_acceleration(reference, &#pose(t), #velocity(t, qd), #acceleration(t, qd, qdd)))
        }
        _ => unreachable!("{kind:?} has no reference frame"),
    }
}

/// The frame trait's implementation for `ty`: each method a `match` on the frame (and the
/// reference frame) calling the function `calls` names.
fn frame_trait_impl(
    frame_trait: &FrameTrait,
    ty: &Ident,
    variants: &[Ident],
    calls: &FrameCalls,
) -> TokenStream {
    let n = Literal::usize_unsuffixed(frame_trait.width);
    let (trait_name, trig) = (&frame_trait.name, &frame_trait.trig);
    let arms = |kind, args| frame_arms(variants, calls, kind, args);
    let pose = arms(QuantityKind::FramePose, quote!(t));
    let jacobian = arms(QuantityKind::FrameJacobian, quote!(t));
    let time_variation = arms(QuantityKind::FrameJacobianTimeVariation, quote!(t, qd));
    let velocity = arms(QuantityKind::FrameVelocity, quote!(t, qd));
    let acceleration = arms(QuantityKind::FrameClassicalAcceleration, quote!(t, qd, qdd));
    let kinematics = arms(QuantityKind::FrameKinematics, quote!(t, qd));
    quote! {
        impl #trait_name for #ty {
            type Frame = Frame;

            fn frame_pose(frame: Frame, t: &#trig) -> Pose {
                match frame {
                    #(#pose)*
                }
            }

            fn frame_jacobian(frame: Frame, reference: ReferenceFrame, t: &#trig) -> SMatrix<f64, 6, #n> {
                match (frame, reference) {
                    #(#jacobian)*
                }
            }

            fn frame_jacobian_time_variation(
                frame: Frame,
                reference: ReferenceFrame,
                t: &#trig,
                qd: &SVector<f64, #n>,
            ) -> SMatrix<f64, 6, #n> {
                match (frame, reference) {
                    #(#time_variation)*
                }
            }

            fn frame_velocity(
                frame: Frame,
                reference: ReferenceFrame,
                t: &#trig,
                qd: &SVector<f64, #n>,
            ) -> SVector<f64, 6> {
                match (frame, reference) {
                    #(#velocity)*
                }
            }

            fn frame_classical_acceleration(
                frame: Frame,
                reference: ReferenceFrame,
                t: &#trig,
                qd: &SVector<f64, #n>,
                qdd: &SVector<f64, #n>,
            ) -> SVector<f64, 6> {
                match (frame, reference) {
                    #(#acceleration)*
                }
            }

            fn frame_kinematics(
                frame: Frame,
                t: &#trig,
                qd: &SVector<f64, #n>,
            ) -> (Pose, SMatrix<f64, 6, #n>, SMatrix<f64, 6, #n>) {
                match frame {
                    #(#kinematics)*
                }
            }
        }
    }
}
