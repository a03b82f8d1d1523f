//! The traced graph (what generated functions compute), evaluated by the interpreter, in the
//! shapes the generic dynamics return, and what the generic dynamics say each quantity is.

use dyngen_codegen::dynamics::NumericDynamics;
use dyngen_codegen::internals::generate::{Shape, SymbolicRobot};
use nalgebra::DMatrix;

/// A quantity's interpreted `values` in the shape the generic code returns: a matrix pair side
/// by side (`n × 2n`), a pose (and the fused kinematics, and a vector pair) as one column.
pub fn shaped(robot: &SymbolicRobot, name: &str, values: Vec<f64>) -> DMatrix<f64> {
    match robot.quantity(name).expect("quantity").shape {
        Shape::Vector(n) => DMatrix::from_column_slice(n, 1, &values),
        Shape::Matrix(r, c) => DMatrix::from_column_slice(r, c, &values),
        Shape::MatrixPair(r, c) => DMatrix::from_column_slice(r, 2 * c, &values),
        Shape::Pose
        | Shape::Kinematics(_)
        | Shape::VectorPair(..)
        | Shape::ContactMatrices(..)
        | Shape::ContactSystem(..)
        | Shape::ContactStep(..)
        | Shape::ContactInertia(..) => DMatrix::from_column_slice(values.len(), 1, &values),
    }
}

/// The generic dynamics' value of every traced function of `(q, q̇, v, a)` (all but those of
/// the torques and the derivatives), by the traced quantity's name.
pub fn generic_values(
    robot: &SymbolicRobot,
    generic: &NumericDynamics,
    [q, qd, v, a]: [&[f64]; 4],
) -> Vec<(&'static str, DMatrix<f64>)> {
    let column = |x: &[f64]| DMatrix::from_column_slice(x.len(), 1, x);
    let (rot, pos) = generic.end_effector_pose(q);
    let mut pose = rot.as_slice().to_vec();
    pose.extend(pos.iter());
    let (j, jd) = (generic.jacobian(q), generic.jacobian_dot(q, qd));
    let mut kinematics = pose.clone();
    kinematics.extend(j.iter());
    kinematics.extend(jd.iter());
    vec![
        ("forward_kinematics", column(&pose)),
        ("jacobian", j),
        ("jacobian_dot", jd),
        ("kinematics", column(&kinematics)),
        ("mass_matrix", generic.mass_matrix(q)),
        ("coriolis_matrix", generic.coriolis_matrix(q, qd)),
        ("gravity", column(generic.gravity_torque(q).as_slice())),
        (
            "inverse_dynamics",
            column(generic.inverse_dynamics(q, qd, a).as_slice()),
        ),
        (
            "slotine_li",
            column(generic.slotine_li(q, qd, v, a, true).as_slice()),
        ),
        ("regressor", generic.regressor(q, qd, v, a)),
        (
            "base_regressor",
            robot.base.base_regressor(&generic.regressor(q, qd, v, a)),
        ),
        ("torque_regressor", generic.regressor(q, qd, qd, a)),
        (
            "base_torque_regressor",
            robot.base.base_regressor(&generic.regressor(q, qd, qd, a)),
        ),
    ]
}
