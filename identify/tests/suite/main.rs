//! The integration tests of `dyngen-identify`: one module per subject, in one test binary
//! (one link instead of one per file, one pool of test threads). A test that changes
//! process-wide state goes in a file of its own beside this directory.

mod common;

mod bad_input;
mod closed_loop;
mod delay;
mod energy;
mod estimation;
mod excitation;
mod industrial;
mod non_physical_description;
mod payload;
mod streaming;
mod torque_channel;
mod uncertainty;
mod urdf_output;
mod workspace;
