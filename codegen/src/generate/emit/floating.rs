//! The module of a floating-base robot: its sizes, names and types, `FloatingBaseDynamics`,
//! `FloatingBaseParameters` and `FloatingDynamicsDerivatives` (each method placed by its row's
//! group), `FloatingFrameKinematics`, then the chunk functions of the large functions.

use super::constants::{base_parameters_function, joint_limits, literal};
use super::contacts::{contact_implementation, ContactTraits};
use super::file::{formatted, header, version_check, Provenance};
use super::frames::{frame_items, FrameTrait};
use super::function::function;
use super::header::Emitted;
use super::leaves::Leaves;
use super::plan::Form;
use super::sizes::Sizes;
use crate::generate::trace::SymbolicRobot;
use crate::model::Model;
use crate::FunctionGroup;
use proc_macro2::{Ident, Literal, TokenStream};
use quote::{format_ident, quote};

/// The traits of a floating-base module, by the group whose methods each holds.
const TRAITS: [FunctionGroup; 3] = [
    FunctionGroup::Dynamics,
    FunctionGroup::BaseParameters,
    FunctionGroup::Derivatives,
];

/// The group whose trait a function of `group` is a method of: the dynamics' groups share
/// `FloatingBaseDynamics`; the contacts' trait is written apart.
fn trait_of(group: FunctionGroup) -> FunctionGroup {
    match group {
        FunctionGroup::BaseParameters | FunctionGroup::Derivatives | FunctionGroup::Contacts => group,
        _ => FunctionGroup::Dynamics,
    }
}

/// The complete generated module of a floating-base `model`, formatted.
pub(super) fn module(model: &Model, robot: &SymbolicRobot, provenance: &Provenance, sizes: &Sizes) -> String {
    let leaves = Leaves::new(robot);
    let ty = format_ident!("{}", provenance.type_name);
    let emitted: Vec<(FunctionGroup, Emitted)> = (robot.quantities.iter())
        .filter(|q| !q.kind.is_per_frame())
        .map(|q| {
            let function = function(robot, &leaves, q, model.nv(), Form::Scalar, sizes);
            (trait_of(q.kind.group()), function)
        })
        .collect();
    let implementations = TRAITS.map(|group| {
        let methods = (emitted.iter())
            .filter(|(g, _)| *g == group)
            .map(|(_, e)| &e.method);
        implementation(model, robot, &ty, group, quote!(#(#methods)*))
    });
    let frames = frame_items(model, robot, &leaves, &ty, &FrameTrait::floating(model), sizes);
    let contacts = robot.functions.contains(FunctionGroup::Contacts).then(|| {
        let [n, nv, p] = [model.dof(), model.nv(), parameter_count(model)].map(Literal::usize_unsuffixed);
        let traits = ContactTraits {
            trig: quote!(FloatingTrig<#n>),
            forward_dynamics: quote!(FloatingBaseDynamics<#n, #nv, #p>),
            frames: quote!(FloatingFrameKinematics<#n, #nv>),
        };
        let methods = (emitted.iter())
            .filter(|(g, _)| *g == FunctionGroup::Contacts)
            .map(|(_, e)| e.method.clone());
        contact_implementation(model, &ty, &traits, methods)
    });
    let chunks = emitted.iter().flat_map(|(_, e)| &e.chunks);
    let version = version_check();
    let (constants, types) = (constants(model, robot), types(model, &ty));
    let tokens = quote! {
        #version

        #constants

        #types

        #(#implementations)*

        #frames

        #contacts

        #(#chunks)*
    };
    formatted(header(&description(model), provenance), tokens)
}

/// What the module computes, for its header.
fn description(model: &Model) -> String {
    let base_body = &model.floating_base().expect("a floating base").name;
    format!(
        "Rigid-body dynamics of `{}` on a floating base (body `{base_body}`; {} joints, {} \
         inertial parameters).",
        model.name(),
        model.dof(),
        parameter_count(model)
    )
}

/// Ten parameters for the base body, then ten per body.
fn parameter_count(model: &Model) -> usize {
    crate::dynamics::FloatingDynamics::parameter_names(model).len()
}

/// The implementation of the trait of `group` (one of [`TRAITS`]) for `ty`, with `methods`.
fn implementation(
    model: &Model,
    robot: &SymbolicRobot,
    ty: &Ident,
    group: FunctionGroup,
    methods: TokenStream,
) -> TokenStream {
    let [n, nv, p, b] = [
        model.dof(),
        model.nv(),
        parameter_count(model),
        robot.base.count(),
    ]
    .map(Literal::usize_unsuffixed);
    match group {
        FunctionGroup::Dynamics => {
            let name = model.name();
            let base = model.floating_base().expect("a floating base");
            let theta = (base.inertia.parameters().into_iter())
                .chain(model.parameters())
                .map(literal);
            quote! {
                impl FloatingBaseDynamics<#n, #nv, #p> for #ty {
                    const NAME: &'static str = #name;
                    const JOINT_NAMES: [&'static str; #n] = JOINT_NAMES;
                    const JOINT_LIMITS: [JointLimits; #n] = JOINT_LIMITS;
                    const PARAMETER_NAMES: [&'static str; #p] = PARAMETER_NAMES;

                    fn parameters() -> SVector<f64, #p> {
                        SVector::from_array_storage(ArrayStorage([[#(#theta),*]]))
                    }

                    #methods
                }
            }
        }
        FunctionGroup::BaseParameters => {
            let base_parameters = base_parameters_function(&robot.base);
            quote! {
                impl FloatingBaseParameters<#n, #nv, #p, #b> for #ty {
                    const BASE_PARAMETER_NAMES: [&'static str; #b] = BASE_PARAMETER_NAMES;

                    #base_parameters

                    #methods
                }
            }
        }
        FunctionGroup::Derivatives => quote! {
            impl FloatingDynamicsDerivatives<#n, #nv, #p> for #ty {
                #methods
            }
        },
        other => unreachable!("a floating-base module has no trait of its own for {other}"),
    }
}

/// The module's imports and constants.
fn constants(model: &Model, robot: &SymbolicRobot) -> TokenStream {
    let joint_names = model.joints().iter().map(|j| j.name.as_str());
    let joint_limits = joint_limits(model);
    let parameter_names = crate::dynamics::FloatingDynamics::parameter_names(model);
    let base = &robot.base;
    let base_names = base.names.iter().map(String::as_str);
    let count_doc = format!(
        " Number of base parameters (the `B` of [`FloatingBaseParameters`]): {} of {}.",
        base.count(),
        parameter_names.len()
    );
    let contacts = match robot.functions.contains(FunctionGroup::Contacts) {
        true => quote!(
            use dyngen_runtime::{ContactDynamics, ContactKind};
        ),
        false => quote!(),
    };
    let [n, nv, nq, p, b] = [
        model.dof(),
        model.nv(),
        model.nq(),
        parameter_names.len(),
        base.count(),
    ]
    .map(Literal::usize_unsuffixed);
    quote! {
        use dyngen_runtime::nalgebra::{ArrayStorage, Matrix3, SMatrix, SVector, Vector3};
        use dyngen_runtime::{
            ConfigurationError, FloatingBaseDynamics, FloatingBaseParameters, FloatingDynamicsDerivatives,
            FloatingFrameKinematics, FloatingTrig, JointLimits, Pose, ReferenceFrame, RobotFrame,
        };
        #contacts

        /// Number of moving joints.
        pub const DOF: usize = #n;
        /// Length of the velocity: the base twist's six, then the joints (the `NV` of the traits).
        pub const NV: usize = #nv;
        /// Length of the configuration: base position, unit quaternion `x y z w`, the joints.
        pub const NQ: usize = #nq;
        /// Number of standard parameters: ten for the base body, then ten per body.
        pub const PARAMETER_COUNT: usize = #p;
        /// Joint names, in the order of the joints in `q` and `ν`.
        pub const JOINT_NAMES: [&str; DOF] = [#(#joint_names),*];
        /// Joint limits from the description (infinite where it sets none).
        pub const JOINT_LIMITS: [JointLimits; DOF] = [#(#joint_limits),*];
        #[doc = #count_doc]
        pub const BASE_PARAMETER_COUNT: usize = #b;
        /// Names of the standard parameters θ, the base body's first.
        pub const PARAMETER_NAMES: [&str; PARAMETER_COUNT] = [#(#parameter_names),*];
        /// What each base parameter combines.
        pub const BASE_PARAMETER_NAMES: [&str; BASE_PARAMETER_COUNT] = [#(#base_names),*];
    }
}

/// The module's types, `trig`, and the robot type.
fn types(model: &Model, ty: &Ident) -> TokenStream {
    let type_doc = format!(
        " `{}` on a floating base: implements [`FloatingBaseDynamics`], \
         [`FloatingBaseParameters`], [`FloatingDynamicsDerivatives`] and \
         [`FloatingFrameKinematics`] with flattened, allocation-free code.",
        model.name()
    );
    quote! {
        /// The configuration prepared for every function: base pose and joint sines and cosines.
        pub type Trig = FloatingTrig<DOF>;
        /// A configuration `q` (NQ entries).
        pub type Configuration = SVector<f64, NQ>;
        /// A velocity, acceleration or generalised force (NV entries, the base's six first).
        pub type Velocity = SVector<f64, NV>;
        /// An NV × NV matrix: `D`, `C`, `D⁻¹`.
        pub type MassMatrix = SMatrix<f64, NV, NV>;
        /// A frame's 6 × NV Jacobian, and the centroidal momentum matrix.
        pub type Jacobian = SMatrix<f64, 6, NV>;
        /// The standard parameters θ.
        pub type Parameters = SVector<f64, PARAMETER_COUNT>;
        /// The base parameters θ_b.
        pub type BaseParameterVector = SVector<f64, BASE_PARAMETER_COUNT>;
        /// The regressor `Y`.
        pub type Regressor = SMatrix<f64, NV, PARAMETER_COUNT>;
        /// The base regressor `Y_b`.
        pub type BaseRegressor = SMatrix<f64, NV, BASE_PARAMETER_COUNT>;

        /// The prepared configuration of `q`; an error for a non-unit quaternion.
        pub fn trig(q: &Configuration) -> Result<Trig, ConfigurationError> {
            FloatingTrig::from_configuration(q.as_slice())
        }

        #[doc = #type_doc]
        #[derive(Clone, Copy, Debug, Default)]
        pub struct #ty;
    }
}
