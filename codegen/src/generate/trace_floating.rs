//! The tracer of a floating-base robot: the floating algorithms run on symbolic inputs, the
//! base pose entering as its rotation matrix and position (`FloatingTrig` computes them once
//! per tick from the quaternion), velocities of `nv = dof + 6` entries.

use super::quantities::QuantityKind;
use super::trace::{base_columns, full_from_base, keep_cheaper, pair_ids};
use super::trace::{
    frame_motion_quantities, ids, inputs, matrix_ids, Arg, Inputs, Quantity, Shape, SymbolicRobot,
};
use crate::base_parameters::BaseParameterSet;
use crate::dynamics::floating::{self as algorithms, FloatingBase};
use crate::dynamics::{self, FloatingDynamics, FrameMotion};
use crate::frame_names::frame_identifiers;
use crate::model::Model;
use crate::scalar::Scalar;
use crate::spatial::{Mat3, RigidInertia, Transform, Vec3};
use crate::symbolic::{record, Expr};
use crate::{FunctionGroup, Functions};

/// The groups a floating-base robot is generated with: its dynamics (with the centroidal
/// quantities), forward dynamics and frames, the functions of `FloatingBaseDynamics` and
/// `FloatingFrameKinematics`, the base parameters (`FloatingBaseParameters`) and the
/// derivatives (`FloatingDynamicsDerivatives`).
pub fn floating_functions() -> Functions {
    Functions::with(&[
        FunctionGroup::Kinematics,
        FunctionGroup::Dynamics,
        FunctionGroup::Regressors,
        FunctionGroup::BaseParameters,
        FunctionGroup::ForwardDynamics,
        FunctionGroup::Derivatives,
        FunctionGroup::Frames,
    ])
    .expect("the floating groups need nothing they lack")
}

/// Records every floating-base quantity of `model` in one graph.
///
/// The inertial parameters are the representative ones of the base parameters (every folded
/// parameter 0, [`BaseParameterSet::representative`]): the same dynamics with fewer terms, as
/// for a fixed base.
pub fn trace_floating(model: &Model) -> SymbolicRobot {
    let base_parameters = BaseParameterSet::compute(model);
    let description = FloatingDynamics::new(model)
        .expect("trace_floating needs a floating base")
        .parameters();
    let theta = base_parameters.representative(&description);
    let (n, nv) = (model.dof(), model.nv());
    let (graph, (inputs, quantities, other_forms)) = record(|| {
        let q = inputs("q", n);
        let rotation = inputs("rot", 9);
        let position = inputs("pos", 3);
        let (qd, v, a, tau) = (
            inputs("qd", nv),
            inputs("v", nv),
            inputs("a", nv),
            inputs("tau", nv),
        );
        let pose = Transform {
            rot: Mat3(std::array::from_fn(|r| {
                std::array::from_fn(|c| rotation[3 * r + c])
            })),
            pos: Vec3([position[0], position[1], position[2]]),
        };
        let theta: Vec<Expr> = theta.iter().map(|&x| Expr::from_f64(x)).collect();
        let mut inertias: Vec<RigidInertia<Expr>> = dynamics::inertias_from_parameters(&theta);
        let base_inertia = inertias.remove(0);
        let base = FloatingBase {
            pose,
            inertia: base_inertia,
        };
        let x = dynamics::joint_transforms(model, &q);
        let world = algorithms::floating_body_poses(model, &pose, &x);
        let regressor = |v: &[Expr]| {
            let full = algorithms::floating_regressor(model, &pose.rot, &x, &qd, v, &a);
            let y = matrix_ids(&full_from_base(&full, &base_parameters));
            let y_base = base_columns(&y, &base_parameters, nv);
            (y, y_base)
        };
        let (y, y_base) = regressor(&v);
        let (torque_y, torque_y_base) = regressor(&qd);
        let gravity = Some(Vec3::from_f64(model.gravity().into()));
        let p = 10 * (model.joints().len() + 1);
        let quantity = |kind, args: Vec<Arg>, shape, outputs| Quantity {
            kind,
            frame: None,
            args,
            shape,
            outputs,
        };
        let centroidal = algorithms::centroidal_momentum_matrix(model, &base, &x, &inertias);
        let mut quantities = vec![
            quantity(
                QuantityKind::MassMatrix,
                vec![],
                Shape::Matrix(nv, nv),
                matrix_ids(&algorithms::floating_mass_matrix(
                    model,
                    &base.inertia,
                    &x,
                    &inertias,
                )),
            ),
            quantity(
                QuantityKind::CoriolisMatrix,
                vec![Arg::Qd],
                Shape::Matrix(nv, nv),
                matrix_ids(&algorithms::floating_coriolis_matrix(
                    model, &base, &x, &inertias, &qd,
                )),
            ),
            quantity(
                QuantityKind::Gravity,
                vec![],
                Shape::Vector(nv),
                ids(&algorithms::floating_gravity(model, &base, &x, &inertias)),
            ),
            quantity(
                QuantityKind::InverseDynamics,
                vec![Arg::Qd, Arg::A],
                Shape::Vector(nv),
                ids(&algorithms::floating_inverse_dynamics(
                    model, &base, &x, &inertias, &qd, &a,
                )),
            ),
            quantity(
                QuantityKind::SlotineLi,
                vec![Arg::Qd, Arg::V, Arg::A],
                Shape::Vector(nv),
                ids(&algorithms::floating_slotine_li(
                    model, &base, &x, &inertias, &qd, &v, &a, gravity,
                )),
            ),
            quantity(
                QuantityKind::Regressor,
                vec![Arg::Qd, Arg::V, Arg::A],
                Shape::Matrix(nv, p),
                y,
            ),
            quantity(
                QuantityKind::BaseRegressor,
                vec![Arg::Qd, Arg::V, Arg::A],
                Shape::Matrix(nv, base_parameters.count()),
                y_base,
            ),
            quantity(
                QuantityKind::TorqueRegressor,
                vec![Arg::Qd, Arg::A],
                Shape::Matrix(nv, p),
                torque_y,
            ),
            quantity(
                QuantityKind::BaseTorqueRegressor,
                vec![Arg::Qd, Arg::A],
                Shape::Matrix(nv, base_parameters.count()),
                torque_y_base,
            ),
            quantity(
                QuantityKind::ForwardDynamics,
                vec![Arg::Qd, Arg::Tau],
                Shape::Vector(nv),
                ids(&algorithms::floating_forward_dynamics(
                    model, &base, &x, &inertias, &qd, &tau,
                )),
            ),
            quantity(
                QuantityKind::MassMatrixInverse,
                vec![],
                Shape::Matrix(nv, nv),
                matrix_ids(&algorithms::floating_mass_matrix_inverse(
                    model, &base, &x, &inertias,
                )),
            ),
            quantity(
                QuantityKind::CenterOfMass,
                vec![],
                Shape::Vector(3),
                ids(&centroidal.com.0),
            ),
            quantity(
                QuantityKind::CentroidalMomentumMatrix,
                vec![],
                Shape::Matrix(6, nv),
                matrix_ids(&centroidal.matrix),
            ),
            quantity(
                QuantityKind::CentroidalBias,
                vec![Arg::Qd],
                Shape::Vector(6),
                ids(&algorithms::centroidal_bias(model, &base, &x, &inertias, &qd)),
            ),
        ];
        let spelled = frame_identifiers(model.frames().iter().map(|f| f.name.as_str()));
        for (index, frame) in model.frames().iter().enumerate() {
            let motion = FrameMotion {
                pose: dynamics::kinematics::frame_pose(Some(&pose), &world, frame),
                jacobian: algorithms::floating_frame_jacobian(model, &pose, &world, frame),
                jacobian_dot: algorithms::floating_frame_jacobian_dot(model, &pose, &world, &qd, frame),
            };
            let snake = &spelled[index].snake;
            quantities.extend(frame_motion_quantities(&motion, &qd, &a, index, snake, nv));
        }
        // The derivatives, traced after everything else so the functions above keep their ids.
        let inverse_derivatives = pair_ids(algorithms::floating_inverse_dynamics_derivatives(
            model, &base, &q, &inertias, &qd, &a,
        ));
        let forward_derivatives = pair_ids(algorithms::floating_forward_dynamics_derivatives(
            model, &base, &q, &inertias, &qd, &tau,
        ));
        quantities.extend([
            quantity(
                QuantityKind::InverseDynamicsDerivatives,
                vec![Arg::Qd, Arg::A],
                Shape::MatrixPair(nv),
                inverse_derivatives,
            ),
            quantity(
                QuantityKind::ForwardDynamicsDerivatives,
                vec![Arg::Qd, Arg::Tau],
                Shape::MatrixPair(nv),
                forward_derivatives,
            ),
        ]);
        let inputs = Inputs {
            q: ids(&q),
            qd: ids(&qd),
            v: ids(&v),
            a: ids(&a),
            tau: ids(&tau),
            theta: Vec::new(),
            r: Vec::new(),
            base_rotation: ids(&rotation),
            base_position: ids(&position),
        };
        // D⁻¹ by sums over common ancestors, traced last so the functions above keep their node
        // ids; kept where it costs less. (The regressors by the bodies' Jacobians cost fewer
        // operations on the G1 but ran slower: longer-lived values. Four rows at a time, as for
        // a fixed base, they ran 1.2–1.45× slower on Solo-12: every body's columns carry the six
        // dense base rows, while the scalar form gets each joint row from one entry of the
        // force it carries up anyway.)
        let inverse = algorithms::floating_mass_matrix_inverse_by_ancestors(model, &base, &x, &inertias);
        let other_forms = vec![(
            QuantityKind::MassMatrixInverse.name().to_owned(),
            matrix_ids(&inverse),
        )];
        (inputs, quantities, other_forms)
    });
    let mut quantities = quantities;
    keep_cheaper(&graph, &mut quantities, other_forms);
    SymbolicRobot {
        graph,
        inputs,
        quantities,
        base: base_parameters,
        functions: floating_functions(),
        chunk_values: super::emit::CHUNK_VALUES,
        scalar_forms: std::collections::HashMap::new(),
    }
}
