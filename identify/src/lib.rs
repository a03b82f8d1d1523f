//! Identification of a robot's dynamics with dyngen's regressor: from a description to an
//! excitation trajectory, from measured data to base parameters with uncertainties, a
//! physically consistent full parameter vector, and an identified description.
//!
//! The pipeline, one file per step:
//! 1. [`fourier`]: periodic finite-Fourier-series joint trajectories, scaled into the joint
//!    limits; [`excitation`]: their coefficients optimised for a well-conditioned stacked base
//!    regressor.
//! 2. [`data`]: the data CSV (time, joint positions and torques by joint name; velocities and
//!    accelerations optional), read with errors that name file, line and column;
//!    [`differentiate`]: zero-phase low-pass filter and central differences for the missing
//!    derivatives.
//! 3. [`observation`]: the base regressor stacked over the samples, in torque form
//!    (`v = q̇`, `a = q̈`), from the generic numeric dynamics of any description.
//! 4. [`least_squares`]: weighted least squares on the base parameters with per-parameter
//!    standard deviations, and the identifiability diagnosis.
//! 5. [`consistent`]: a physically consistent full θ (every body's pseudo-inertia positive
//!    definite, armature and friction non-negative) by a log-Cholesky parameterisation.
//! 6. [`describe`]: the identified robot as a dyngen YAML description; [`pipeline`]: all of
//!    it in one call.

pub mod consistent;
pub mod data;
pub mod describe;
pub mod differentiate;
pub mod error;
pub mod excitation;
pub mod fourier;
pub mod least_squares;
pub mod observation;
pub mod pipeline;
pub mod plot;
pub mod simulate;

pub use error::IdentifyError;
