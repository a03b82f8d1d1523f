//! Joint-level parameters: the torques at a joint that no rigid body explains.
//!
//! Per moving joint `j`, four optional regressor columns, appended to `Y` after the ten
//! inertial columns of every body (joint after joint, each joint's kinds in the order
//! [`JointTermKind::ALL`]):
//!
//! | kind | parameter | torque at joint `j` | regressor column (row `j`) |
//! |---|---|---|---|
//! | armature (reflected rotor inertia) | `Ia` | `Ia·a_j` | `a_j` |
//! | viscous friction | `fv` | `fv·v_j` | `v_j` |
//! | Coulomb friction | `fc` | `fc·σ(q̇_j)` | `σ(q̇_j)` |
//! | offset (sensor bias, cable torque) | `fo` | `fo` | `1` |
//!
//! `σ(q̇) = sign(q̇)` (0 at rest), or with smoothing `ε` (`coulomb_smoothing`),
//! `σ(q̇) = tanh(q̇/ε)`: differentiable, as adaptive laws and simulators prefer, and equal to
//! the sign to within `1 − tanh(3) ≈ 0.5%` once `|q̇| > 3ε`. Armature multiplies `a` as the
//! rotor inertia does in `D a` (it adds `Ia` to `D`'s diagonal); viscous friction multiplies
//! `v` as `C` does, so at `v = q̇`, `a = q̈` the row is the physical torque `τ`.
//!
//! Which kinds exist is a choice of the description (`joint_parameters.columns`); a robot that
//! chooses none has exactly the rigid-body regressor of `10·n` columns.

/// One kind of joint-level parameter.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum JointTermKind {
    Armature,
    Viscous,
    Coulomb,
    Offset,
}

impl JointTermKind {
    /// Every kind, in column order.
    pub const ALL: [JointTermKind; 4] = [
        JointTermKind::Armature,
        JointTermKind::Viscous,
        JointTermKind::Coulomb,
        JointTermKind::Offset,
    ];

    /// The parameter's symbol in names, e.g. `fv[joint3]`.
    pub fn symbol(self) -> &'static str {
        match self {
            JointTermKind::Armature => "Ia",
            JointTermKind::Viscous => "fv",
            JointTermKind::Coulomb => "fc",
            JointTermKind::Offset => "fo",
        }
    }

    /// The word used in descriptions (`columns: [armature, viscous, coulomb, offset]`).
    pub fn keyword(self) -> &'static str {
        match self {
            JointTermKind::Armature => "armature",
            JointTermKind::Viscous => "viscous",
            JointTermKind::Coulomb => "coulomb",
            JointTermKind::Offset => "offset",
        }
    }

    /// The runtime's kind of this parameter (what generated code's `PARAMETER_KINDS` says).
    pub fn parameter_kind(self) -> dyngen_runtime::ParameterKind {
        match self {
            JointTermKind::Armature => dyngen_runtime::ParameterKind::Armature,
            JointTermKind::Viscous => dyngen_runtime::ParameterKind::ViscousFriction,
            JointTermKind::Coulomb => dyngen_runtime::ParameterKind::CoulombFriction,
            JointTermKind::Offset => dyngen_runtime::ParameterKind::Offset,
        }
    }

    /// Whether a physical value must be non-negative (an offset may have either sign).
    pub fn is_non_negative(self) -> bool {
        !matches!(self, JointTermKind::Offset)
    }
}

/// The joint-level values of one joint (all four kinds; only the chosen ones enter θ).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct JointTermValues {
    /// `Ia`, kg·m² (revolute) or kg (prismatic).
    pub armature: f64,
    /// `fv`, N·m·s/rad or N·s/m.
    pub viscous: f64,
    /// `fc`, N·m or N.
    pub coulomb: f64,
    /// `fo`, N·m or N.
    pub offset: f64,
}

impl JointTermValues {
    pub fn get(&self, kind: JointTermKind) -> f64 {
        match kind {
            JointTermKind::Armature => self.armature,
            JointTermKind::Viscous => self.viscous,
            JointTermKind::Coulomb => self.coulomb,
            JointTermKind::Offset => self.offset,
        }
    }

    pub fn set(&mut self, kind: JointTermKind, value: f64) {
        match kind {
            JointTermKind::Armature => self.armature = value,
            JointTermKind::Viscous => self.viscous = value,
            JointTermKind::Coulomb => self.coulomb = value,
            JointTermKind::Offset => self.offset = value,
        }
    }
}

/// The joint-level parameters of a model: which columns its regressor has, and the values.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct JointTerms {
    /// The chosen kinds, in [`JointTermKind::ALL`] order without repeats. Empty: none.
    pub kinds: Vec<JointTermKind>,
    /// `None`: Coulomb friction uses `sign(q̇)`; `Some(ε)`: `tanh(q̇/ε)`, `ε > 0`.
    pub coulomb_smoothing: Option<f64>,
    /// Values per moving joint (same order as the joints); empty means all zero.
    pub values: Vec<JointTermValues>,
}

impl JointTerms {
    /// Parameters per joint (the number of chosen kinds).
    pub fn per_joint(&self) -> usize {
        self.kinds.len()
    }

    /// The values of joint `j` (zero when none were given).
    pub fn value(&self, j: usize) -> JointTermValues {
        self.values.get(j).copied().unwrap_or_default()
    }

    /// The values of joint `j` that act: the chosen kinds' (the others are 0, so that
    /// `Y θ` and the torque functions always agree).
    pub fn effective(&self, j: usize) -> JointTermValues {
        let given = self.value(j);
        let mut v = JointTermValues::default();
        for &k in &self.kinds {
            v.set(k, given.get(k));
        }
        v
    }

    /// Whether kind `kind` is one of the columns.
    pub fn has(&self, kind: JointTermKind) -> bool {
        self.kinds.contains(&kind)
    }

    /// The chosen kinds, sorted and without repeats (the order of θ and `Y`).
    pub fn normalized_kinds(kinds: &[JointTermKind]) -> Vec<JointTermKind> {
        JointTermKind::ALL
            .into_iter()
            .filter(|k| kinds.contains(k))
            .collect()
    }
}
