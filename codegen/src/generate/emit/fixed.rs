//! The module of a fixed-base robot: its sizes, names and types, then one trait implementation
//! per chosen group, whose methods are the functions of that group's rows of the quantity table
//! (with the base parameters, the lane forms of the rows that have one), then the chunk
//! functions of the large ones.

use super::composed::composed;
use super::constants::{base_parameters_function, joint_limits, joint_names, literal, parameter_kinds};
use super::contacts::{contact_implementation, ContactTraits};
use super::file::{formatted, header, type_doc, version_check, Provenance};
use super::frames::{frame_items, FrameTrait};
use super::function::function;
use super::header::Emitted;
use super::leaves::Leaves;
use super::plan::Form;
use super::sizes::Sizes;
use crate::generate::trace::{Quantity, SymbolicRobot};
use crate::model::Model;
use crate::{FunctionGroup, Functions};
use proc_macro2::{Ident, Literal, TokenStream};
use quote::{format_ident, quote};

/// The complete generated module of a fixed-base `model`, formatted.
pub(super) fn module(model: &Model, robot: &SymbolicRobot, provenance: &Provenance, sizes: &Sizes) -> String {
    let module = FixedModule::new(model, robot, provenance, sizes);
    let version = version_check();
    let (constants, types) = (module.constants(), module.types());
    let implementations = robot.functions.groups().map(|g| module.implementation(g));
    let chunks = (module.emitted.iter().map(|(_, e)| e))
        .chain(&module.lane_functions)
        .flat_map(|e| &e.chunks);
    let tokens = quote! {
        #version

        #constants

        #types

        #(#implementations)*

        #(#chunks)*
    };
    formatted(header(&description(model, robot), provenance), tokens)
}

/// A fixed-base module being assembled: its robot, and its functions emitted.
struct FixedModule<'a> {
    model: &'a Model,
    robot: &'a SymbolicRobot,
    leaves: Leaves,
    sizes: &'a Sizes,
    ty: Ident,
    /// Every function but the per-frame ones, with the group whose trait it is a method of.
    emitted: Vec<(FunctionGroup, Emitted)>,
    /// The lane forms (several states per call), which come with the base parameters (their
    /// trait is bounded by `B`).
    lane_functions: Vec<Emitted>,
}

impl<'a> FixedModule<'a> {
    fn new(model: &'a Model, robot: &'a SymbolicRobot, provenance: &Provenance, sizes: &'a Sizes) -> Self {
        let n = model.dof();
        let leaves = Leaves::new(robot);
        let emitted = (robot.quantities.iter())
            .filter(|q| !q.kind.is_per_frame())
            .map(|q| {
                let emitted = match q.composed {
                    true => composed(model, q),
                    false => function(robot, &leaves, q, n, Form::Scalar, sizes),
                };
                (q.kind.group(), emitted)
            })
            .collect();
        let has_lanes = robot.functions.contains(FunctionGroup::BaseParameters);
        let lane_functions = (robot.quantities.iter())
            .filter(|q| has_lanes && q.kind.has_lane_form())
            .map(|q| function(robot, &leaves, &lane_form(robot, q), n, Form::Lanes, sizes))
            .collect();
        FixedModule {
            model,
            robot,
            leaves,
            sizes,
            ty: format_ident!("{}", provenance.type_name),
            emitted,
            lane_functions,
        }
    }

    /// The methods of `group`'s trait.
    fn methods(&self, group: FunctionGroup) -> impl Iterator<Item = &TokenStream> {
        (self.emitted.iter())
            .filter(move |(g, _)| *g == group)
            .map(|(_, e)| &e.method)
    }

    /// The implementation of `group`'s trait (with the base parameters, `LaneDynamics` too).
    fn implementation(&self, group: FunctionGroup) -> TokenStream {
        let (model, ty) = (self.model, &self.ty);
        let [n, p, b] =
            [model.dof(), model.parameter_count(), self.robot.base.count()].map(Literal::usize_unsuffixed);
        let methods = self.methods(group);
        match group {
            FunctionGroup::Kinematics => {
                let name = model.name();
                let end_effector_body = Literal::usize_unsuffixed(model.end_effector_body());
                quote! {
                    impl Kinematics<#n> for #ty {
                        const NAME: &'static str = #name;
                        const JOINT_NAMES: [&'static str; #n] = JOINT_NAMES;
                        const JOINT_LIMITS: [JointLimits; #n] = JOINT_LIMITS;
                        const END_EFFECTOR_BODY: usize = #end_effector_body;

                        #(#methods)*
                    }
                }
            }
            FunctionGroup::Dynamics => {
                let theta = model.parameters().into_iter().map(literal);
                quote! {
                    impl RobotDynamics<#n, #p> for #ty {
                        const PARAMETER_NAMES: [&'static str; #p] = PARAMETER_NAMES;
                        const PARAMETER_KINDS: [ParameterKind; #p] = PARAMETER_KINDS;

                        fn parameters() -> SVector<f64, #p> {
                            SVector::from_array_storage(ArrayStorage([[#(#theta),*]]))
                        }

                        #(#methods)*
                    }
                }
            }
            FunctionGroup::BaseParameters => {
                let base_parameters = base_parameters_function(&self.robot.base);
                let lane_methods = self.lane_functions.iter().map(|e| &e.method);
                quote! {
                    impl BaseParameters<#n, #p, #b> for #ty {
                        const BASE_PARAMETER_NAMES: [&'static str; #b] = BASE_PARAMETER_NAMES;

                        #base_parameters

                        #(#methods)*
                    }

                    impl LaneDynamics<#n, #b> for #ty {
                        #(#lane_methods)*
                    }
                }
            }
            FunctionGroup::Frames => {
                let frame_trait = FrameTrait::fixed(model);
                frame_items(model, self.robot, &self.leaves, ty, &frame_trait, self.sizes)
            }
            FunctionGroup::Contacts => {
                let traits = ContactTraits {
                    trig: quote!(JointTrig<#n>),
                    forward_dynamics: quote!(ForwardDynamics<#n, #p>),
                    frames: quote!(FrameKinematics<#n>),
                };
                contact_implementation(model, ty, &traits, methods.cloned())
            }
            other => {
                let name = format_ident!("{}", other.trait_name());
                quote! {
                    impl #name<#n, #p> for #ty {
                        #(#methods)*
                    }
                }
            }
        }
    }

    /// The module's imports and constants.
    fn constants(&self) -> TokenStream {
        let (model, robot) = (self.model, self.robot);
        let [n, p, b] =
            [model.dof(), model.parameter_count(), robot.base.count()].map(Literal::usize_unsuffixed);
        let runtime_items = runtime_items(&robot.functions)
            .into_iter()
            .map(|item| format_ident!("{item}"));
        let joint_names = joint_names(model);
        let joint_limits = joint_limits(model);
        let param_names = model.parameter_names();
        let param_kinds = parameter_kinds(model);
        let base_names = robot.base.names.iter().map(String::as_str);
        let count_doc = base_count_doc(model, robot);
        quote! {
            use dyngen_runtime::nalgebra::{ArrayStorage, Matrix3, SMatrix, SVector, Vector3};
            use dyngen_runtime::{#(#runtime_items),*};

            /// Number of moving joints (the `N` of [`Kinematics`] and [`RobotDynamics`]).
            pub const DOF: usize = #n;
            /// Number of standard parameters, ten per body (the `P` of [`RobotDynamics`]).
            pub const PARAMETER_COUNT: usize = #p;
            #[doc = #count_doc]
            pub const BASE_PARAMETER_COUNT: usize = #b;
            /// Joint names, in the order of `q`.
            pub const JOINT_NAMES: [&str; DOF] = [#(#joint_names),*];
            /// Joint limits from the description (infinite where it sets none).
            pub const JOINT_LIMITS: [JointLimits; DOF] = [#(#joint_limits),*];
            /// Names of the standard parameters θ, e.g. `"mcx[link3]"`.
            pub const PARAMETER_NAMES: [&str; PARAMETER_COUNT] = [#(#param_names),*];
            /// The kind of each standard parameter.
            pub const PARAMETER_KINDS: [ParameterKind; PARAMETER_COUNT] = [#(#param_kinds),*];
            /// What each base parameter combines.
            pub const BASE_PARAMETER_NAMES: [&str; BASE_PARAMETER_COUNT] = [#(#base_names),*];
        }
    }

    /// The module's types, and the robot type.
    fn types(&self) -> TokenStream {
        let ty = &self.ty;
        let type_doc = robot_type_doc(self.model.name(), &self.robot.functions);
        quote! {
            /// The standard parameters, for generic code (`HybridController<Standard, DOF, PARAMETER_COUNT>`).
            pub type Standard = dyngen_runtime::Standard<#ty>;
            /// The base parameters, for generic code (`HybridController<Base, DOF, BASE_PARAMETER_COUNT>`).
            pub type Base = dyngen_runtime::Base<#ty, PARAMETER_COUNT>;
            /// Joint sines and cosines, the first argument of every function.
            pub type Trig = JointTrig<DOF>;
            /// A joint-space vector: `q`, `q̇`, `q̈`, `τ`.
            pub type JointVector = SVector<f64, DOF>;
            /// The 6 × DOF end-effector Jacobian.
            pub type Jacobian = SMatrix<f64, 6, DOF>;
            /// A DOF × DOF joint-space matrix: `D`, `C`.
            pub type JointMatrix = SMatrix<f64, DOF, DOF>;
            /// The standard parameters θ.
            pub type Parameters = SVector<f64, PARAMETER_COUNT>;
            /// The base parameters θ_b.
            pub type BaseParameterVector = SVector<f64, BASE_PARAMETER_COUNT>;
            /// The regressor `Y`.
            pub type Regressor = SMatrix<f64, DOF, PARAMETER_COUNT>;
            /// The base regressor `Y_b`.
            pub type BaseRegressor = SMatrix<f64, DOF, BASE_PARAMETER_COUNT>;

            #[doc = #type_doc]
            #[derive(Clone, Copy, Debug, Default)]
            pub struct #ty;
        }
    }
}

/// `q` as its lane form computes it: the scalar formulation where the traced one is in lane
/// vectors (the regressors, four rows at a time), since the lane form is generic over its own
/// lane type.
fn lane_form(robot: &SymbolicRobot, q: &Quantity) -> Quantity {
    match robot.scalar_forms.get(&q.name()) {
        Some(outputs) => Quantity {
            outputs: outputs.clone(),
            ..q.clone()
        },
        None => q.clone(),
    }
}

/// What the module computes, for its header: `Rigid-body dynamics of `arm7` (7 joints, …)`.
fn description(model: &Model, robot: &SymbolicRobot) -> String {
    let (n, p, b) = (model.dof(), model.parameter_count(), robot.base.count());
    // A robot without joint-level parameters keeps its header word for word.
    let parameters = match model.joint_terms().per_joint() {
        0 => format!("{p} inertial parameters"),
        k => {
            let kinds: Vec<&str> = model.joint_terms().kinds.iter().map(|k| k.keyword()).collect();
            format!(
                "{p} parameters: {} inertial, {} joint-level ({})",
                model.inertial_parameter_count(),
                k * n,
                kinds.join(", ")
            )
        }
    };
    // Mimic joints have bodies but no coordinate: say how many the robot has besides its `n`.
    let joints = match model.joints().len() - n {
        0 => format!("{n} joints"),
        m => format!("{n} joints and {m} mimic joints"),
    };
    format!(
        "Rigid-body dynamics of `{}` ({joints}, {parameters}, {b} base parameters).",
        model.name()
    )
}

/// The doc of `BASE_PARAMETER_COUNT`, which links the trait of the base parameters only where
/// the module implements (and so imports) it.
fn base_count_doc(model: &Model, robot: &SymbolicRobot) -> String {
    let group = FunctionGroup::BaseParameters;
    let link = match robot.functions.contains(group) {
        true => format!("[`{}`]", group.trait_name()),
        false => format!("`{}`", group.trait_name()),
    };
    format!(
        " Number of base parameters of `{}` (the `B` of {link}): {} of {}.",
        model.name(),
        robot.base.count(),
        model.parameter_count()
    )
}

/// What the module imports from `dyngen-runtime`: the data types, and the traits of its groups.
fn runtime_items(functions: &Functions) -> Vec<&'static str> {
    let mut items = vec!["JointLimits", "JointTrig", "ParameterKind", "Pose"];
    items.extend(functions.groups().map(FunctionGroup::trait_name));
    if functions.contains(FunctionGroup::BaseParameters) {
        items.extend(["JointTrigLanes", "LaneDynamics", "Lanes"]);
    }
    if functions.contains(FunctionGroup::Frames) {
        items.extend(["ReferenceFrame", "RobotFrame"]);
    }
    if functions.contains(FunctionGroup::Contacts) {
        items.extend([
            "ContactInertia",
            "ContactKind",
            "ContactMatrices",
            "ContactStep",
            "ContactSystem",
        ]);
    }
    items.sort_unstable();
    items
}

/// The robot type's doc: which traits it implements.
fn robot_type_doc(name: &str, functions: &Functions) -> String {
    let mut traits: Vec<String> = functions.groups().map(|g| g.trait_name().to_owned()).collect();
    if functions.contains(FunctionGroup::BaseParameters) {
        traits.push("LaneDynamics".to_owned());
    }
    type_doc(&format!("`{name}`"), &traits)
}
