//! The closed loop a robot was measured in, and its simulation with a model: what the
//! instrumental-variable and output-error estimators ([`Estimator`](crate::Estimator)) rest on.
//!
//! A robot is identified while a controller makes it follow a reference; the torques logged
//! are that controller's output. Given the law and the reference, the same loop run on a
//! model gives noise-free positions, velocities and accelerations (and the torques the model
//! would have needed), from which nothing of the measurement noise leaks back.
//!
//! - The law, per joint: `τ = k_p e + k_d ė + k_i ∫e`, `e = q_r − q` ([`ControlLaw`]). It is
//!   evaluated continuously (a controller running far faster than the log); a law with an
//!   integral term starts its integral at zero at the first sample simulated.
//! - The reference ([`Reference`]): positions and velocities at sample times, between them the
//!   cubic Hermite curve through both (exact for cubics; a smooth reference sampled at a
//!   hundred times its band is within 10⁻⁸ of itself).
//! - The simulation: the forward dynamics of the model (`NumericDynamics`, armature and
//!   friction included) under the law, by fourth-order Runge–Kutta, each interval between
//!   output times in the same power of two of steps, small against the loop's fastest
//!   oscillation and decay at the start and at postures along the reference
//!   ([`STEP_PER_PERIOD`] of the period over 2π, [`STEP_PER_DECAY`] of the time constant,
//!   from the eigenvalues of `D⁻¹ K_p` and `D⁻¹ (K_d + friction slope)`): accurate to far
//!   below the noise, and stable. A power of two, so that models near each other take the
//!   same steps and their simulations differ smoothly.
//! - Divergence: a state that is not finite, or a joint more than [`DIVERGED`] (rad or m) off
//!   its reference, stops the simulation with the time and the joint.

use crate::data::Samples;
use crate::differentiate::differences;
use crate::error::IdentifyError;
use crate::fourier::FourierTrajectory;
use dyngen_model::dynamics::NumericDynamics;
use dyngen_model::model::{JointTermKind, JointTerms, Model};
use nalgebra::DMatrix;

/// One joint's gains: `τ = kp (q_r − q) + kd (q̇_r − q̇) + ki ∫(q_r − q) dt`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JointGains {
    /// N·m/rad (N/m for a prismatic joint).
    pub kp: f64,
    /// N·m·s/rad.
    pub kd: f64,
    /// N·m/(rad·s); 0 for a PD law.
    pub ki: f64,
}

/// The control law the robot was run with: a PID (or PD) per joint, in joint order.
#[derive(Clone, Debug, PartialEq)]
pub struct ControlLaw {
    pub gains: Vec<JointGains>,
}

/// The reference the controller tracked, at sample times.
#[derive(Clone, Debug, PartialEq)]
pub struct Reference {
    pub time: Vec<f64>,
    pub q: Vec<Vec<f64>>,
    pub qd: Vec<Vec<f64>>,
}

/// The closed loop a robot was measured in: the law and the reference it tracked.
#[derive(Clone, Debug, PartialEq)]
pub struct ClosedLoop {
    pub law: ControlLaw,
    pub reference: Reference,
}

/// A joint this far (rad or m) from its reference is not tracking it: the loop diverged.
pub const DIVERGED: f64 = 1.0;
/// The integration step, at most this many radians of the loop's fastest oscillation: its
/// error per period is then below 10⁻⁴ of its amplitude.
const STEP_PER_PERIOD: f64 = 0.25;
/// The integration step, at most this share of the loop's fastest decay (the damping and the
/// friction's slope): well inside the method's stability (2.78), and a decaying motion needs
/// no more accuracy than that.
const STEP_PER_DECAY: f64 = 1.0;
/// Postures along the reference at which the step is made small enough for the loop (a joint's
/// inertia changes with the posture, and with it how fast the loop is).
const POSTURES: usize = 8;
/// Integration steps between two output times, at most: a loop stiffer than this resolves is
/// integrated as far as it goes, and diverges if it must.
const MAX_STEPS: usize = 1 << 10;

impl ControlLaw {
    /// A PD law with these gains per joint.
    pub fn pd(kp: &[f64], kd: &[f64]) -> ControlLaw {
        ControlLaw {
            gains: kp
                .iter()
                .zip(kd)
                .map(|(&kp, &kd)| JointGains { kp, kd, ki: 0.0 })
                .collect(),
        }
    }

    /// A critically damped PD whose loop has the natural frequency `omega` (rad/s) on a joint
    /// whose diagonal of the mass matrix is `inertia[j]` (each joint taken alone).
    pub fn critically_damped(inertia: &[f64], omega: f64) -> ControlLaw {
        let kp: Vec<f64> = inertia.iter().map(|m| m * omega * omega).collect();
        let kd: Vec<f64> = inertia.iter().map(|m| 2.0 * m * omega).collect();
        ControlLaw::pd(&kp, &kd)
    }

    /// The law checked against the robot: one set of gains per joint, finite, `kp > 0`,
    /// `kd, ki ≥ 0`.
    pub(crate) fn check(&self, model: &Model) -> Result<(), IdentifyError> {
        let joints = model.joints();
        if self.gains.len() != joints.len() {
            let missing: Vec<&str> = joints
                .iter()
                .skip(self.gains.len())
                .map(|j| j.name.as_str())
                .collect();
            return Err(IdentifyError::data(if missing.is_empty() {
                format!(
                    "the control law has gains for {} joints, the robot has {}",
                    self.gains.len(),
                    joints.len()
                )
            } else {
                format!(
                    "the control law has no gains for joint{} {} (every joint needs kp and kd)",
                    if missing.len() > 1 { "s" } else { "" },
                    missing.join(", ")
                )
            }));
        }
        for (g, joint) in self.gains.iter().zip(joints) {
            let ok = g.kp.is_finite()
                && g.kd.is_finite()
                && g.ki.is_finite()
                && g.kp > 0.0
                && g.kd >= 0.0
                && g.ki >= 0.0;
            if !ok {
                return Err(IdentifyError::data(format!(
                    "joint '{}': gains kp {}, kd {}, ki {}: kp must be positive, kd and ki not negative",
                    joint.name, g.kp, g.kd, g.ki
                )));
            }
        }
        Ok(())
    }

    /// The torques at error `e`, its rate `ed` and its integral `z`.
    fn torque(&self, e: &[f64], ed: &[f64], z: &[f64]) -> Vec<f64> {
        self.gains
            .iter()
            .enumerate()
            .map(|(j, g)| g.kp * e[j] + g.kd * ed[j] + g.ki * z[j])
            .collect()
    }
}

impl Reference {
    /// The reference of a data file or an excitation (`dyngen excite`'s CSV): its times,
    /// positions and velocities (by central differences when the file has none: a reference
    /// is exact, there is nothing to filter).
    pub fn from_samples(samples: &Samples) -> Result<Reference, IdentifyError> {
        let located = |e: IdentifyError| samples.locate(e);
        if samples.len() < 3 {
            return Err(located(IdentifyError::data(format!(
                "a reference of {} samples: at least 3 are needed",
                samples.len()
            ))));
        }
        let qd = match &samples.qd {
            Some(qd) => qd.clone(),
            None => {
                let n = samples.q[0].len();
                let mut qd = vec![vec![0.0; n]; samples.len()];
                for j in 0..n {
                    let x: Vec<f64> = samples.q.iter().map(|r| r[j]).collect();
                    for (k, v) in differences(&samples.time, &x).0.into_iter().enumerate() {
                        qd[k][j] = v;
                    }
                }
                qd
            }
        };
        Ok(Reference {
            time: samples.time.clone(),
            q: samples.q.clone(),
            qd,
        })
    }

    /// `trajectory` sampled at `times`.
    pub fn from_trajectory(trajectory: &FourierTrajectory, times: &[f64]) -> Reference {
        let samples: Vec<_> = times.iter().map(|&t| trajectory.at(t)).collect();
        Reference {
            time: times.to_vec(),
            q: samples.iter().map(|s| s.q.clone()).collect(),
            qd: samples.iter().map(|s| s.qd.clone()).collect(),
        }
    }

    /// Whether the reference covers `[from, to]` (to a thousandth of its step).
    pub(crate) fn covers(&self, from: f64, to: f64) -> Result<(), String> {
        let (first, last) = (self.time[0], self.time[self.time.len() - 1]);
        let slack = 1e-3 * (last - first) / (self.time.len() - 1) as f64;
        if from < first - slack || to > last + slack {
            return Err(format!(
                "the reference covers {first} s to {last} s, the data {from} s to {to} s: \
                 the reference must cover the whole log"
            ));
        }
        Ok(())
    }

    /// Positions and velocities at `t` (held at the ends outside the samples).
    pub(crate) fn at(&self, t: f64) -> (Vec<f64>, Vec<f64>) {
        let last = self.time.len() - 1;
        let k = self.time.partition_point(|&s| s <= t).clamp(1, last) - 1;
        let h = self.time[k + 1] - self.time[k];
        let s = ((t - self.time[k]) / h).clamp(0.0, 1.0);
        let (s2, s3) = (s * s, s * s * s);
        let (h00, h10, h01, h11) = (
            2.0 * s3 - 3.0 * s2 + 1.0,
            s3 - 2.0 * s2 + s,
            -2.0 * s3 + 3.0 * s2,
            s3 - s2,
        );
        let (d00, d10, d01, d11) = (
            6.0 * s2 - 6.0 * s,
            3.0 * s2 - 4.0 * s + 1.0,
            -6.0 * s2 + 6.0 * s,
            3.0 * s2 - 2.0 * s,
        );
        let (q0, q1, v0, v1) = (&self.q[k], &self.q[k + 1], &self.qd[k], &self.qd[k + 1]);
        let q = (0..q0.len())
            .map(|j| h00 * q0[j] + h10 * h * v0[j] + h01 * q1[j] + h11 * h * v1[j])
            .collect();
        let qd = (0..q0.len())
            .map(|j| (d00 * q0[j] + d01 * q1[j]) / h + d10 * v0[j] + d11 * v1[j])
            .collect();
        (q, qd)
    }
}

/// Each joint's friction as a damping (N·m·s/rad) in the model of `theta`: its viscous friction
/// and its smoothed Coulomb friction's slope at rest, `f_c/ε` (none without smoothing: a
/// step, which no step size resolves).
pub(crate) fn friction_damping(model: &Model, theta: &[f64]) -> Vec<f64> {
    let smoothing = model.joint_terms().coulomb_smoothing;
    model
        .joint_term_values_from(theta)
        .iter()
        .map(|v| v.viscous.abs() + smoothing.map_or(0.0, |e| v.coulomb.abs() / e))
        .collect()
}

/// `model` with its Coulomb friction smoothed over at least `smoothing` (rad/s): a sign that
/// flips within one integration step makes a simulation, and all that is fitted to it, jump
/// with the model. Unchanged without a Coulomb column.
pub(crate) fn smoothed(model: &Model, smoothing: f64) -> Model {
    let terms = model.joint_terms();
    if !terms.kinds.contains(&JointTermKind::Coulomb) {
        return model.clone();
    }
    let wider = terms.coulomb_smoothing.map_or(smoothing, |e| e.max(smoothing));
    model
        .clone()
        .with_joint_terms(JointTerms {
            coulomb_smoothing: Some(wider),
            ..terms.clone()
        })
        .expect("a positive smoothing keeps a model valid")
}

/// A simulated run at the output times: the state, the acceleration and the law's torques;
/// and the integration steps taken between two output times.
#[derive(Clone, Debug)]
pub(crate) struct Run {
    pub q: Vec<Vec<f64>>,
    pub qd: Vec<Vec<f64>>,
    pub qdd: Vec<Vec<f64>>,
    pub tau: Vec<Vec<f64>>,
    pub steps: usize,
}

/// The loop's state: positions, velocities, the integral of the error.
#[derive(Clone)]
struct State {
    q: Vec<f64>,
    qd: Vec<f64>,
    z: Vec<f64>,
}

/// The loop of `law` tracking `reference` on `dynamics`.
pub(crate) struct Loop<'a> {
    pub dynamics: &'a NumericDynamics<'a>,
    pub law: &'a ControlLaw,
    pub reference: &'a Reference,
    /// The position the law sees rounded to this quantum (an encoder), when given.
    pub quantum: Option<f64>,
    /// Whether the law adds the simulated model's own gravity torques (the stiff PD that
    /// tracks measured positions does: [`crate::Estimator::InstrumentalVariables`]).
    pub gravity_compensation: bool,
    /// Integration steps between two output times, at least (a "real" robot is integrated
    /// finer than a model needs).
    pub min_steps: usize,
}

impl Loop<'_> {
    /// The law's torques and the state's rate at time `t`.
    fn rate(&self, t: f64, x: &State) -> (Vec<f64>, State) {
        let (qr, qdr) = self.reference.at(t);
        let seen: Vec<f64> = match self.quantum {
            Some(step) => x.q.iter().map(|q| (q / step).round() * step).collect(),
            None => x.q.clone(),
        };
        let e: Vec<f64> = qr.iter().zip(&seen).map(|(r, q)| r - q).collect();
        let ed: Vec<f64> = qdr.iter().zip(&x.qd).map(|(r, v)| r - v).collect();
        let mut tau = self.law.torque(&e, &ed, &x.z);
        if self.gravity_compensation {
            let g = self.dynamics.gravity_torque(&x.q);
            tau.iter_mut().zip(g.iter()).for_each(|(t, g)| *t += g);
        }
        let qdd = self.dynamics.forward_dynamics(&x.q, &x.qd, &tau);
        let rate = State {
            q: x.qd.clone(),
            qd: qdd.as_slice().to_vec(),
            z: e,
        };
        (tau, rate)
    }

    /// The loop from `q0, qd0` at `times[0]` (integral zero), at every one of `times` (at
    /// least two), with joint friction damping `friction` ([`friction_damping`]); an error
    /// naming the time and the joint when it diverges.
    pub fn run(&self, times: &[f64], q0: &[f64], qd0: &[f64], friction: &[f64]) -> Result<Run, String> {
        let n = q0.len();
        let longest = times.windows(2).map(|w| w[1] - w[0]).fold(0.0, f64::max);
        // The postures the loop passes through: how fast it is changes with the mass matrix.
        let postures = (0..POSTURES).map(|i| {
            self.reference
                .at(times[0] + (times[times.len() - 1] - times[0]) * i as f64 / POSTURES as f64)
                .0
        });
        let step = std::iter::once(q0.to_vec())
            .chain(postures)
            .map(|q| self.largest_step(&q, friction))
            .fold(f64::INFINITY, f64::min);
        let steps = (longest / step)
            .ceil()
            .max(self.min_steps as f64)
            .min(MAX_STEPS as f64) as usize;
        let steps = steps.next_power_of_two();
        let mut x = State {
            q: q0.to_vec(),
            qd: qd0.to_vec(),
            z: vec![0.0; n],
        };
        let mut run = Run {
            q: Vec::with_capacity(times.len()),
            qd: Vec::with_capacity(times.len()),
            qdd: Vec::with_capacity(times.len()),
            tau: Vec::with_capacity(times.len()),
            steps,
        };
        let axpy = |x: &State, a: f64, d: &State| State {
            q: x.q.iter().zip(&d.q).map(|(u, v)| u + a * v).collect(),
            qd: x.qd.iter().zip(&d.qd).map(|(u, v)| u + a * v).collect(),
            z: x.z.iter().zip(&d.z).map(|(u, v)| u + a * v).collect(),
        };
        for (k, &t) in times.iter().enumerate() {
            let (tau, rate) = self.rate(t, &x);
            self.check(t, &x, &rate)?;
            run.q.push(x.q.clone());
            run.qd.push(x.qd.clone());
            run.qdd.push(rate.qd.clone());
            run.tau.push(tau);
            let Some(&next) = times.get(k + 1) else { break };
            let h = (next - t) / steps as f64;
            let mut first = Some(rate);
            for s in 0..steps {
                let ts = t + s as f64 * h;
                let k1 = first.take().unwrap_or_else(|| self.rate(ts, &x).1);
                let k2 = self.rate(ts + 0.5 * h, &axpy(&x, 0.5 * h, &k1)).1;
                let k3 = self.rate(ts + 0.5 * h, &axpy(&x, 0.5 * h, &k2)).1;
                let k4 = self.rate(ts + h, &axpy(&x, h, &k3)).1;
                let sum = |f: fn(&State) -> &Vec<f64>| -> Vec<f64> {
                    (0..n)
                        .map(|j| (f(&k1)[j] + 2.0 * f(&k2)[j] + 2.0 * f(&k3)[j] + f(&k4)[j]) / 6.0)
                        .collect()
                };
                let d = State {
                    q: sum(|s| &s.q),
                    qd: sum(|s| &s.qd),
                    z: sum(|s| &s.z),
                };
                x = axpy(&x, h, &d);
            }
        }
        Ok(run)
    }

    /// The largest integration step at `q`, with the joints' friction damping `friction`:
    /// [`STEP_PER_PERIOD`] of the fastest oscillation's period over 2π and [`STEP_PER_DECAY`]
    /// of the fastest decay's time constant of the loop linearised there, `D q̈ = −K_p e −
    /// (K_d + F) ė`: the largest eigenvalues of `D⁻¹ K_p` (its square root) and of
    /// `D⁻¹ (K_d + F)`. (The joints taken alone, `k/D_jj`, miss how the joints load each
    /// other: a light wrist coupled to its neighbours moves faster than its diagonal says.)
    fn largest_step(&self, q: &[f64], friction: &[f64]) -> f64 {
        let d = self.dynamics.mass_matrix(q);
        let Some(inverse) = d.cholesky().map(|c| c.inverse()) else {
            // Not positive definite: the model has no motion to resolve, and the simulation
            // stops at the first state that is not finite.
            return f64::INFINITY;
        };
        // The largest eigenvalue of `D⁻¹ K` for diagonal `K ≥ 0`: that of the symmetric
        // `K^½ D⁻¹ K^½`.
        let fastest = |k: &dyn Fn(usize) -> f64| {
            let root: Vec<f64> = (0..inverse.nrows()).map(|j| k(j).max(0.0).sqrt()).collect();
            let scaled = DMatrix::from_fn(inverse.nrows(), inverse.ncols(), |i, j| {
                root[i] * inverse[(i, j)] * root[j]
            });
            scaled.symmetric_eigenvalues().max()
        };
        let gains = &self.law.gains;
        let oscillation = fastest(&|j| gains[j].kp).sqrt();
        let decay = fastest(&|j| gains[j].kd + friction[j]);
        (STEP_PER_PERIOD / oscillation).min(STEP_PER_DECAY / decay)
    }

    /// An error when the state at `t` is not finite or a joint is [`DIVERGED`] off its
    /// reference.
    fn check(&self, t: f64, x: &State, rate: &State) -> Result<(), String> {
        let (qr, _) = self.reference.at(t);
        let names = self.dynamics.model.joints();
        for j in 0..x.q.len() {
            let finite = x.q[j].is_finite() && x.qd[j].is_finite() && rate.qd[j].is_finite();
            let off = (x.q[j] - qr[j]).abs();
            if !finite || off > DIVERGED {
                return Err(format!(
                    "at t = {t:.3} s joint '{}' is {} its reference",
                    names[j].name,
                    if finite {
                        format!("{off:.3} off")
                    } else {
                        "not a finite number, far from".to_string()
                    }
                ));
            }
        }
        Ok(())
    }
}
