//! The integration tests of `dyngen-control`: one module per subject, in one test binary
//! (one link instead of one per file, one pool of test threads). A test that changes
//! process-wide state goes in a file of its own beside this directory.

mod bad_input;
mod closed_loop_thresholds;
mod controlled_frame;
mod lyapunov;
mod noise_and_estimation;
mod plant_forward_dynamics;
mod plant_regressor;
mod reference_derivative;
mod rigid_plane_closed_loop;
mod rigid_plane_dynamics;
mod rigid_plane_impact;
mod rigid_plane_stiffness_limit;
mod task_and_gains;
