//! dyngen's runtime: what generated robot code links against (the [`RobotDynamics`] trait and
//! [`JointTrig`]), and the controllers and simulator that are generic over any such robot.
//!
//! Invariant: this crate never depends on the generator; generated code depends only on this
//! crate and `nalgebra`.

mod robot;

pub use robot::{JointTrig, Pose, RobotDynamics};
pub use nalgebra;
