//! Errors: configuration errors are found before a run starts; tick errors stop a run.

/// A controller or scenario setting that cannot work, found before the first tick.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ConfigError {
    #[error("gain {name} is not positive definite: {detail}")]
    NotPositiveDefinite { name: &'static str, detail: String },
    #[error(
        "contact stiffness K ({rows}×{cols}) is not of full row rank: smallest singular value {sigma_min:.3e} \
         (needs > {threshold:.1e} relative to the largest)"
    )]
    StiffnessRankDeficient {
        rows: usize,
        cols: usize,
        sigma_min: f64,
        threshold: f64,
    },
    #[error("contact stiffness K is inconsistent with the task: {0}")]
    StiffnessShape(String),
    #[error("task dimension {task} asks for more directions than the robot's {dof} degrees of freedom")]
    TaskDimension { task: usize, dof: usize },
    #[error(
        "task dimension {task} does not match its orientation task, {orientation} ({expected} rows); \
         supported: 3 (position), 5 (position + tool axis), 6 (position + orientation)"
    )]
    TaskKind {
        task: usize,
        orientation: super::task::Orientation,
        expected: usize,
    },
    #[error(
        "the desired orientation is {angle_deg:.1}° from the start orientation (at most {limit_deg}°): the \
         rotation error sin φ·u falls beyond 90° and vanishes at 180°; approach it in smaller steps"
    )]
    OrientationTooFar { angle_deg: f64, limit_deg: f64 },
    #[error("desired force contradicts the contact model: {0}")]
    ForceContradictsContact(String),
    #[error(
        "the robot starts at a singular configuration: smallest singular value of the task \
         Jacobian {sigma:.3e} is below {threshold:.3e}"
    )]
    SingularStart { sigma: f64, threshold: f64 },
    #[error(
        "gains too high for the sampling period: λ_max(D̂⁻¹G)·dt = {value:.2} > {limit} (lower κ or raise the rate)"
    )]
    SamplingLimit { value: f64, limit: f64 },
    #[error(
        "on a rigid surface the force loop's gain per control period is {gain:.2} (above {limit} the \
         force oscillates and grows): raise the model stiffness k from {stiffness:e} to at least \
         {needed:.1e} N/m ({unit:.1e} N/m for a gain of 1), or lower λ or G"
    )]
    RigidForceLoop {
        gain: f64,
        limit: f64,
        stiffness: f64,
        needed: f64,
        unit: f64,
    },
    #[error("invalid setting `{name}`: {detail}")]
    Invalid { name: &'static str, detail: String },
}

/// A control tick that cannot produce a usable torque.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum TickError {
    #[error("non-finite measurement (q, q̇ or F̄ contains NaN or infinity)")]
    NonFiniteMeasurement,
    #[error("non-finite torque or reference (the model produced NaN or infinity)")]
    NonFiniteTorque,
    #[error("task Jacobian J Jᵀ not invertible even with the damping guard (smallest eigenvalue {0:.3e})")]
    Singular(f64),
}
