//! The one table of generated functions: each quantity's name, the runtime trait it is a method
//! of, whether it also has a lane form, and the group a user would choose it by. The tracer
//! records quantities by these kinds, the emitter places each method by its trait, and a test
//! holds the table to the traits of `dyngen-runtime` and to the reference in `docs/dynamics.md`.

/// One generated function. The order of [`QuantityKind::ALL`] is the order the tracer records
/// them in, which is append-only: node ids follow creation order, so a quantity added at the end
/// leaves every earlier function's code byte-identical.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum QuantityKind {
    ForwardKinematics,
    Jacobian,
    JacobianDot,
    MassMatrix,
    CoriolisMatrix,
    Gravity,
    InverseDynamics,
    SlotineLi,
    Regressor,
    BaseRegressor,
    ForwardDynamics,
    MassMatrixInverse,
    InverseDynamicsDerivatives,
    ForwardDynamicsDerivatives,
    TorqueRegressor,
    BaseTorqueRegressor,
    Kinematics,
    RegressorProducts,
    BaseRegressorProducts,
}

/// The runtime trait a generated function is a method of.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Home {
    /// `dyngen_runtime::Kinematics`: functions of the joint angles (and rates) alone.
    Kinematics,
    /// `dyngen_runtime::RobotDynamics`: the dynamics with the standard parameters.
    RobotDynamics,
    /// `dyngen_runtime::BaseParameters`: what uses only the base parameters' columns.
    BaseParameters,
}

/// The groups of functions a user thinks in when choosing what to generate.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Group {
    /// Pose, `J`, `J̇`.
    Kinematics,
    /// `D`, `C`, `g`, `τ`, the Slotine–Li torque.
    Dynamics,
    /// The regressors and their products, standard parameters.
    Regressors,
    /// The same with the base parameters.
    BaseParameters,
    /// `q̈ = D⁻¹ (τ − C q̇ − g)` and `D⁻¹`.
    ForwardDynamics,
    /// `∂τ/∂(q, q̇)` and `∂q̈/∂(q, τ)`.
    Derivatives,
}

/// A row of the table.
#[derive(Clone, Copy, Debug)]
struct Row {
    name: &'static str,
    home: Home,
    group: Group,
    lane_form: bool,
}

impl QuantityKind {
    /// Every kind, in trace order.
    pub const ALL: [QuantityKind; 19] = [
        QuantityKind::ForwardKinematics,
        QuantityKind::Jacobian,
        QuantityKind::JacobianDot,
        QuantityKind::MassMatrix,
        QuantityKind::CoriolisMatrix,
        QuantityKind::Gravity,
        QuantityKind::InverseDynamics,
        QuantityKind::SlotineLi,
        QuantityKind::Regressor,
        QuantityKind::BaseRegressor,
        QuantityKind::ForwardDynamics,
        QuantityKind::MassMatrixInverse,
        QuantityKind::InverseDynamicsDerivatives,
        QuantityKind::ForwardDynamicsDerivatives,
        QuantityKind::TorqueRegressor,
        QuantityKind::BaseTorqueRegressor,
        QuantityKind::Kinematics,
        QuantityKind::RegressorProducts,
        QuantityKind::BaseRegressorProducts,
    ];

    fn row(self) -> Row {
        use Group as G;
        use Home as H;
        let row = |name, home, group, lane_form| Row {
            name,
            home,
            group,
            lane_form,
        };
        match self {
            QuantityKind::ForwardKinematics => row("forward_kinematics", H::Kinematics, G::Kinematics, false),
            QuantityKind::Jacobian => row("jacobian", H::Kinematics, G::Kinematics, false),
            QuantityKind::JacobianDot => row("jacobian_dot", H::Kinematics, G::Kinematics, false),
            QuantityKind::MassMatrix => row("mass_matrix", H::RobotDynamics, G::Dynamics, false),
            QuantityKind::CoriolisMatrix => row("coriolis_matrix", H::RobotDynamics, G::Dynamics, false),
            QuantityKind::Gravity => row("gravity", H::RobotDynamics, G::Dynamics, false),
            QuantityKind::InverseDynamics => row("inverse_dynamics", H::RobotDynamics, G::Dynamics, true),
            QuantityKind::SlotineLi => row("slotine_li", H::RobotDynamics, G::Dynamics, false),
            QuantityKind::Regressor => row("regressor", H::RobotDynamics, G::Regressors, false),
            QuantityKind::BaseRegressor => row("base_regressor", H::BaseParameters, G::BaseParameters, false),
            QuantityKind::ForwardDynamics => {
                row("forward_dynamics", H::RobotDynamics, G::ForwardDynamics, false)
            }
            QuantityKind::MassMatrixInverse => {
                row("mass_matrix_inverse", H::RobotDynamics, G::ForwardDynamics, false)
            }
            QuantityKind::InverseDynamicsDerivatives => row(
                "inverse_dynamics_derivatives",
                H::RobotDynamics,
                G::Derivatives,
                false,
            ),
            QuantityKind::ForwardDynamicsDerivatives => row(
                "forward_dynamics_derivatives",
                H::RobotDynamics,
                G::Derivatives,
                false,
            ),
            QuantityKind::TorqueRegressor => row("torque_regressor", H::RobotDynamics, G::Regressors, false),
            QuantityKind::BaseTorqueRegressor => row(
                "base_torque_regressor",
                H::BaseParameters,
                G::BaseParameters,
                true,
            ),
            QuantityKind::Kinematics => row("kinematics", H::Kinematics, G::Kinematics, false),
            QuantityKind::RegressorProducts => {
                row("regressor_products", H::RobotDynamics, G::Regressors, false)
            }
            QuantityKind::BaseRegressorProducts => row(
                "base_regressor_products",
                H::BaseParameters,
                G::BaseParameters,
                false,
            ),
        }
    }

    /// The generated function's name, e.g. `mass_matrix`.
    pub fn name(self) -> &'static str {
        self.row().name
    }

    /// The kind named `name`, if any.
    pub fn from_name(name: &str) -> Option<QuantityKind> {
        QuantityKind::ALL.into_iter().find(|k| k.name() == name)
    }

    /// The runtime trait the function is a method of.
    pub fn home(self) -> Home {
        self.row().home
    }

    /// The group a user chooses it by.
    pub fn group(self) -> Group {
        self.row().group
    }

    /// Whether it also comes in lane form (`<name>_lanes`, several states per call, a method
    /// of `dyngen_runtime::LaneDynamics`): what identification and batched roll-outs evaluate
    /// in bulk.
    pub fn has_lane_form(self) -> bool {
        self.row().lane_form
    }

    /// Whether it is one of the base-parameter columns of a regressor (its doc names them).
    pub fn uses_base_columns(self) -> bool {
        self.home() == Home::BaseParameters
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashSet;

    #[test]
    fn names_are_distinct_snake_case_and_round_trip() {
        let mut seen = HashSet::new();
        for kind in QuantityKind::ALL {
            let name = kind.name();
            assert!(seen.insert(name), "{name} twice");
            assert!(
                name.chars().all(|c| c.is_ascii_lowercase() || c == '_') && !name.starts_with('_'),
                "{name} is not a snake_case function name"
            );
            assert_eq!(QuantityKind::from_name(name), Some(kind));
        }
        assert_eq!(QuantityKind::from_name("mass_matrix_lanes"), None);
    }

    #[test]
    fn every_group_and_home_has_a_function() {
        use Group as G;
        for group in [
            G::Kinematics,
            G::Dynamics,
            G::Regressors,
            G::BaseParameters,
            G::ForwardDynamics,
            G::Derivatives,
        ] {
            assert!(
                QuantityKind::ALL.iter().any(|k| k.group() == group),
                "{group:?} empty"
            );
        }
        for home in [Home::Kinematics, Home::RobotDynamics, Home::BaseParameters] {
            assert!(
                QuantityKind::ALL.iter().any(|k| k.home() == home),
                "{home:?} empty"
            );
        }
        // Kinematics methods need no parameters: nothing of a dynamics group may live there.
        for kind in QuantityKind::ALL {
            assert_eq!(
                kind.home() == Home::Kinematics,
                kind.group() == Group::Kinematics,
                "{kind:?}"
            );
        }
    }
}
