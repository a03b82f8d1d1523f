//! Simulation of the controller in contact: the true plant (generated dynamics with the true
//! parameters through the regressor, plus an unmodelled payload and, for robots with
//! joint-level columns, friction and armature off their nominal values), a compliant or rigid plane, RK4,
//! sensor noise, the press-and-circle scenario, the closed-loop run and the demo set-up.

mod contact;
mod demo;
mod noise;
mod plant;
mod presets;
mod report;
mod rigid_force_loop;
mod rigid_plane;
mod rk4;
mod run;
mod scenario;
mod surface;
mod true_joint_terms;

pub use contact::PlaneContact;
pub use demo::{Demo, DemoOptions, RunKind};
pub use noise::{Gaussian, NoiseConfig};
pub use plant::{Payload, Plant, PlantError, PlantState};
pub use presets::{start_posture, start_posture_for};
pub use report::{summary_table, write_csv};
pub use rigid_plane::RigidPlane;
pub use rk4::{rk4_step, RkState};
pub use run::{simulate, RunResult, RunStatus, Sample, SimConfig, Summary};
pub use scenario::PressAndCircle;
pub use surface::{Surface, SurfaceKind};
pub use true_joint_terms::JointTermFactors;
