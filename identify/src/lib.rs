//! Identification of a robot's dynamics with dyngen's regressor: from a description to an
//! excitation trajectory, from measured data to base parameters with uncertainties, a
//! physically consistent full parameter vector, and an identified description.
//!
//! Every item is at the crate root; the pipeline, one private module per step:
//! 1. Excitation: [`FourierTrajectory`] (periodic finite Fourier series, scaled into
//!    [`TrajectoryLimits`]), its coefficients optimised by [`optimise`] for a well-conditioned
//!    stacked base regressor ([`condition_number`]); [`optimise_within`] also keeps frames in
//!    a [`Workspace`] (boxes and planes, [`Region`]), checked over the whole period.
//! 2. Data: [`read_csv`] reads the data CSV into [`Samples`] (time, joint positions and
//!    torques by joint name; velocities and accelerations optional), with errors that name
//!    file, line and column; [`to_csv`] writes one. [`prepare`] computes missing velocities and
//!    accelerations (zero-phase low-pass filter, central differences).
//! 3. Observation: the base regressor of a [`BaseRegressorSource`] (the generic numeric
//!    dynamics of any description, [`BaseModel`], or a compiled robot, [`Compiled`]), in
//!    torque form, stacked over the samples; or, without accelerations, the energy theorem or
//!    the Lagrange equations integrated over windows ([`Observation`]).
//! 4. Estimation: least squares on the base parameters weighted by each joint's noise, the
//!    noise re-estimated from the weighted residuals until it settles, with per-parameter
//!    standard deviations and covariance ([`BaseEstimate`]; [`BaseEstimate::trust`] flags the
//!    parameters whose relative σ is above a limit), or an [`IdentifyError::Unidentifiable`]
//!    that names the parameter the data cannot determine; then a physically consistent full θ as
//!    compatible with the data as the least squares allow ([`ConsistentEstimate`]: every
//!    body's pseudo-inertia positive definite with a margin, armature and friction positive,
//!    by a log-Cholesky parameterisation, from the best of several starts
//!    ([`ConsistentStart`]), made from the description with its bodies that no real body can
//!    be repaired first ([`Identification::notes`] says which)), with the σ of its base
//!    parameters by linearisation at the optimum.
//! 5. The identified robot as a dyngen YAML description ([`to_yaml`],
//!    [`Identification::yaml`]) or as a URDF with what URDF cannot say in a YAML wrapper beside
//!    it ([`to_urdf`], [`Identification::urdf`]), checked by loading it back: always one the loader accepts
//!    ([`WrittenEstimate`]), with warnings ([`Identification::warnings`]) when no consistent
//!    robot fits the data; [`identify`] runs all of it in one call.
//!
//! The torque channel is estimated with the parameters when asked: a delay behind the
//! positions, in whole samples or a fraction ([`IdentifyOptions::max_delay`],
//! [`IdentifyOptions::fractional_delay`], [`DelaySearch`]), and each joint's gain relative to
//! one joint's ([`IdentifyOptions::torque_gains`], [`TorqueGains`]).
//!
//! Closed-loop data: on a log taken under a controller, whose coarse encoders put noise in
//! the regressor and, through the controller, in the torques, [`Estimator::InstrumentalVariables`]
//! (IDIM-IV) and [`Estimator::Didim`] fit the parameters from a simulation of the identified
//! model in the robot's loop ([`ClosedLoop`]: the [`ControlLaw`] and the [`Reference`]),
//! iterated until it settles ([`ClosedLoopEstimate`]; DIDIM by Gauss–Newton). [`identify_base`] stops after the base
//! parameters, for comparisons and studies.
//!
//! Long logs: [`identify_file`] reads the data file one line at a time ([`SampleReader`]),
//! accumulates per-joint [`NormalEquations`] and computes missing derivatives window by window,
//! so memory does not grow with the log. Payloads: [`identify_payload`] identifies a tool or a
//! grasped object at a frame with the robot held, from joint torques, a force/torque sensor's
//! wrench (`fx … mz[<frame>]` columns), or both ([`PayloadEstimate`]).
//!
//! [`measure`], [`measure_closed_loop`], [`measure_wrench`], [`with_payload`], [`with_body_at`],
//! [`with_bodies_scaled`] and [`with_joint_terms`] simulate measurements of a "true" robot, for
//! tests and studies.

mod closed_loop;
mod consistent;
mod data;
mod delay;
mod describe;
mod differentiate;
mod energy;
mod error;
mod estimator;
mod excitation;
mod fixed_point;
mod fourier;
mod gains;
mod instrumental;
mod least_squares;
mod levenberg_marquardt;
mod loadable;
mod log_cholesky;
mod normal_equations;
mod objective;
mod observation;
mod payload;
mod physical_start;
mod pipeline;
mod sensitivity;
mod simulate;
mod starts;
mod streaming;
mod torque_channel;
mod urdf;
mod workspace;

pub use closed_loop::{ClosedLoop, ControlLaw, JointGains, Reference, DIVERGED};
pub use consistent::{pseudo_inertia_margins, ConsistentEstimate};
pub use data::{read_csv, to_csv, Sample, SampleReader, SampleWriter, Samples};
pub use delay::{DelaySearch, DELAY_MARGIN};
pub use describe::to_yaml;
pub use energy::{Observation, DEFAULT_WINDOW};
pub use error::{IdentifyError, Place};
pub use estimator::{BaseIdentification, Estimator, STIFF_PD_SHARE};
pub use excitation::{condition_number, optimise, optimise_within, Excitation, ExcitationOptions};
pub use fixed_point::{ClosedLoopEstimate, IterationStart, CONVERGED, MAX_ITERATIONS};
pub use fourier::{FourierTrajectory, JointSample, TrajectoryLimits, DEFAULT_ACCELERATION_PER_VELOCITY};
pub use least_squares::{BaseEstimate, Trust, DEFAULT_MAX_RELATIVE_STD};
pub use normal_equations::NormalEquations;
pub use observation::{prepare, BaseModel, BaseRegressorSource, Compiled, Prepared};
pub use payload::{
    identify_payload, PayloadData, PayloadEstimate, PayloadOptions, SourceCheck, DISAGREEMENT_LIMIT,
    SENSOR_MISFIT_LIMIT,
};
pub use pipeline::{
    identify, identify_base, identify_base_with, identify_file, identify_with, Identification,
    IdentifyOptions, WrittenEstimate,
};
pub use simulate::{
    measure, measure_closed_loop, measure_wrench, with_bodies_scaled, with_body_at, with_joint_terms,
    with_payload, Logging,
};
pub use starts::ConsistentStart;
pub use streaming::{estimate_streaming, Progress, StreamedEstimate};
pub use torque_channel::{TorqueGains, GAIN_UNDETERMINED};
pub use urdf::{to_urdf, wrapper_path, UrdfFiles};
pub use workspace::{ExcitationError, Region, Workspace, WorkspaceCheck, WorkspaceConstraint};
