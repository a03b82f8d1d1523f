//! How the simulated robot's joint friction and armature differ from the nominal values of its
//! description (which are the controller's starting estimate): one factor per kind.

use dyngen_runtime::ParameterKind;

/// True joint-level parameters = factor × the description's nominal value, per kind. Inertial
/// parameters are not scaled (the true robot differs from the description there by its
/// payload). Robots without joint-level columns are not affected.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JointTermFactors {
    pub armature: f64,
    pub viscous: f64,
    pub coulomb: f64,
    pub offset: f64,
}

impl JointTermFactors {
    /// The true robot is its description.
    pub const NOMINAL: JointTermFactors = JointTermFactors {
        armature: 1.0,
        viscous: 1.0,
        coulomb: 1.0,
        offset: 1.0,
    };

    /// The demo's default: reflected inertia 1.25× and friction and offset 2× the nominal
    /// values. On `arm7_friction`, whose description holds a cold catalogue estimate, this
    /// makes the true joint terms those the identification example takes as the real arm's
    /// (armature 0.5 … 0.05 kg·m², viscous 0.8 … 0.1 N·m·s/rad, Coulomb 3 … 0.5 N·m); friction
    /// of harmonic drives changes by about this much with temperature and load.
    pub const DEMO: JointTermFactors = JointTermFactors {
        armature: 1.25,
        viscous: 2.0,
        coulomb: 2.0,
        offset: 2.0,
    };

    /// The factor of a standard parameter of kind `kind` (1 for inertial parameters).
    pub fn of(&self, kind: ParameterKind) -> f64 {
        match kind {
            ParameterKind::Mass | ParameterKind::FirstMoment | ParameterKind::Inertia => 1.0,
            ParameterKind::Armature => self.armature,
            ParameterKind::ViscousFriction => self.viscous,
            ParameterKind::CoulombFriction => self.coulomb,
            ParameterKind::Offset => self.offset,
        }
    }
}

impl Default for JointTermFactors {
    fn default() -> Self {
        JointTermFactors::DEMO
    }
}
