//! The integration tests of `dyngen-downstream-example`: one module per subject, in one test binary
//! (one link instead of one per file, one pool of test threads). A test that changes
//! process-wide state goes in a file of its own beside this directory.

mod against_pinocchio;
mod build_script;
mod c_library;
mod chunked_code;
mod floating_base;
mod floating_couplings;
mod generated_crate;
mod mimic_joints;
mod no_std;
mod publishable;
