//! A "real" robot for experiments and tests: a description plus a payload and realistic
//! joint friction and armature, measured along a trajectory with torque noise, or run in a
//! closed loop and logged as a real controller's log is (encoders, a torque channel with
//! noise, a delay and a gain).

use crate::closed_loop::{friction_damping, ControlLaw, Loop, Reference};
use crate::data::Samples;
use crate::error::IdentifyError;
use crate::excitation::normal;
use crate::fourier::FourierTrajectory;
use dyngen_model::dynamics::NumericDynamics;
use dyngen_model::model::{Inertia, JointTermKind, JointTermValues, JointTerms, Model};
use dyngen_runtime::{ReferenceFrame, SplitMix64};
use nalgebra::{Matrix3, Vector3};

/// `model` with a point-like payload of `mass` kg (a solid sphere of radius `radius`) at
/// `offset` in the end-effector frame, welded to the body that carries the end-effector.
pub fn with_payload(model: &Model, mass: f64, offset: Vector3<f64>, radius: f64) -> Model {
    let payload = Inertia {
        mass,
        com: offset,
        inertia_com: Matrix3::identity() * (0.4 * mass * radius * radius),
    };
    with_body_at(model, &model.end_effector().name, &payload)
}

/// `model` with a rigid body of `inertia` (given in the coordinates of the frame named
/// `frame`) welded to the body that carries that frame. Panics when `model` has no such frame
/// (a simulation helper: the frame is the caller's own).
pub fn with_body_at(model: &Model, frame: &str, inertia: &Inertia) -> Model {
    let frame = model
        .frames()
        .iter()
        .find(|f| f.name == frame)
        .unwrap_or_else(|| panic!("no frame '{frame}'"));
    let mut bodies = model.bodies().to_vec();
    let body = crate::pipeline::carrier(frame);
    bodies[body].inertia = bodies[body]
        .inertia
        .merged(&inertia.transformed(&frame.placement));
    model
        .clone()
        .with_bodies(bodies)
        .expect("a payload keeps a model valid")
}

/// What a force/torque sensor at `frame` reads along `trajectory` (the samples of
/// [`measure`] at `duration` s and `rate` Hz) when `truth` is `held` plus what lies beyond the
/// sensor: the wrench the load applies to the sensor, `[f; m]` in the sensor frame, plus
/// Gaussian noise `noise` per axis and a constant `offset`. Computed from the two robots'
/// inverse dynamics (`τ_truth − τ_held = Jᵀ w`, `J` the frame's local Jacobian), not from a
/// body regressor, so it checks one.
#[allow(clippy::too_many_arguments)]
pub fn measure_wrench(
    held: &Model,
    truth: &Model,
    frame: &str,
    trajectory: &FourierTrajectory,
    duration: f64,
    rate: f64,
    noise: &[f64; 6],
    offset: &[f64; 6],
    seed: u64,
) -> Vec<[f64; 6]> {
    let (held_dynamics, truth_dynamics) = (NumericDynamics::new(held), NumericDynamics::new(truth));
    let mut rng = SplitMix64::new(seed);
    let count = (duration * rate).round() as usize;
    (0..count)
        .map(|k| {
            let s = trajectory.at(k as f64 / rate);
            let difference = truth_dynamics.inverse_dynamics(&s.q, &s.qd, &s.qdd)
                - held_dynamics.inverse_dynamics(&s.q, &s.qd, &s.qdd);
            let jacobian = held_dynamics
                .frame_motion(frame, &s.q, &s.qd)
                .unwrap_or_else(|| panic!("no frame '{frame}'"))
                .jacobian(ReferenceFrame::Local);
            let required = jacobian
                .transpose()
                .svd(true, true)
                .solve(&difference, 1e-12)
                .expect("an SVD solve");
            std::array::from_fn(|c| -required[c] + offset[c] + noise[c] * normal(&mut rng))
        })
        .collect()
}

/// `model` with body `b`'s mass and inertia `factors[b]` times the description's (its centre
/// of mass kept): a description off by as much.
pub fn with_bodies_scaled(model: &Model, factors: &[f64]) -> Model {
    let mut bodies = model.bodies().to_vec();
    for (body, &f) in bodies.iter_mut().zip(factors) {
        body.inertia.mass *= f;
        body.inertia.inertia_com *= f;
    }
    model
        .clone()
        .with_bodies(bodies)
        .expect("positive factors keep a model valid")
}

/// `model` with every joint-level column and the given values per joint.
pub fn with_joint_terms(model: &Model, values: &[JointTermValues], coulomb_smoothing: Option<f64>) -> Model {
    let terms = JointTerms {
        kinds: JointTermKind::ALL.to_vec(),
        coulomb_smoothing,
        values: values.to_vec(),
    };
    model
        .clone()
        .with_joint_terms(terms)
        .expect("physical joint values")
}

/// Samples of `truth` along `trajectory`: `duration` s at `rate` Hz, exact positions,
/// velocities and accelerations (`with_derivatives`; else positions only), torques from the
/// inverse dynamics plus Gaussian noise of standard deviation `noise[j]` (seeded).
pub fn measure(
    truth: &Model,
    trajectory: &FourierTrajectory,
    duration: f64,
    rate: f64,
    noise: &[f64],
    seed: u64,
    with_derivatives: bool,
) -> Samples {
    let dynamics = NumericDynamics::new(truth);
    let mut rng = SplitMix64::new(seed);
    let count = (duration * rate).round() as usize;
    let mut samples = Samples {
        qd: with_derivatives.then(Vec::new),
        qdd: with_derivatives.then(Vec::new),
        tau: Some(Vec::new()),
        ..Samples::default()
    };
    for k in 0..count {
        let t = k as f64 / rate;
        let s = trajectory.at(t);
        let tau = dynamics.inverse_dynamics(&s.q, &s.qd, &s.qdd);
        let tau: Vec<f64> = tau
            .iter()
            .zip(noise)
            .map(|(x, sd)| x + sd * normal(&mut rng))
            .collect();
        samples.time.push(t);
        samples.q.push(s.q);
        if let Some(v) = samples.qd.as_mut() {
            v.push(s.qd);
        }
        if let Some(v) = samples.qdd.as_mut() {
            v.push(s.qdd);
        }
        if let Some(v) = samples.tau.as_mut() {
            v.push(tau);
        }
    }
    samples
}

/// How the log of a simulated closed loop ([`measure_closed_loop`]) reads the robot.
#[derive(Clone, Debug, PartialEq)]
pub struct Logging {
    /// Encoders of this many bits per turn: positions (in the log and as the controller sees
    /// them) rounded to `2π/2^bits`; `None`: exact.
    pub encoder_bits: Option<u32>,
    /// Standard deviation of the Gaussian noise on each joint's logged torque.
    pub torque_noise: Vec<f64>,
    /// Samples the torque channel lags the positions (any fraction): the torques logged on a
    /// line are those of that much earlier.
    pub torque_delay: f64,
    /// Each joint's torque channel reads this many times the torque (1 when empty).
    pub torque_gain: Vec<f64>,
    pub seed: u64,
}

/// Integration steps between output times of a "real" robot, at least: its positions and
/// torques are those of the continuous loop to far below any noise.
const TRUTH_STEPS: usize = 8;

/// `truth` run by `law` along `trajectory` (starting on it, at rest in the integral),
/// `duration` s logged at `rate` Hz as [`Logging`] says: positions and torques (no
/// velocities or accelerations); and the reference at the log's times. The torques logged
/// are the law's (what the drives applied), read through the torque channel.
pub fn measure_closed_loop(
    truth: &Model,
    law: &ControlLaw,
    trajectory: &FourierTrajectory,
    duration: f64,
    rate: f64,
    logging: &Logging,
) -> Result<(Samples, Reference), IdentifyError> {
    let count = (duration * rate).round() as usize;
    let delay = logging.torque_delay;
    if !(delay.is_finite() && delay >= 0.0) {
        return Err(IdentifyError::data(format!("a torque delay of {delay} samples")));
    }
    // Times in samples: the log's, and the torques' `delay` earlier; the loop starts before
    // the first of them.
    let mut at: Vec<f64> = (0..count).flat_map(|k| [k as f64, k as f64 - delay]).collect();
    let start = -(delay.ceil() + 1.0);
    at.push(start);
    at.sort_by(f64::total_cmp);
    at.dedup_by(|a, b| (*a - *b).abs() < 1e-9);
    let times: Vec<f64> = at.iter().map(|s| s / rate).collect();
    let reference = Reference::from_trajectory(trajectory, &times);
    let dynamics = NumericDynamics::new(truth);
    let quantum = logging
        .encoder_bits
        .map(|bits| 2.0 * std::f64::consts::PI / 2f64.powi(bits as i32));
    let closed = Loop {
        dynamics: &dynamics,
        law,
        reference: &reference,
        quantum,
        gravity_compensation: false,
        min_steps: TRUTH_STEPS,
    };
    let first = trajectory.at(times[0]);
    let run = closed
        .run(
            &times,
            &first.q,
            &first.qd,
            &friction_damping(truth, &truth.parameters()),
        )
        .map_err(|e| IdentifyError::data(format!("the simulated robot diverged: {e}")))?;
    let index = |s: f64| at.partition_point(|&x| x < s - 1e-9);
    let mut rng = SplitMix64::new(logging.seed);
    let mut samples = Samples {
        tau: Some(Vec::with_capacity(count)),
        ..Samples::default()
    };
    for k in 0..count {
        let q = &run.q[index(k as f64)];
        let tau = &run.tau[index(k as f64 - delay)];
        samples.time.push(k as f64 / rate);
        samples.q.push(match quantum {
            Some(step) => q.iter().map(|v| (v / step).round() * step).collect(),
            None => q.clone(),
        });
        let logged = tau
            .iter()
            .enumerate()
            .map(|(j, t)| {
                let gain = logging.torque_gain.get(j).copied().unwrap_or(1.0);
                gain * t + logging.torque_noise.get(j).copied().unwrap_or(0.0) * normal(&mut rng)
            })
            .collect();
        samples.tau.as_mut().expect("made with torques").push(logged);
    }
    let log_times = samples.time.clone();
    Ok((samples, Reference::from_trajectory(trajectory, &log_times)))
}
