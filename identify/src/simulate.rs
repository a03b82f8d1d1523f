//! A "real" robot for experiments and tests: a description plus a payload and realistic
//! joint friction and armature, measured along a trajectory with torque noise.

use crate::data::Samples;
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
