//! The integration tests of `dyngen-cli`: one module per subject, in one test binary
//! (one link instead of one per file, one pool of test threads). A test that changes
//! process-wide state goes in a file of its own beside this directory.

mod common;

mod contacts;
mod excite_workspace;
mod frames;
mod gen;
mod identification;
mod identify_inputs;
mod inertia;
mod inspect;
mod payload;
mod usage;
