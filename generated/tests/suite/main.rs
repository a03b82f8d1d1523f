//! The integration tests of `dyngen-generated`: one module per subject, in one test binary
//! (one link instead of one per file, one pool of test threads). A test that changes
//! process-wide state goes in a file of its own beside this directory.

mod base_regressor;
mod free_motion_energy;
mod generated_code;
mod generated_contact_system;
mod generated_contacts;
mod generated_floating;
mod generated_forward_dynamics;
mod generated_frames;
mod generated_fresh;
mod generated_version_check;
mod operational_space;
mod result_buffers;
