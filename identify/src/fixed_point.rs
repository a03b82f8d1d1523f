//! The closed-loop estimators' iteration: simulate the identified model in the loop the robot
//! ran in, rebuild the regressor (or the torques' Jacobian) on the simulated motion, solve,
//! and again with the new estimate, until it stops moving.
//!
//! - **IDIM-IV** (Janot, Vandanjon, Gautier): the instruments are the base regressor of the
//!   simulated motion, `Z = Y_b(q_s, q̇_s, q̈_s)`, and each step solves
//!   `(Zᵀ Σ⁻¹ W) θ_b = Zᵀ Σ⁻¹ τ` with the measured regressor `W` ([`crate::instrumental`]),
//!   starting from the weighted least squares (from the description's values when the least
//!   squares' model diverges in the loop).
//! - **DIDIM** (Gautier, Janot, Vandanjon): closed-loop output error, by Gauss–Newton. The
//!   simulated loop's torques `τ_s(θ_b)` are the law's output along the model's own motion;
//!   each simulation also integrates their Jacobian `∂τ_s/∂θ_b` ([`crate::sensitivity`]), and
//!   each step is the weighted least squares of `τ − τ_s(θ₀) + J θ₀` on `J`: the motion's own
//!   sensitivity to `θ_b` included, so that the iteration settles at the output error's
//!   minimum (the classical step, `J = Y_b` of the simulated motion, settles elsewhere). It
//!   needs no measured velocity or acceleration: only the torques, the reference and the law.
//!   It starts from the description's values (from the least squares' when the description's
//!   model diverges in the loop).
//!
//! The step measure: the largest change of an unknown in units of its σ; the iteration has
//! converged when it is below [`CONVERGED`]. It diverges when the simulated loop does
//! ([`crate::closed_loop`]) from every start or at a later estimate, or when the step grows three times in a row while above one σ;
//! after [`MAX_ITERATIONS`] without converging it stops. All three are errors naming the
//! estimator and the last step.

use crate::closed_loop::{friction_damping, ControlLaw, Loop, Reference};
use crate::error::IdentifyError;
use crate::least_squares::BaseEstimate;
use crate::sensitivity::torque_sensitivities;
use dyngen_model::base_parameters::BaseParameterSet;
use dyngen_model::dynamics::NumericDynamics;
use dyngen_model::model::Model;
use nalgebra::DMatrix;
use std::fmt;

/// Converged: no unknown moved by more than this share of its σ in the last step (and no
/// joint's noise by more than the least squares' tolerance).
pub const CONVERGED: f64 = 0.05;
/// Simulations before an iteration that has not converged stops.
pub const MAX_ITERATIONS: usize = 30;

/// How a closed-loop estimate (IDIM-IV or DIDIM) was reached.
#[derive(Clone, Debug, PartialEq)]
pub struct ClosedLoopEstimate {
    /// The law the model was simulated with: the one given, or the stiff PD that tracked the
    /// measured positions.
    pub law: ControlLaw,
    /// Whether `law` is the stiff PD on the measured positions (no law was given).
    pub tracking_measured: bool,
    /// Where the iteration started.
    pub started_from: IterationStart,
    /// At each iteration, the largest change of an unknown, in units of its σ.
    pub steps: Vec<f64>,
    /// Per joint, the RMS difference between the last simulation's positions and the measured
    /// ones (rad or m): how closely the simulated loop reproduces the robot's.
    pub position_rms: Vec<f64>,
}

/// The law of the simulated loop.
pub(crate) enum LoopLaw {
    /// The robot's own.
    Given(ControlLaw),
    /// No law given: a stiff PD with the simulated model's gravity compensated, tracking the
    /// measured positions (see [`stiff_law`]).
    Stiff(ControlLaw),
}

/// The rows a simulation gives its estimator, besides the law's torques.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum SimulatedRows {
    /// `Y_b` of the simulated motion (IDIM-IV's instruments).
    Regressor,
    /// The law's torques' sensitivity `∂τ_s/∂θ_b`, integrated with the motion
    /// ([`crate::sensitivity`]): DIDIM's Gauss–Newton Jacobian.
    TorqueSensitivity,
}

/// What a simulation of the model gives the estimators, on the kept samples.
pub(crate) struct Simulated {
    /// The law simulated.
    pub law: ControlLaw,
    /// The rows the simulator was asked for ([`SimulatedRows`]), stacked (rows sample-major).
    pub rows: DMatrix<f64>,
    /// The law's torques along the simulated motion, stacked as `rows` (one column).
    pub torques: DMatrix<f64>,
    pub position_rms: Vec<f64>,
}

/// The model in the robot's loop, along the log.
pub(crate) struct Simulator<'a> {
    /// The description, its Coulomb friction smoothed ([`crate::closed_loop::smoothed`]) so
    /// that the integration step resolves it: what is simulated.
    pub model: Model,
    /// The description, its Coulomb friction smoothed only as much as keeps the regressor of
    /// the simulated motion continuous in the estimate: the regressor's friction column
    /// stays close to the robot's, and the iteration's map smooth.
    pub regressor: Model,
    pub base: &'a BaseParameterSet,
    pub law: LoopLaw,
    pub rows: SimulatedRows,
    pub reference: Reference,
    /// The times simulated, from the first sample simulated to the last kept.
    pub times: Vec<f64>,
    /// The log index of `times[0]`.
    pub first: usize,
    /// The state at `times[0]`.
    pub start: (Vec<f64>, Vec<f64>),
    /// The kept samples' log indices and measured positions.
    pub kept: &'a [usize],
    pub measured: &'a [Vec<f64>],
}

/// The stiff PD that tracks the measured positions when no law is given: natural frequency
/// `omega` (rad/s) on each joint of the model of `theta_b` taken alone (critically damped,
/// its gains from the model's mass-matrix diagonal at `q`), the model's gravity compensated.
/// Stiff for the model it tracks with, so that the simulated motion follows the measured one:
/// instruments that follow `W` closely (a loose loop, its lag `g/k_p` or `D q̈/k_p` of the
/// size of the motion, makes weak instruments whose estimate wanders from one iteration to
/// the next). Its gains are held through the iteration, so that the loop changes only with
/// the model.
pub(crate) fn stiff_law(
    model: &Model,
    base: &BaseParameterSet,
    theta_b: &[f64],
    q: &[f64],
    omega: f64,
) -> ControlLaw {
    let theta = standard_of(base, theta_b);
    let mass = NumericDynamics::with_parameters(model, &theta).mass_matrix(q);
    let inertia: Vec<f64> = (0..model.dof()).map(|j| mass[(j, j)].abs().max(1e-9)).collect();
    ControlLaw::critically_damped(&inertia, omega)
}

/// The standard parameters with `theta_b` on the base columns and 0 on the folded ones: the
/// same dynamics (see `BaseParameterSet::representative`).
pub(crate) fn standard_of(base: &BaseParameterSet, theta_b: &[f64]) -> Vec<f64> {
    let mut theta = vec![0.0; base.standard_count];
    for (&c, &v) in base.columns.iter().zip(theta_b) {
        theta[c] = v;
    }
    theta
}

impl Simulator<'_> {
    /// The loop with the model of `theta_b`; an error saying where it diverged.
    pub fn run(&self, theta_b: &[f64]) -> Result<Simulated, String> {
        let theta = standard_of(self.base, theta_b);
        let dynamics = NumericDynamics::with_parameters(&self.model, &theta);
        let law = match &self.law {
            LoopLaw::Given(law) | LoopLaw::Stiff(law) => law.clone(),
        };
        let closed = Loop {
            dynamics: &dynamics,
            law: &law,
            reference: &self.reference,
            quantum: None,
            gravity_compensation: matches!(self.law, LoopLaw::Stiff(_)),
            min_steps: 1,
        };
        let friction = friction_damping(&self.model, &theta);
        let run = closed.run(&self.times, &self.start.0, &self.start.1, &friction)?;
        let sensitivities = match self.rows {
            SimulatedRows::Regressor => Vec::new(),
            SimulatedRows::TorqueSensitivity => {
                torque_sensitivities(&dynamics, self.base, &law, &self.times, &run)?
            }
        };
        let at = |k: usize| k - self.first;
        let n = self.model.dof();
        let columns = NumericDynamics::new(&self.regressor);
        let mut rows = DMatrix::zeros(self.kept.len() * n, self.base.count());
        let mut torques = DMatrix::zeros(self.kept.len() * n, 1);
        for (i, &k) in self.kept.iter().enumerate() {
            let block = match self.rows {
                SimulatedRows::Regressor => {
                    let (q, qd, qdd) = (&run.q[at(k)], &run.qd[at(k)], &run.qdd[at(k)]);
                    self.base.base_regressor(&columns.regressor(q, qd, qd, qdd))
                }
                SimulatedRows::TorqueSensitivity => sensitivities[at(k)].clone(),
            };
            rows.rows_mut(i * n, n).copy_from(&block);
            for (j, t) in run.tau[at(k)].iter().enumerate() {
                torques[(i * n + j, 0)] = *t;
            }
        }
        let position_rms = (0..n)
            .map(|j| {
                let sum: f64 = self
                    .kept
                    .iter()
                    .zip(self.measured)
                    .map(|(&k, q)| (run.q[at(k)][j] - q[j]).powi(2))
                    .sum();
                (sum / self.kept.len() as f64).sqrt()
            })
            .collect();
        Ok(Simulated {
            law,
            rows,
            torques,
            position_rms,
        })
    }
}

/// Where an iteration started: the first of its starts whose simulated loop does not diverge.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum IterationStart {
    /// The weighted least squares on the measured regressor.
    LeastSquares,
    /// The description's own values.
    Description,
}

impl fmt::Display for IterationStart {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            IterationStart::LeastSquares => "the least squares' estimate",
            IterationStart::Description => "the description's values",
        })
    }
}

/// Iterates `solve` on the simulations of its own estimates, from the first of `starts`
/// (every unknown: the base parameters, the first `b`, then any of the torque channel) whose
/// loop does not diverge, and each joint's noise `noise`; `what` names the estimator in
/// errors. `solve` is given the simulation, the unknowns it was simulated with and the
/// noise. The least squares' estimate of a noisy log need not be physical, and a model
/// whose mass matrix is not positive along the motion can diverge in the loop where the
/// description does not; the fixed point does not depend on where it starts. `solve` weighs
/// the joints by the noise it is given and returns the noise its residuals show, so that
/// parameters and noise settle together. Returns the last estimate and how it was reached.
pub(crate) fn iterate(
    what: &str,
    starts: Vec<(IterationStart, Vec<f64>)>,
    mut noise: Vec<f64>,
    b: usize,
    simulator: &Simulator<'_>,
    mut solve: impl FnMut(&Simulated, &[f64], &[f64]) -> Result<BaseEstimate, IdentifyError>,
) -> Result<(BaseEstimate, ClosedLoopEstimate), IdentifyError> {
    let mut failures = Vec::new();
    let mut first = None;
    for (from, theta) in starts {
        match simulator.run(&theta[..b]) {
            Ok(simulated) => {
                first = Some((from, theta, simulated));
                break;
            }
            Err(e) => failures.push(format!("from {from}: {e}")),
        }
    }
    let Some((started_from, mut theta, mut simulated)) = first else {
        return Err(IdentifyError::Diverged(format!(
            "{what}: the closed loop simulated diverges ({}): the gains do not stabilise the model, \
             or the estimate is far from the robot",
            failures.join("; ")
        )));
    };
    let mut steps: Vec<f64> = Vec::new();
    loop {
        let estimate = solve(&simulated, &theta, &noise)?;
        let (k, step) = (0..theta.len())
            .map(|k| {
                let sigma = estimate.std_dev[k].max(1e-12 * estimate.theta_b[k].abs());
                (k, (estimate.theta_b[k] - theta[k]).abs() / sigma)
            })
            .max_by(|a, b| a.1.total_cmp(&b.1))
            .unwrap_or((0, 0.0));
        steps.push(step);
        let last_name = &estimate.names[k];
        theta.clone_from(&estimate.theta_b);
        noise.clone_from(&estimate.joint_noise);
        if step <= CONVERGED && estimate.noise_settled {
            let how = ClosedLoopEstimate {
                law: simulated.law,
                tracking_measured: matches!(simulator.law, LoopLaw::Stiff(_)),
                started_from,
                steps,
                position_rms: simulated.position_rms,
            };
            return Ok((estimate, how));
        }
        let growing = steps.len() >= 4 && steps[steps.len() - 4..].windows(2).all(|w| w[1] > w[0]);
        if growing && step > 1.0 {
            return Err(IdentifyError::Diverged(format!(
                "{what} diverges: its steps grow ({}σ, the last moving '{last_name}'): the simulated \
                 loop does not behave as the robot's (check the gains and the reference)",
                format_steps(&steps)
            )));
        }
        if steps.len() == MAX_ITERATIONS {
            return Err(IdentifyError::Diverged(format!(
                "{what} did not converge in {MAX_ITERATIONS} simulations (steps {}σ, the last moving \
                 '{last_name}'): the simulated loop does not settle on the robot's (check the gains \
                 and the reference)",
                format_steps(&steps)
            )));
        }
        simulated = simulator.run(&theta[..b]).map_err(|e| {
            IdentifyError::Diverged(format!(
                "{what}: the closed loop simulated with the estimate of iteration {} diverges ({e}): \
                 the gains do not stabilise the model, or the estimate is far from the robot",
                steps.len()
            ))
        })?;
    }
}

/// The last few steps, for a message.
fn format_steps(steps: &[f64]) -> String {
    let from = steps.len().saturating_sub(4);
    steps[from..]
        .iter()
        .map(|s| format!("{s:.3}"))
        .collect::<Vec<_>>()
        .join(", ")
}
