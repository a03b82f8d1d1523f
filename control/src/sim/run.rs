//! The closed loop: the plant integrated by RK4 at a fine step ([`Plant::step`]), the controller at its own rate
//! with sample-and-hold, optional sensor noise, a log, and divergence detection that stops the
//! run with the time and the reason and keeps the data logged so far.

use super::noise::{Gaussian, NoiseConfig};
use super::plant::{Plant, PlantState};
use super::scenario::PressAndCircle;
use crate::controller::orientation::orientation_angle;
use crate::controller::parameter_error_energy;
use crate::controller::{HybridController, Measurement};
use dyngen_runtime::{JointTrig, Parameterization};
use nalgebra::SVector;
use std::time::Instant;

/// Simulation settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SimConfig {
    /// Controller period (s): 1 ms.
    pub control_period: f64,
    /// RK4 steps of the plant per control period: 5 (5 kHz).
    pub substeps: usize,
    pub noise: Option<NoiseConfig>,
    pub seed: u64,
    /// The run is declared diverged above this joint speed (rad/s).
    pub max_joint_velocity: f64,
    /// … or above this contact force (N).
    pub max_force: f64,
}

impl Default for SimConfig {
    fn default() -> Self {
        SimConfig {
            control_period: 1e-3,
            substeps: 5,
            noise: None,
            seed: 0x5eed,
            max_joint_velocity: 20.0,
            max_force: 1000.0,
        }
    }
}

/// One logged control tick.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample {
    pub t: f64,
    /// Controlled force `F_t` as the controller saw it (N).
    pub force: f64,
    /// The true contact force along the normal (N, ≥ 0).
    pub true_force: f64,
    /// How deep the controlled frame's origin is inside the true surface (m; negative: its
    /// height above it). On a compliant plane `F / k`; on a rigid one at most the drift the
    /// Baumgarte terms pull back.
    pub penetration: f64,
    pub desired_force: f64,
    /// `F_t − F_d` from the true (noise-free) contact force (N).
    pub force_error: f64,
    /// `‖K⁻ (x_t − x_d)‖` from the true state (m).
    pub in_plane_error: f64,
    /// Angle between the actual and the desired orientation (or tool axis) from the true state
    /// (rad); `NaN` for the position task, which leaves the orientation free.
    pub orientation_error: f64,
    /// `‖J⁻ (q − q_ν)‖` (rad).
    pub null_error: f64,
    /// `V = ½ rᵀ D r + ½ θ̃ᵀ Γ⁻¹ θ̃` (the second term only when adapting, and over the adapted
    /// parameters, `Γᵢ > 0`).
    pub lyapunov: f64,
    /// `‖θ̂ − θ‖` in the parameterisation's coordinates.
    pub theta_error: f64,
    /// `‖θ̂_j − θ_j‖ / ‖θ_j‖` over the parameters made of joint terms only (friction, offset,
    /// and an armature no inertia combines with); `NaN` for a robot without them.
    pub joint_term_error: f64,
    /// `‖e‖`, the composite adaptation's prediction error (N·m; 0 for the other laws).
    pub prediction_error: f64,
    /// `max |τᵢ|` (N·m).
    pub tau_max: f64,
    /// Wall time of the control tick (ns).
    pub tick_ns: f64,
    /// Damping of the singularity guard.
    pub damping: f64,
    /// Stiffness in use by the controller (N/m).
    pub stiffness: f64,
}

/// How a run ended.
#[derive(Clone, Debug, PartialEq)]
pub enum RunStatus {
    Completed,
    Diverged { time: f64, reason: String },
}

/// The log of a run and how it ended.
#[derive(Clone, Debug)]
pub struct RunResult {
    pub samples: Vec<Sample>,
    pub status: RunStatus,
}

/// Figures over a time window of a run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Summary {
    pub rms_force_error: f64,
    pub rms_in_plane_error: f64,
    /// `NaN` for the position task.
    pub rms_orientation_error: f64,
    pub final_null_error: f64,
    pub max_tau: f64,
    pub median_tick_ns: f64,
}

impl RunResult {
    /// RMS errors over `t ≥ from`; max |τ| and tick time over the whole run.
    pub fn summary(&self, from: f64) -> Summary {
        let window: Vec<&Sample> = self.samples.iter().filter(|s| s.t >= from).collect();
        let n = window.len().max(1) as f64;
        let rms = |f: &dyn Fn(&Sample) -> f64| (window.iter().map(|s| f(s).powi(2)).sum::<f64>() / n).sqrt();
        let mut ticks: Vec<f64> = self.samples.iter().map(|s| s.tick_ns).collect();
        ticks.sort_by(f64::total_cmp);
        Summary {
            rms_force_error: if window.is_empty() {
                f64::NAN
            } else {
                rms(&|s| s.force_error)
            },
            rms_in_plane_error: if window.is_empty() {
                f64::NAN
            } else {
                rms(&|s| s.in_plane_error)
            },
            rms_orientation_error: if window.is_empty() {
                f64::NAN
            } else {
                rms(&|s| s.orientation_error)
            },
            final_null_error: self.samples.last().map_or(f64::NAN, |s| s.null_error),
            max_tau: self.samples.iter().map(|s| s.tau_max).fold(0.0, f64::max),
            median_tick_ns: ticks.get(ticks.len() / 2).copied().unwrap_or(f64::NAN),
        }
    }
}

/// 1 for each parameter of `Z` made of joint-level parameters only, else 0.
fn joint_term_mask<Z: Parameterization<N, M>, const N: usize, const M: usize>() -> SVector<f64, M> {
    let joint = Z::gain_by_kind(|kind| f64::from(u8::from(kind.is_joint_level())));
    let inertial = Z::gain_by_kind(|kind| f64::from(u8::from(!kind.is_joint_level())));
    joint.zip_map(&inertial, |j, i| f64::from(u8::from(j > 0.0 && i == 0.0)))
}

/// Runs the scenario from rest at `q0`. `progress` is called with the fraction done.
///
/// The plant touches the plane with the controller's controlled frame (the end-effector unless
/// chosen with [`HybridController::with_controlled_frame`]), whatever its own contact frame,
/// and the logged errors are those of that frame.
pub fn simulate<Z, const N: usize, const M: usize, const T: usize>(
    plant: &Plant<Z, N, M>,
    controller: &mut HybridController<Z, N, M, T>,
    scenario: &PressAndCircle<N>,
    q0: &SVector<f64, N>,
    config: &SimConfig,
    progress: &mut dyn FnMut(f64),
) -> RunResult
where
    Z: Parameterization<N, M>,
{
    // The contact and the logged errors at the frame the controller controls.
    let frame = *controller.frame();
    let plant = &plant.at_frame(frame);
    let dt = config.control_period;
    let steps = (scenario.duration() / dt).round() as usize;
    let h = dt / config.substeps.max(1) as f64;
    let theta_true = *plant.parameters();
    let mut rng = Gaussian::new(config.seed);
    let mut state = PlantState::at_rest(*q0);
    let mut samples = Vec::with_capacity(steps + 1);
    let task = controller.config().task;
    let gamma = controller.config().gains.gamma;
    let adapting = controller.config().adaptation.is_adapting();
    let joint_terms = joint_term_mask::<Z, N, M>();
    let joint_norm = theta_true.component_mul(&joint_terms).norm();
    let mut last_progress = 0;
    // The torque acting on the plant until this tick's takes over (sample and hold): the force
    // a sensor reads at the tick is the one under it (on a rigid plane the force depends on it).
    let mut held_tau = SVector::<f64, N>::zeros();

    let diverged = |samples: Vec<Sample>, time: f64, reason: String| RunResult {
        samples,
        status: RunStatus::Diverged { time, reason },
    };

    for step in 0..=steps {
        let t = step as f64 * dt;
        let trig = JointTrig::new(&state.q);
        let true_force = match plant.contact_force(&state, &held_tau) {
            Ok(f) => f,
            Err(e) => return diverged(samples, t, format!("plant: {e}")),
        };
        let mut m = Measurement {
            q: state.q,
            qd: state.qd,
            force: true_force,
        };
        if let Some(n) = config.noise {
            m.q += rng.vector::<N>(n.q);
            m.qd += rng.vector::<N>(n.qd);
            m.force += rng.vector::<3>(n.force);
        }
        let desired = scenario.desired(t);
        let theta_before = *controller.theta_hat();
        let start = Instant::now();
        let out = controller.tick(&m, &desired, dt);
        let tick_ns = start.elapsed().as_nanos() as f64;
        let out = match out {
            Ok(o) => o,
            Err(e) => return diverged(samples, t, format!("controller: {e}")),
        };

        // Logged errors from the true state (the controller's own are from noisy measurements).
        let pose = frame.pose::<Z::Robot>(&trig);
        let x_t = task.rotation * pose.translation;
        let f_true = (task.force_selection * (task.rotation * true_force))[0];
        let x_err = x_t - desired.position;
        let in_plane = (controller.split().k_minus.fixed_view::<3, 3>(0, 0) * x_err).norm();
        let orientation_error = orientation_angle(&task.orientation, &pose.rotation, &desired.orientation);
        let r = out.reference.r;
        let theta_err = theta_before - theta_true;
        let mut v = 0.5 * r.dot(&(plant.mass_matrix(&trig) * r));
        if adapting {
            v += parameter_error_energy(&theta_err, &gamma);
        }
        samples.push(Sample {
            t,
            force: out.reference.force[0],
            true_force: f_true,
            penetration: plant.contact.penetration(&pose.translation),
            desired_force: desired.force[0],
            force_error: if f_true > 0.0 {
                f_true - desired.force[0]
            } else {
                out.reference.force_error[0]
            },
            in_plane_error: in_plane,
            orientation_error,
            null_error: out.reference.null_error.norm(),
            lyapunov: v,
            theta_error: theta_err.norm(),
            joint_term_error: theta_err.component_mul(&joint_terms).norm() / joint_norm,
            prediction_error: out.prediction_error.norm(),
            tau_max: out.tau.amax(),
            tick_ns,
            damping: out.damping,
            stiffness: -controller.stiffness()[(0, 2)],
        });
        if step == steps {
            break;
        }

        // Plant: `substeps` steps with the torque held.
        held_tau = out.tau;
        for sub in 0..config.substeps.max(1) {
            let ts = t + sub as f64 * h;
            match plant.step(&state, &held_tau, h) {
                Ok(s) => state = s,
                Err(e) => return diverged(samples, ts, format!("plant: {e}")),
            }
        }
        let t_next = t + dt;
        if let Some((i, v)) = state
            .qd
            .iter()
            .enumerate()
            .find(|(_, v)| !(v.is_finite() && v.abs() <= config.max_joint_velocity))
        {
            return diverged(
                samples,
                t_next,
                format!(
                    "joint {} speed {v:.3e} rad/s exceeds {} rad/s",
                    i + 1,
                    config.max_joint_velocity
                ),
            );
        }
        let f = match plant.contact_force(&state, &held_tau) {
            Ok(f) => f.norm(),
            Err(e) => return diverged(samples, t_next, format!("plant: {e}")),
        };
        if !(f.is_finite() && f <= config.max_force) {
            return diverged(
                samples,
                t_next,
                format!("contact force {f:.3e} N exceeds {} N", config.max_force),
            );
        }
        let pct = (100 * step) / steps.max(1);
        if pct > last_progress {
            last_progress = pct;
            progress(step as f64 / steps as f64);
        }
    }
    progress(1.0);
    RunResult {
        samples,
        status: RunStatus::Completed,
    }
}
