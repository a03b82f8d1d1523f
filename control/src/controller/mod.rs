//! The adaptive hybrid force/position controller of the technical note *Adaptive Hybrid
//! Force-Position Control for Redundant Manipulators* (`docs/controller.md` gives it equation by
//! equation, with the deviations): the controlled frame, the end-effector or any named frame
//! (`frame`), task dimension and task-frame contact split (`task`),
//! orientation rows by rotation error on the geometric Jacobian (`orientation`), projections
//! with the singularity guard (`projections`, solving with the small Cholesky factor of `spd`
//! and the fused products of `matvec`), reference velocity and analytic reference acceleration
//! (`reference`), the law (`law`; `Y θ̂` and `Yᵀ r` from the robot's generated
//! `regressor_products`, without forming `Y`), the
//! adaptation (`adaptation`; the composite adaptation's prediction filter in `composite`), gains (`gains`) and online stiffness estimation
//! (`stiffness_estimator`).

mod adaptation;
mod composite;
mod error;
pub(crate) mod frame;
mod gains;
mod law;
mod matvec;
pub(crate) mod orientation;
mod projections;
mod reference;
mod spd;
mod stiffness_estimator;
mod task;

pub use adaptation::{parameter_error_energy, GammaByKind};
pub use composite::{Composite, PredictionFilter, DIRECTION_STEP};
pub use error::{ConfigError, TickError};
pub use frame::frame_named;
pub use gains::{mass_matrix_estimate, mass_matrix_shaped_gain, Gains};
pub use law::{
    Adaptation, ControlOutput, ControllerConfig, HybridController, MAX_START_ORIENTATION_ERROR_DEG,
};
pub use projections::{Projections, SingularityGuard};
pub use reference::{Desired, Measurement, Reference};
pub use stiffness_estimator::StiffnessEstimator;
pub use task::{ContactTask, Orientation, Split};
