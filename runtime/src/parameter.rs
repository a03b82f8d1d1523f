//! What each entry of a robot's parameter vector θ is.

use nalgebra::{Matrix3, Vector3};

/// Standard parameters per body: `[m, m·cx, m·cy, m·cz, Ixx, Ixy, Iyy, Ixz, Iyz, Izz]`, the
/// inertia about the body (joint) frame origin.
pub const PARAMETERS_PER_BODY: usize = 10;

/// Names of a body's ten standard parameters, in the order of [`body_parameters`] (a robot's
/// `PARAMETER_NAMES` are these with the body's name, `"mcx[link3]"`).
pub const BODY_PARAMETER_NAMES: [&str; PARAMETERS_PER_BODY] =
    ["m", "mcx", "mcy", "mcz", "Ixx", "Ixy", "Iyy", "Ixz", "Iyz", "Izz"];

/// A rigid body's ten standard parameters `[m, m·cx, m·cy, m·cz, Ixx, Ixy, Iyy, Ixz, Iyz, Izz]`
/// from its mass, centre of mass `com` and rotational inertia about the centre of mass, all
/// in the body (joint) frame: `I_O = I_C + m (cᵀc·1 − c cᵀ)` (parallel axes).
pub fn body_parameters(
    mass: f64,
    com: &Vector3<f64>,
    inertia_com: &Matrix3<f64>,
) -> [f64; PARAMETERS_PER_BODY] {
    let h = com * mass;
    let io = inertia_com + (Matrix3::identity() * com.dot(com) - com * com.transpose()) * mass;
    [
        mass,
        h.x,
        h.y,
        h.z,
        io[(0, 0)],
        io[(0, 1)],
        io[(1, 1)],
        io[(0, 2)],
        io[(1, 2)],
        io[(2, 2)],
    ]
}

/// The physical kind of a standard parameter: what an adaptation or identification gain is
/// chosen by, and what a physical-consistency constraint applies to. Carried as data by the
/// generated code, so nothing has to parse parameter names.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ParameterKind {
    /// A body's mass `m` (kg).
    Mass,
    /// A component of a body's first moment `m·c` (kg·m).
    FirstMoment,
    /// A component of a body's rotational inertia about its joint frame origin (kg·m²).
    Inertia,
    /// A joint's armature (reflected rotor inertia), kg·m² or kg.
    Armature,
    /// A joint's viscous friction coefficient, N·m·s/rad or N·s/m.
    ViscousFriction,
    /// A joint's Coulomb friction, N·m or N.
    CoulombFriction,
    /// A joint's constant torque offset, N·m or N.
    Offset,
}

impl ParameterKind {
    /// The kind of entry `k` (0–9) of a body's ten standard parameters.
    pub const fn of_body_entry(k: usize) -> ParameterKind {
        match k {
            0 => ParameterKind::Mass,
            1..=3 => ParameterKind::FirstMoment,
            _ => ParameterKind::Inertia,
        }
    }

    /// Whether the parameter belongs to a joint (armature, friction, offset) rather than a body.
    pub const fn is_joint_level(self) -> bool {
        matches!(
            self,
            ParameterKind::Armature
                | ParameterKind::ViscousFriction
                | ParameterKind::CoulombFriction
                | ParameterKind::Offset
        )
    }
}
