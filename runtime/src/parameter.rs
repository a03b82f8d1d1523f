//! What each entry of a robot's parameter vector θ is.

/// Standard parameters per body: `[m, m·cx, m·cy, m·cz, Ixx, Ixy, Iyy, Ixz, Iyz, Izz]`, the
/// inertia about the body (joint) frame origin.
pub const PARAMETERS_PER_BODY: usize = 10;

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
}
