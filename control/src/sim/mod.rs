//! Simulation of the controller in contact: the true plant (generated dynamics with the true
//! parameters through the regressor, plus an unmodelled payload and, for robots with
//! joint-level columns, friction and armature off their nominal values), a compliant plane, RK4,
//! sensor noise, the press-and-circle scenario, the closed-loop run and the demo set-up.

pub mod contact;
pub mod demo;
pub mod noise;
pub mod plant;
pub mod presets;
pub mod report;
pub mod rk4;
pub mod run;
pub mod scenario;
pub mod true_joint_terms;

pub use contact::PlaneContact;
pub use demo::{Demo, DemoOptions, RunKind};
pub use noise::{Gaussian, NoiseConfig};
pub use plant::{Payload, Plant, PlantError, PlantState};
pub use presets::{start_posture, start_posture_for};
pub use report::{summary_table, write_csv};
pub use rk4::{rk4_step, RkState};
pub use run::{simulate, RunResult, RunStatus, Sample, SimConfig, Summary};
pub use scenario::PressAndCircle;
pub use true_joint_terms::JointTermFactors;
