//! The adaptive hybrid force/position controller for redundant manipulators
//! ([`controller`], `docs/controller.md`) and the simulator that shows it working ([`sim`]),
//! generic over any robot dyngen generates and over the parameterisation of its dynamics
//! ([`dyngen_runtime::Parameterization`]: `arm7::Base` or `arm7::Standard`).

pub mod controller;
mod mass_matrix;
pub mod sim;

pub use mass_matrix::mass_matrix_through_regressor;

/// The README's Rust examples, compiled and run as doctests of this crate (which has the
/// committed robots as a dev-dependency), so the README cannot drift from the API.
#[cfg(doctest)]
#[doc = include_str!("../../README.md")]
pub struct ReadmeDoctests;

/// This crate's README (the controller in a loop), checked the same way.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct CrateReadmeDoctests;
