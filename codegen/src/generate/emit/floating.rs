//! The module of a floating-base robot: its sizes, names and types, then one trait
//! implementation per chosen group (`FloatingBaseDynamics`, `FloatingRegressors`, …, each
//! method placed by its row's group, [`FunctionGroup::floating_trait_name`]), then the chunk
//! functions of the large functions.

use super::composed::composed;
use super::constants::{base_parameters_function, joint_limits, joint_names, literal};
use super::contacts::{contact_implementation, ContactTraits};
use super::file::{formatted, header, type_doc, version_check, Provenance};
use super::frames::{frame_items, FrameTrait};
use super::function::function;
use super::header::Emitted;
use super::leaves::Leaves;
use super::plan::Form;
use super::sizes::Sizes;
use crate::generate::trace::SymbolicRobot;
use crate::model::Model;
use crate::{FunctionGroup, Functions};
use proc_macro2::{Ident, Literal, TokenStream};
use quote::{format_ident, quote};

/// The complete generated module of a floating-base `model`, formatted.
pub(super) fn module(model: &Model, robot: &SymbolicRobot, provenance: &Provenance, sizes: &Sizes) -> String {
    let leaves = Leaves::new(robot);
    let ty = format_ident!("{}", provenance.type_name);
    let emitted: Vec<(FunctionGroup, Emitted)> = (robot.quantities.iter())
        .filter(|q| !q.kind.is_per_frame())
        .map(|q| {
            let function = match q.composed {
                true => composed(model, q),
                false => function(robot, &leaves, q, model.nv(), Form::Scalar, sizes),
            };
            (q.kind.group(), function)
        })
        .collect();
    let implementations = robot.functions.groups().map(|group| {
        let methods = (emitted.iter())
            .filter(|(g, _)| *g == group)
            .map(|(_, e)| e.method.clone());
        implementation(model, robot, &leaves, &ty, group, methods, sizes)
    });
    let chunks = emitted.iter().flat_map(|(_, e)| &e.chunks);
    let version = version_check();
    let (constants, types) = (constants(model, robot), types(model, &robot.functions, &ty));
    let tokens = quote! {
        #version

        #constants

        #types

        #(#implementations)*

        #(#chunks)*
    };
    formatted(header(&description(model), provenance), tokens)
}

/// What the module computes, for its header.
fn description(model: &Model) -> String {
    let base_body = &model.floating_base().expect("a floating base").name;
    let parameters = match model.joint_terms().kinds.is_empty() {
        true => format!("{} inertial parameters", parameter_count(model)),
        false => format!("{} parameters, joint-level ones included", parameter_count(model)),
    };
    format!(
        "Rigid-body dynamics of `{}` on a floating base (body `{base_body}`; {} joints, \
         {parameters}).",
        model.name(),
        model.dof(),
    )
}

/// Ten parameters for the base body, then ten per body, then the joint-level ones.
fn parameter_count(model: &Model) -> usize {
    crate::dynamics::FloatingDynamics::parameter_count(model)
}

/// The implementation of `group`'s trait for `ty`, with `methods` (the frames' items, enum
/// included, for `frames`).
fn implementation(
    model: &Model,
    robot: &SymbolicRobot,
    leaves: &Leaves,
    ty: &Ident,
    group: FunctionGroup,
    methods: impl Iterator<Item = TokenStream>,
    sizes: &Sizes,
) -> TokenStream {
    let [n, nv, p, b] = [
        model.dof(),
        model.nv(),
        parameter_count(model),
        robot.base.count(),
    ]
    .map(Literal::usize_unsuffixed);
    match group {
        // A floating base's end-effector functions are among its frames'.
        FunctionGroup::Kinematics => quote!(),
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

                    #(#methods)*
                }
            }
        }
        FunctionGroup::BaseParameters => {
            let base_parameters = base_parameters_function(&robot.base);
            quote! {
                impl FloatingBaseParameters<#n, #nv, #p, #b> for #ty {
                    const BASE_PARAMETER_NAMES: [&'static str; #b] = BASE_PARAMETER_NAMES;

                    #base_parameters

                    #(#methods)*
                }
            }
        }
        FunctionGroup::Frames => frame_items(model, robot, leaves, ty, &FrameTrait::floating(model), sizes),
        FunctionGroup::Contacts => {
            let traits = ContactTraits {
                trig: quote!(FloatingTrig<#n>),
                forward_dynamics: quote!(FloatingForwardDynamics<#n, #nv, #p>),
                frames: quote!(FloatingFrameKinematics<#n, #nv>),
            };
            contact_implementation(model, ty, &traits, methods)
        }
        FunctionGroup::Regressors | FunctionGroup::ForwardDynamics | FunctionGroup::Derivatives => {
            let name = format_ident!("{}", group.floating_trait_name().expect("a floating trait"));
            quote! {
                impl #name<#n, #nv, #p> for #ty {
                    #(#methods)*
                }
            }
        }
    }
}

/// The module's imports and constants.
fn constants(model: &Model, robot: &SymbolicRobot) -> TokenStream {
    let joint_names = joint_names(model);
    let joint_limits = joint_limits(model);
    let parameter_names = crate::dynamics::FloatingDynamics::parameter_names(model);
    let base = &robot.base;
    let base_names = base.names.iter().map(String::as_str);
    // The trait is linked only where the module implements (and so imports) it.
    let trait_name = match robot.functions.contains(FunctionGroup::BaseParameters) {
        true => "[`FloatingBaseParameters`]",
        false => "`FloatingBaseParameters`",
    };
    let count_doc = format!(
        " Number of base parameters (the `B` of {trait_name}): {} of {}.",
        base.count(),
        parameter_names.len()
    );
    let parameter_count_doc = match model.joint_terms().kinds.is_empty() {
        true => " Number of standard parameters: ten for the base body, then ten per body.",
        false => {
            " Number of standard parameters: ten for the base body, then ten per body, then the \
             joint-level ones."
        }
    };
    let (nalgebra_items, runtime_items) = imports(&robot.functions);
    let nalgebra_items = nalgebra_items.into_iter().map(|item| format_ident!("{item}"));
    let runtime_items = runtime_items.into_iter().map(|item| format_ident!("{item}"));
    let [n, nv, nq, p, b] = [
        model.dof(),
        model.nv(),
        model.nq(),
        parameter_names.len(),
        base.count(),
    ]
    .map(Literal::usize_unsuffixed);
    quote! {
        use dyngen_runtime::nalgebra::{#(#nalgebra_items),*};
        use dyngen_runtime::{#(#runtime_items),*};

        /// Number of moving joints.
        pub const DOF: usize = #n;
        /// Length of the velocity: the base twist's six, then the joints (the `NV` of the traits).
        pub const NV: usize = #nv;
        /// Length of the configuration: base position, unit quaternion `x y z w`, the joints.
        pub const NQ: usize = #nq;
        #[doc = #parameter_count_doc]
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

/// What the module imports from `nalgebra` and from `dyngen-runtime`: the data types its chosen
/// groups use, and their traits (an unused import would be a warning in the user's build).
fn imports(functions: &Functions) -> (Vec<&'static str>, Vec<&'static str>) {
    let mut nalgebra = vec!["ArrayStorage", "SMatrix", "SVector"];
    let mut runtime = vec!["ConfigurationError", "FloatingTrig", "JointLimits"];
    runtime.extend(functions.groups().filter_map(FunctionGroup::floating_trait_name));
    if functions.contains(FunctionGroup::Frames) {
        nalgebra.extend(["Matrix3", "Vector3"]);
        runtime.extend(["Pose", "ReferenceFrame", "RobotFrame"]);
    }
    if functions.contains(FunctionGroup::Contacts) {
        runtime.extend([
            "ContactInertia",
            "ContactKind",
            "ContactMatrices",
            "ContactStep",
            "ContactSystem",
        ]);
    }
    nalgebra.sort_unstable();
    runtime.sort_unstable();
    runtime.dedup();
    (nalgebra, runtime)
}

/// The module's types, `trig`, and the robot type.
fn types(model: &Model, functions: &Functions, ty: &Ident) -> TokenStream {
    let traits: Vec<String> = (functions.groups())
        .filter_map(FunctionGroup::floating_trait_name)
        .map(str::to_owned)
        .collect();
    let type_doc = type_doc(&format!("`{}` on a floating base", model.name()), &traits);
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
