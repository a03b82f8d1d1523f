//! Rust source from a traced robot: one flat, single-assignment function per quantity.
//!
//! By concern: `leaves` (how inputs are spelled), `plan` (what a function computes, in what
//! order, with which multiply-adds), `signature` (parameters and the inputs' destructuring),
//! `function` (one quantity as a function), `vector_stores` (outputs written a vector at a
//! time), `into_form` (its form writing into a kept `ResultBuffer`), `chunks` (a large one in
//! chunks), `constants` (constant items and `θ_b`), and this file, which assembles the module.
//!
//! Each function declares all its temporaries once (`let [x0, x1, …]: [f64; K];`), then assigns
//! every live node in creation order, `xK = a op b;`, with atoms (literals, inputs, earlier
//! temporaries) as operands: never nested expressions, which overflow rustc's parser on large
//! robots, and never one `let` per node, which nests debug-info scopes as deep as the function
//! is long (see `Plan::statements`). Functions of more than `CHUNK_VALUES` values are split into
//! `<name>_partK` chunk functions that hand on the values later chunks read through arrays the
//! calling function owns (`chunks`). Inputs are destructured once at the top of a function;
//! vector and matrix results are written in place through destructured `&mut` entries, the
//! others built with `from_array_storage`, so the generated code has no indexing, no allocation
//! and no panic path.

mod chunks;
mod constants;
mod floating;
mod frames;
mod function;
mod into_form;
mod lane_width;
mod leaves;
mod plan;
mod signature;
mod vector_stores;

use super::trace::{Quantity, SymbolicRobot};
use crate::model::Model;
use crate::{FunctionGroup, Functions};
pub use chunks::CHUNK_VALUES;
use constants::{base_parameters_function, joint_limits, literal, parameter_kinds};
pub use floating::emit_floating;
use function::{function, Emitted};
use leaves::Leaves;
use plan::Form;
use proc_macro2::{Literal, TokenStream};
use quote::{format_ident, quote};

/// What the header of a generated file records.
#[derive(Clone, Debug)]
pub struct Provenance {
    /// The description as the user named it, e.g. `robots/arm7.yaml`.
    pub source: String,
    /// Content hash of every file the description read.
    pub source_hash: String,
    /// The command that regenerates the file.
    pub regenerate: String,
    /// Name of the generated robot type, e.g. `Arm7`.
    pub type_name: String,
}

/// Name of the generated robot type, e.g. `arm7` → `Arm7`, `ur5_robot` → `Ur5Robot`.
pub fn type_name(robot: &str) -> String {
    let mut out = String::new();
    for part in robot
        .split(|c: char| !c.is_ascii_alphanumeric())
        .filter(|p| !p.is_empty())
    {
        let mut chars = part.chars();
        if let Some(first) = chars.next() {
            out.push(first.to_ascii_uppercase());
            out.extend(chars);
        }
    }
    if out.is_empty() || out.starts_with(|c: char| c.is_ascii_digit()) {
        out.insert_str(0, "Robot");
    }
    out
}

/// Attributes for the `mod` item that holds a generated file: the lints flattened numeric code
/// trips by design (long literals, long functions, names like `x12`/`x13`), and no rustfmt
/// (the file is already formatted, by prettyplease, and must stay byte-identical).
pub const MODULE_ATTRIBUTES: &str = "#[rustfmt::skip]\n#[allow(clippy::approx_constant, clippy::excessive_precision, clippy::unreadable_literal, clippy::too_many_lines, clippy::many_single_char_names, clippy::similar_names, clippy::neg_multiply)]";

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
    items.sort_unstable();
    items
}

/// The robot type's doc: which traits it implements.
fn type_doc(name: &str, functions: &Functions) -> String {
    let mut traits: Vec<String> = functions
        .groups()
        .map(|g| format!("[`{}`]", g.trait_name()))
        .collect();
    if functions.contains(FunctionGroup::BaseParameters) {
        traits.push("[`LaneDynamics`]".to_owned());
    }
    let listed = match traits.split_last() {
        Some((last, [])) => last.clone(),
        Some((last, rest)) => format!("{} and {last}", rest.join(", ")),
        None => String::new(),
    };
    format!(" `{name}`: implements {listed} with flattened, allocation-free code.")
}

/// The complete generated module for `model`, formatted. The module declaration that
/// includes it carries the lint allows of [`MODULE_ATTRIBUTES`].
pub fn emit(model: &Model, robot: &SymbolicRobot, provenance: &Provenance) -> String {
    let n = model.dof();
    let p = model.parameter_count();
    let leaves = Leaves::new(robot);
    let ty = format_ident!("{}", provenance.type_name);
    let name = &model.name();
    let coordinates = model.coordinate_joints();
    let joint_names = coordinates.iter().map(|&k| model.joints()[k].name.as_str());
    let joint_limits = joint_limits(model);
    let end_effector_body = Literal::usize_unsuffixed(model.end_effector_body());
    let param_names = model.parameter_names();
    let param_kinds = parameter_kinds(model);
    let theta: Vec<TokenStream> = model.parameters().into_iter().map(literal).collect();
    let functions = robot.functions;
    let emitted: Vec<(FunctionGroup, Emitted)> = robot
        .quantities
        .iter()
        .filter(|q| !q.kind.is_per_frame())
        .map(|q| (q.kind.group(), function(robot, &leaves, q, n, Form::Scalar)))
        .collect();
    // The lane functions come with the base parameters (their trait is bounded by `B`).
    let has_lanes = functions.contains(FunctionGroup::BaseParameters);
    let lane_functions: Vec<Emitted> = robot
        .quantities
        .iter()
        .filter(|q| has_lanes && q.kind.has_lane_form())
        .map(|q| match robot.scalar_forms.get(&q.name()) {
            Some(outputs) => {
                let scalar = Quantity {
                    outputs: outputs.clone(),
                    ..q.clone()
                };
                function(robot, &leaves, &scalar, n, Form::Lanes)
            }
            None => function(robot, &leaves, q, n, Form::Lanes),
        })
        .collect();
    let methods = |group: FunctionGroup| {
        emitted
            .iter()
            .filter(move |(g, _)| *g == group)
            .map(|(_, e)| &e.method)
    };
    let chunks = emitted
        .iter()
        .map(|(_, e)| e)
        .chain(&lane_functions)
        .flat_map(|e| &e.chunks);
    let base = &robot.base;
    let base_names = base.names.iter().map(String::as_str);
    let base_parameters = base_parameters_function(base);
    let b = Literal::usize_unsuffixed(base.count());
    // Doc links only to the traits the module implements (and so imports).
    let link = |group: FunctionGroup| match functions.contains(group) {
        true => format!("[`{}`]", group.trait_name()),
        false => format!("`{}`", group.trait_name()),
    };
    let count_doc = format!(
        " Number of base parameters of `{name}` (the `B` of {}): {} of {p}.",
        link(FunctionGroup::BaseParameters),
        base.count()
    );
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
    let (n, p) = (Literal::usize_unsuffixed(n), Literal::usize_unsuffixed(p));
    let header = format!(
        "// Rigid-body dynamics of `{name}` ({joints}, {parameters}, {b} base parameters).\n\
         // Generated by dyngen {} from `{}` (fnv1a64 {}).\n\
         // Do not edit by hand: regenerate with `{}`.\n\n",
        env!("CARGO_PKG_VERSION"),
        provenance.source,
        provenance.source_hash,
        provenance.regenerate
    );
    let type_doc = type_doc(name, &functions);
    // The generator's version: the runtime accepts it only if it is its own (`__private`, which
    // generated code calls, changes in any release).
    let generated_by = env!("CARGO_PKG_VERSION");
    let runtime_items = runtime_items(&functions)
        .into_iter()
        .map(|item| format_ident!("{item}"));
    let implementations: Vec<TokenStream> = functions
        .groups()
        .map(|group| {
            let methods = methods(group);
            match group {
                FunctionGroup::Kinematics => quote! {
                    impl Kinematics<#n> for #ty {
                        const NAME: &'static str = #name;
                        const JOINT_NAMES: [&'static str; #n] = JOINT_NAMES;
                        const JOINT_LIMITS: [JointLimits; #n] = JOINT_LIMITS;
                        const END_EFFECTOR_BODY: usize = #end_effector_body;

                        #(#methods)*
                    }
                },
                FunctionGroup::Dynamics => {
                    let theta = &theta;
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
                    let lane_methods = lane_functions.iter().map(|e| &e.method);
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
                    frames::frame_items(model, robot, &leaves, &ty, &frames::FrameTrait::fixed(model))
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
        })
        .collect();
    let tokens = quote! {
        dyngen_runtime::__require_version!(#generated_by);

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

        #(#implementations)*

        #(#chunks)*
    };
    match syn::parse2::<syn::File>(tokens) {
        Ok(file) => header + &prettyplease::unparse(&file),
        // Only a bug in this emitter can get here; show the tokens so it can be found.
        Err(e) => panic!("dyngen emitted invalid Rust ({e}); this is a bug in dyngen"),
    }
}
