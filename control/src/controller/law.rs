//! The control law: `τ = Jᵀ F̄ + Y(q, q̇, q̇_r, q̈_r) θ̂ − G r` (eq. 42), with `θ̂̇ = −Γ Yᵀ r`
//! (eq. 46) when adapting, or the composite `θ̂̇ = −Γ (Yᵀ r + Wᵀ R e)`. With `θ̂` fixed at the
//! true parameters this is the known-parameter law of Lemma 1 (`Y θ = D q̈_r + C q̇_r + g` by
//! linearity).

use super::adaptation::rate_from_regressor_product;
use super::composite::{
    composite_product, implicit_step, prediction_signals, Composite, FilterStep, PredictionFilter,
    PredictionSignals,
};
use super::error::{ConfigError, TickError};
use super::frame::ControlledFrame;
use super::gains::Gains;
use super::matvec;
use super::orientation::{orientation_angle, OrientationRows};
use super::projections::{smallest_singular, Projections, SingularityGuard};
use super::reference::{reference, Desired, Measurement, Reference, ReferenceGains};
use super::stiffness_estimator::StiffnessEstimator;
use super::task::{ContactTask, Orientation, Split};
use dyngen_runtime::{FrameKinematics, JointTrig, Parameterization, Pose};
use nalgebra::{SMatrix, SVector, Vector3};
use std::marker::PhantomData;

/// The largest angle (degrees) between the start orientation and the desired one that the
/// set-up accepts (the rotation error of the orientation rows of an [`Orientation`] task).
pub const MAX_START_ORIENTATION_ERROR_DEG: f64 = 90.0;

/// How `θ̂` moves.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Adaptation {
    /// `θ̂̇ = −Γ Yᵀ r` (Slotine–Li, the note's eq. 46).
    On,
    /// `θ̂̇ = −Γ (Yᵀ r + Wᵀ R e)`: also down the prediction error of the filtered joint torque
    /// (see [`Composite`]).
    Composite(Composite),
    /// `θ̂` stays at `θ̂(0)`.
    Off,
}

impl Adaptation {
    /// Whether `θ̂` moves at all.
    pub fn is_adapting(&self) -> bool {
        !matches!(self, Adaptation::Off)
    }
}

/// Everything the controller is configured with.
#[derive(Clone, Copy, Debug)]
pub struct ControllerConfig<const N: usize, const M: usize, const T: usize = 3, const S: usize = 1> {
    pub gains: Gains<N, M>,
    pub task: ContactTask<T, S>,
    pub guard: SingularityGuard,
    /// Per-joint torque limit (N·m): the torque is clamped to `±limit` (a guard, not part of
    /// the law; saturation voids the Lyapunov argument while it lasts).
    pub torque_limit: SVector<f64, N>,
    pub adaptation: Adaptation,
    /// `θ̂(0)`, in the parameterisation's own coordinates.
    pub theta_hat0: SVector<f64, M>,
}

/// Output of one evaluation of the law.
#[derive(Clone, Copy, Debug)]
pub struct ControlOutput<const N: usize, const M: usize, const S: usize> {
    pub tau: SVector<f64, N>,
    /// `θ̂̇` of the law in continuous time (0 with the adaptation off). The tick steps `θ̂` by
    /// `θ̂̇ dt`, except the composite adaptation's prediction term, which it steps implicitly.
    pub theta_hat_dot: SVector<f64, M>,
    pub reference: Reference<N, S>,
    /// `μ²` of the singularity guard (0 away from singularities).
    pub damping: f64,
    /// Whether any joint torque was clamped.
    pub saturated: bool,
    /// The composite adaptation's prediction error `e = W θ̂ − τ_f` (N·m); 0 for the other
    /// laws.
    pub prediction_error: SVector<f64, N>,
}

/// The adaptive hybrid force/position controller, generic over the parameterisation `Z` of a
/// robot's dynamics (`arm7::Base` or `arm7::Standard`: `Z` knows its robot), the robot's `N`
/// joints, the `M` adapted parameters, the task dimension `T` (3 by default: position; 5:
/// position and tool axis; 6: position and orientation, see [`ContactTask`]) and the `S`
/// force-controlled directions (one by default: a contact normal). A tick allocates nothing.
///
/// `HybridController<arm7::Base, { arm7::DOF }, { arm7::BASE_PARAMETER_COUNT }>` (position),
/// `HybridController<arm7::Base, { arm7::DOF }, { arm7::BASE_PARAMETER_COUNT }, 6>` (pose).
/// The number of force-controlled directions comes last, as it changes least often.
///
/// The task rows and the contact force act at the *controlled frame*: the end-effector by
/// default (through [`dyngen_runtime::Kinematics`], for every robot), or any named frame of a
/// robot generated with the group `frames`, chosen with [`Self::with_controlled_frame`].
#[derive(Clone, Debug)]
pub struct HybridController<Z, const N: usize, const M: usize, const T: usize = 3, const S: usize = 1> {
    config: ControllerConfig<N, M, T, S>,
    split: Split<T, S>,
    theta_hat: SVector<f64, M>,
    estimator: Option<StiffnessEstimator<S>>,
    frame: ControlledFrame<N>,
    /// The prediction filter advanced to the coming tick (composite adaptation); `None`
    /// before the first tick.
    filter: Option<(PredictionFilter<N, M>, FilterStep)>,
    _robot: PhantomData<fn() -> Z>,
}

/// The task rows at one state: `J_T`, `J̇_T`, the orientation rows, the pose and the
/// controlled frame's linear velocity.
struct TaskKinematics<const N: usize, const T: usize> {
    pose: Pose,
    velocity: Vector3<f64>,
    j_force: SMatrix<f64, 3, N>,
    j: SMatrix<f64, T, N>,
    jd: SMatrix<f64, T, N>,
    orientation: OrientationRows<T>,
}

impl<Z, const N: usize, const M: usize, const T: usize, const S: usize> HybridController<Z, N, M, T, S>
where
    Z: Parameterization<N, M>,
{
    /// Checks the configuration (gains positive definite, `K` of full row rank and consistent
    /// with the task, task dimension at most the DOF) and builds the controller.
    pub fn new(config: ControllerConfig<N, M, T, S>) -> Result<Self, ConfigError> {
        if T > N {
            return Err(ConfigError::TaskDimension { task: T, dof: N });
        }
        config.gains.validate(config.adaptation.is_adapting())?;
        if let Adaptation::Composite(c) = config.adaptation {
            c.validate()?;
        }
        let split = config.task.validate()?;
        if !config.torque_limit.iter().all(|t| t.is_finite() && *t > 0.0) {
            return Err(ConfigError::Invalid {
                name: "torque limit",
                detail: "every joint limit must be finite and > 0".into(),
            });
        }
        if !config.theta_hat0.iter().all(|t| t.is_finite()) {
            return Err(ConfigError::Invalid {
                name: "θ̂(0)",
                detail: "contains NaN or infinity".into(),
            });
        }
        Ok(HybridController {
            config,
            split,
            theta_hat: config.theta_hat0,
            estimator: None,
            frame: ControlledFrame::END_EFFECTOR,
            filter: None,
            _robot: PhantomData,
        })
    }

    /// Controls `frame` instead of the end-effector: its origin's position (and, for task
    /// dimensions 5 and 6, its orientation; the tool axis of [`Orientation::ToolAxis`] is in its
    /// axes) follows the desired motion, and the measured force `F̄` is taken as acting at its
    /// origin (`τ = J_frameᵀ F̄ + …`). The frame's Jacobian is the generated one in
    /// [`dyngen_runtime::ReferenceFrame::LocalWorldAligned`], the convention of
    /// [`dyngen_runtime::Kinematics::kinematics`], so choosing the end-effector
    /// (`RobotFrame::ALL[0]`) gives the same torques as the default. Only for robots generated
    /// with the group `frames`; [`frame_named`](super::frame_named) finds a frame by its name.
    pub fn with_controlled_frame(self, frame: <Z::Robot as FrameKinematics<N>>::Frame) -> Self
    where
        Z::Robot: FrameKinematics<N>,
    {
        self.at_frame(ControlledFrame::of::<Z::Robot>(frame))
    }

    pub(crate) fn at_frame(mut self, frame: ControlledFrame<N>) -> Self {
        self.frame = frame;
        self
    }

    /// The name of the frame chosen with [`Self::with_controlled_frame`]; `None` when the
    /// controller controls the end-effector by default.
    pub fn controlled_frame(&self) -> Option<&'static str> {
        self.frame.name()
    }

    pub(crate) fn frame(&self) -> &ControlledFrame<N> {
        &self.frame
    }

    /// Estimate the contact stiffness online (Remark 3, no stability proof) starting from
    /// `k_hat0` (S×3: the position columns of `K`; the orientation columns stay zero), which
    /// replaces `K` in the law from the first tick on.
    pub fn with_stiffness_estimation(
        mut self,
        k_hat0: &SMatrix<f64, S, 3>,
        rate: f64,
    ) -> Result<Self, ConfigError> {
        let est = StiffnessEstimator::new(k_hat0, rate)?;
        self.split = Split::new(&pad_columns(&est.stiffness()))?;
        self.estimator = Some(est);
        Ok(self)
    }

    /// Fails if `q0` is singular for the task (the smallest singular value of the task
    /// Jacobian below the guard's threshold) or, for an orientation task, if the desired
    /// orientation at the start `d0` is more than
    /// [`MAX_START_ORIENTATION_ERROR_DEG`] away from the robot's.
    pub fn check_start(&self, q0: &SVector<f64, N>, d0: &Desired<N, S>) -> Result<(), ConfigError> {
        let k = self.task_kinematics(&JointTrig::new(q0), &SVector::zeros(), d0);
        let (sigma, _) = smallest_singular(&k.j);
        let threshold = self.config.guard.sigma_threshold;
        if !(sigma.is_finite() && sigma >= threshold) {
            return Err(ConfigError::SingularStart { sigma, threshold });
        }
        let angle = orientation_angle(&self.config.task.orientation, &k.pose.rotation, &d0.orientation);
        let limit = MAX_START_ORIENTATION_ERROR_DEG;
        if angle.is_finite() && angle.to_degrees() > limit || angle.is_nan() && T > 3 {
            return Err(ConfigError::OrientationTooFar {
                angle_deg: angle.to_degrees(),
                limit_deg: limit,
            });
        }
        Ok(())
    }

    /// `J⁺ v` at rest at `q`, the desired motion `d`: the joint velocity the reference asks
    /// for a task-space velocity `v` (how much of it the task rows pass to each joint).
    pub(crate) fn task_pseudo_inverse_mul(
        &self,
        q: &SVector<f64, N>,
        d: &Desired<N, S>,
        v: &SVector<f64, T>,
    ) -> Result<SVector<f64, N>, TickError> {
        let k = self.task_kinematics(&JointTrig::new(q), &SVector::zeros(), d);
        Ok(Projections::new(&k.j, &k.jd, &self.config.guard)?.pinv_mul(v))
    }

    /// `J_T`, `J̇_T` and the orientation rows (see [`super::orientation`]) of the controlled
    /// frame.
    #[inline]
    fn task_kinematics(
        &self,
        trig: &JointTrig<N>,
        qd: &SVector<f64, N>,
        d: &Desired<N, S>,
    ) -> TaskKinematics<N, T> {
        let task = &self.config.task;
        let (pose, j6, jd6) = self.frame.kinematics::<Z::Robot>(trig, qd);
        let j_force: SMatrix<f64, 3, N> = j6.fixed_rows::<3>(0).into_owned();
        let velocity = matvec::mul(&j_force, qd);
        // Full orientation: P = I, so the task Jacobian is the geometric one (no products).
        let full = T == 6 && task.orientation == Orientation::Full;
        let rows = if full { 6 } else { 3 };
        let mut j = SMatrix::<f64, T, N>::from_fn(|i, c| if i < rows { j6[(i, c)] } else { 0.0 });
        let mut jd = SMatrix::<f64, T, N>::from_fn(|i, c| if i < rows { jd6[(i, c)] } else { 0.0 });
        let orientation = if T > 3 {
            let jw = j6.fixed_rows::<3>(3);
            let omega = jw * qd;
            let o = OrientationRows::<T>::new(
                &task.orientation,
                &pose.rotation,
                &omega,
                &d.orientation,
                &d.angular_velocity,
            );
            if !full {
                j += o.p * jw;
                jd += o.p * jd6.fixed_rows::<3>(3) + o.p_dot * jw;
            }
            o
        } else {
            OrientationRows {
                p: SMatrix::zeros(),
                p_dot: SMatrix::zeros(),
                error: Vector3::zeros(),
                error_rate: Vector3::zeros(),
            }
        };
        TaskKinematics {
            pose,
            velocity,
            j_force,
            j,
            jd,
            orientation,
        }
    }

    pub fn config(&self) -> &ControllerConfig<N, M, T, S> {
        &self.config
    }
    pub fn theta_hat(&self) -> &SVector<f64, M> {
        &self.theta_hat
    }
    pub fn set_theta_hat(&mut self, theta_hat: SVector<f64, M>) {
        self.theta_hat = theta_hat;
    }
    /// `K`, `K⁺`, `K⁻` in use.
    pub fn split(&self) -> &Split<T, S> {
        &self.split
    }
    /// The `K` in use (the estimate when estimating).
    pub fn stiffness(&self) -> SMatrix<f64, S, T> {
        self.split.k
    }
    pub fn estimator(&self) -> Option<&StiffnessEstimator<S>> {
        self.estimator.as_ref()
    }

    /// Evaluates the law at `θ̂` without changing any state: what an integrator that treats
    /// `θ̂` as part of the closed-loop state calls at each stage. The composite adaptation uses
    /// the controller's own prediction filter, as the next [`Self::tick`] would (see
    /// [`Self::evaluate_composite`] to integrate the filter too).
    #[inline]
    pub fn evaluate(
        &self,
        m: &Measurement<N>,
        d: &Desired<N, S>,
        theta_hat: &SVector<f64, M>,
    ) -> Result<ControlOutput<N, M, S>, TickError> {
        Ok(self.evaluate_with(m, d, theta_hat, None)?.0)
    }

    /// The composite law in continuous time, the prediction filter part of the state: the law
    /// at `θ̂` with the filter state `filter` (`P_f`, `Q_f`, `τ_f`; from rest, start it with
    /// [`Self::prediction_filter_start`]), and the filter's rate. For any other adaptation the
    /// rate is 0 and `filter` is not used.
    pub fn evaluate_composite(
        &self,
        m: &Measurement<N>,
        d: &Desired<N, S>,
        theta_hat: &SVector<f64, M>,
        filter: &PredictionFilter<N, M>,
    ) -> Result<(ControlOutput<N, M, S>, PredictionFilter<N, M>), TickError> {
        let (out, state) = self.evaluate_with(m, d, theta_hat, Some(filter))?;
        let rate = match (self.config.adaptation, state) {
            (Adaptation::Composite(c), Some(s)) => s.now.rate(&s.signals, &out.tau, c.bandwidth),
            _ => PredictionFilter {
                momentum: SMatrix::zeros(),
                rest: SMatrix::zeros(),
                torque: SVector::zeros(),
            },
        };
        Ok((out, rate))
    }

    /// The prediction filter's state at the start of a motion measured by `m`, from which
    /// `W θ = τ_f` holds at every instant (`P_f = Y_p`, `Q_f = 0`, `τ_f = 0`).
    pub fn prediction_filter_start(&self, m: &Measurement<N>) -> PredictionFilter<N, M> {
        let trig = JointTrig::new(&m.q);
        let j6 = self.frame.jacobian::<Z::Robot>(&trig);
        let j_force: SMatrix<f64, 3, N> = j6.fixed_rows::<3>(0).into_owned();
        let contact = matvec::tr_mul(&j_force, &m.force);
        PredictionFilter::start(&prediction_signals::<Z, N, M>(&trig, &m.q, &m.qd, contact))
    }

    /// The law at `θ̂`; for the composite adaptation, with the prediction filter `filter`, or
    /// (`None`) the controller's own completed with this measurement. Returns, for the composite
    /// adaptation, what the caller needs to step `θ̂` and the filter.
    #[inline]
    fn evaluate_with(
        &self,
        m: &Measurement<N>,
        d: &Desired<N, S>,
        theta_hat: &SVector<f64, M>,
        filter: Option<&PredictionFilter<N, M>>,
    ) -> Result<(ControlOutput<N, M, S>, Option<CompositeState<N, M>>), TickError> {
        // A NaN or infinity anywhere makes the sum non-finite (cheaper than testing each entry; a
        // sum that overflows from finite values ~1e308 is refused too, rightly).
        if !(plain_sum(m.q.as_slice()) + plain_sum(m.qd.as_slice()) + plain_sum(m.force.as_slice()))
            .is_finite()
        {
            return Err(TickError::NonFiniteMeasurement);
        }
        let trig = JointTrig::new(&m.q);
        let k = self.task_kinematics(&trig, &m.qd, d);
        let proj = Projections::new(&k.j, &k.jd, &self.config.guard)?;
        let gains = ReferenceGains {
            lambda: self.config.gains.lambda,
            lambda_null: self.config.gains.lambda_null,
        };
        let reference = reference(
            m,
            d,
            &self.config.task,
            &self.split,
            &k.pose.translation,
            &k.velocity,
            &k.orientation,
            &proj,
            &gains,
        );
        // `Y θ̂` and `Yᵀ r` without forming `Y` (generated robots: one force per column, none
        // carried up the tree); with the adaptation off, `Yᵀ r` is not used.
        let (y_theta, y_tr_r) = Z::regressor_products(
            &trig,
            &m.qd,
            &reference.qd_r,
            &reference.qdd_r,
            theta_hat,
            &reference.r,
        );
        let contact = matvec::tr_mul(&k.j_force, &m.force);
        let mut prediction_error = SVector::zeros();
        let mut composite = None;
        let theta_hat_dot = match self.config.adaptation {
            Adaptation::On => rate_from_regressor_product(&self.config.gains.gamma, &y_tr_r),
            Adaptation::Composite(c) => {
                let signals = prediction_signals::<Z, N, M>(&trig, &m.q, &m.qd, contact);
                let now = match (filter, &self.filter) {
                    (Some(given), _) => *given,
                    (None, Some((advanced, step))) => advanced.completed(&signals, step),
                    (None, None) => PredictionFilter::start(&signals),
                };
                let w = now.regressor(&signals, c.bandwidth);
                let (product, e) = composite_product(&y_tr_r, &w, &now, theta_hat, c.weight);
                prediction_error = e;
                composite = Some(CompositeState {
                    now,
                    signals,
                    w,
                    slotine_li_rate: rate_from_regressor_product(&self.config.gains.gamma, &y_tr_r),
                });
                rate_from_regressor_product(&self.config.gains.gamma, &product)
            }
            Adaptation::Off => SVector::zeros(),
        };
        let mut tau = contact + y_theta - matvec::mul(&self.config.gains.g, &reference.r);
        if !(plain_sum(tau.as_slice()) + plain_sum(theta_hat_dot.as_slice())).is_finite() {
            return Err(TickError::NonFiniteTorque);
        }
        let mut saturated = false;
        for (t, l) in tau.iter_mut().zip(self.config.torque_limit.iter()) {
            if t.abs() > *l {
                *t = t.clamp(-l, *l);
                saturated = true;
            }
        }
        Ok((
            ControlOutput {
                tau,
                theta_hat_dot,
                reference,
                damping: proj.damping,
                saturated,
                prediction_error,
            },
            composite,
        ))
    }

    /// One control tick of period `dt`: evaluates the law, then advances `θ̂` (explicit Euler;
    /// for the composite adaptation the prediction term implicit, see
    /// `docs/controller.md`; the estimate is held between ticks), the prediction filter of the
    /// composite adaptation (exactly, for the torque held over the period) and the stiffness
    /// estimate. Allocation-free.
    #[inline]
    pub fn tick(
        &mut self,
        m: &Measurement<N>,
        d: &Desired<N, S>,
        dt: f64,
    ) -> Result<ControlOutput<N, M, S>, TickError> {
        let (out, composite) = self.evaluate_with(m, d, &self.theta_hat, None)?;
        match (self.config.adaptation, composite) {
            (Adaptation::Composite(c), Some(s)) => {
                self.theta_hat = implicit_step(
                    &self.theta_hat,
                    &s.slotine_li_rate,
                    &s.w,
                    &s.now,
                    &self.config.gains.gamma,
                    c.weight,
                    dt,
                )
                .ok_or(TickError::NonFiniteTorque)?;
                let step = FilterStep::new(c.bandwidth, dt);
                self.filter = Some((s.now.advanced(&s.signals, &out.tau, &step), step));
            }
            (adaptation, _) => {
                if adaptation.is_adapting() {
                    self.theta_hat += out.theta_hat_dot * dt;
                }
            }
        }
        if let Some(est) = self.estimator.as_mut() {
            let f_meas = self.config.task.force_selection * (self.config.task.rotation * m.force);
            est.update(&out.reference.deflection, &f_meas, dt);
            if let Ok(split) = Split::new(&pad_columns(&est.stiffness())) {
                self.split = split;
            }
        }
        Ok(out)
    }
}

/// What one evaluation of the composite law leaves for the step of `θ̂` and of the filter.
struct CompositeState<const N: usize, const M: usize> {
    /// The prediction filter at this instant.
    now: PredictionFilter<N, M>,
    signals: PredictionSignals<N, M>,
    /// `W`.
    w: SMatrix<f64, N, M>,
    /// `−Γ Yᵀ r`.
    slotine_li_rate: SVector<f64, M>,
}

/// `Σ xᵢ` over a slice: what nalgebra's `sum` computes, without its general strided iterator
/// (which does not unroll; over the 43 entries of `θ̂̇` it cost more than the sum).
#[inline]
fn plain_sum(x: &[f64]) -> f64 {
    x.iter().sum()
}

/// `K` (S×3, position rows) with zero orientation columns: S×T.
#[inline]
fn pad_columns<const S: usize, const T: usize>(k: &SMatrix<f64, S, 3>) -> SMatrix<f64, S, T> {
    SMatrix::from_fn(|i, j| if j < 3 { k[(i, j)] } else { 0.0 })
}
