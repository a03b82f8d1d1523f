//! The demo set-up, shared by the example, the tests and the benchmark: the true plant with an
//! unmodelled payload (and, on a robot with joint-level columns, friction and armature off
//! their nominal values), the press-and-circle scenario above a table, and the controllers
//! compared (adaptive, adaptation off, known parameters; optionally the composite adaptation;
//! on a robot with joint-level columns also adaptive with the joint terms held at their
//! nominal values), for a task of dimension `T`: 3
//! (position, the default), 5 (position and the tool axis held along `tool_direction`), 6
//! (position and the orientation whose tool axis is along `tool_direction`). The task and the
//! contact are at the end-effector ([`Demo::new`]) or at any named frame of a robot generated
//! with the group `frames` ([`Demo::new_at_frame`]). The table is compliant by default, or
//! rigid ([`DemoOptions::surface`]).

use super::contact::PlaneContact;
use super::plant::{Payload, Plant};
use super::rigid_force_loop::{rigid_force_loop_gain, RIGID_FORCE_LOOP_LIMIT};
use super::rigid_plane::RigidPlane;
use super::run::{simulate, RunResult, SimConfig};
use super::scenario::PressAndCircle;
use super::surface::{Surface, SurfaceKind};
use super::true_joint_terms::JointTermFactors;
use crate::controller::frame::ControlledFrame;
use crate::controller::{
    mass_matrix_shaped_gain, Adaptation, Composite, ConfigError, ContactTask, ControllerConfig, Gains,
    GammaByKind, HybridController, SingularityGuard,
};
use dyngen_runtime::{FrameKinematics, JointTrig, Kinematics, Parameterization};
use nalgebra::{Rotation3, SMatrix, SVector, Vector3};

/// Which law a run uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RunKind {
    /// Lemma 3 from `θ̂(0)`: the inertial parameters at `0.5·θ_desc` (payload unknown), the
    /// joint-level ones at [`DemoOptions::joint_estimate_scale`] times the description's
    /// nominal values; every parameter adapts (the joint terms with the joint-level gain).
    Adaptive,
    /// The same with the composite adaptation ([`DemoOptions::composite`]): the update also
    /// descends the prediction error of the filtered joint torque.
    Composite,
    /// [`RunKind::Adaptive`] with the joint terms held at their `θ̂(0)` (joint-level gain 0)
    /// while the inertial parameters adapt: with `joint_estimate_scale = 0` the controller
    /// models no joint friction or armature at all. Only for robots with joint-level columns.
    AdaptiveJointTermsHeld,
    /// [`RunKind::Composite`] with the joint terms held at their `θ̂(0)`.
    CompositeJointTermsHeld,
    /// The same `θ̂(0)`, never updated.
    AdaptationOff,
    /// Lemma 1: the true parameters, payload (and true friction and armature) included.
    KnownParameters,
}

impl RunKind {
    pub const ALL: [RunKind; 6] = [
        RunKind::Adaptive,
        RunKind::Composite,
        RunKind::AdaptiveJointTermsHeld,
        RunKind::CompositeJointTermsHeld,
        RunKind::AdaptationOff,
        RunKind::KnownParameters,
    ];
    pub fn label(self) -> &'static str {
        match self {
            RunKind::Adaptive => "adaptive",
            RunKind::Composite => "composite",
            RunKind::AdaptiveJointTermsHeld => "adaptive, joint terms held",
            RunKind::CompositeJointTermsHeld => "composite, joint terms held",
            RunKind::AdaptationOff => "adaptation off",
            RunKind::KnownParameters => "known parameters",
        }
    }
    /// A file name for the run's data (`adaptive_joint_terms_held`).
    pub fn file_stem(self) -> String {
        self.label().replace(", ", "_").replace(' ', "_")
    }
}

/// Everything the demo can be told.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DemoOptions {
    /// Surface stiffness `k` (N/m): the compliant table's and the controller's contact model's
    /// (for a rigid table, the model's only).
    pub stiffness: f64,
    /// The table: compliant (the default) or rigid.
    pub surface: SurfaceKind,
    pub target_force: f64,
    /// `G = κ D̂(q₀)`.
    pub kappa: f64,
    pub lambda: f64,
    pub lambda_null: f64,
    /// `Γ` by kind; `gamma.joint` adapts the joint-level parameters (0: held at nominal).
    pub gamma: GammaByKind,
    /// `θ̂(0) = scale · θ_desc` for the inertial parameters.
    pub initial_estimate_scale: f64,
    /// `θ̂(0) = scale · θ_desc` for the joint-level parameters (armature, friction, offset): 1
    /// starts at the description's nominal values, 0 at no joint friction or armature at all.
    pub joint_estimate_scale: f64,
    pub payload: Payload,
    /// The true robot's joint-level parameters relative to the description's nominal values
    /// (only robots with joint-level columns have any).
    pub true_joint_terms: JointTermFactors,
    /// Height of the start above the table (m); negative starts in contact, pressing.
    pub start_height: f64,
    pub circle_time: f64,
    /// Revolutions of the circle per second (Hz).
    pub circle_frequency: f64,
    pub sim: SimConfig,
    /// The composite adaptation's filter bandwidth and weight: with `Some`, the comparison
    /// adds the runs [`RunKind::Composite`] (and [`RunKind::CompositeJointTermsHeld`]).
    pub composite: Option<Composite>,
    /// Online stiffness estimation: `(k̂(0)/k, rate γ)`.
    pub stiffness_estimation: Option<(f64, f64)>,
    pub guard: SingularityGuard,
    /// The tool axis (unit, in the axes of the controlled frame: the end-effector's by
    /// default): its direction is held by tasks of dimension 5 and 6.
    pub tool_axis: Vector3<f64>,
    /// Where the tool axis points once turned (base frame, unit): straight down by default.
    pub tool_direction: Vector3<f64>,
}

impl Default for DemoOptions {
    fn default() -> Self {
        DemoOptions {
            stiffness: 1e4,
            surface: SurfaceKind::Compliant,
            target_force: 10.0,
            kappa: 400.0,
            lambda: 100.0,
            lambda_null: 10.0,
            gamma: GammaByKind::default(),
            initial_estimate_scale: 0.5,
            joint_estimate_scale: 1.0,
            true_joint_terms: JointTermFactors::DEMO,
            payload: Payload {
                mass: 1.5,
                com: Vector3::new(0.02, 0.0, 0.1),
                size: Vector3::new(0.08, 0.08, 0.06),
            },
            start_height: 0.01,
            circle_time: 8.0,
            circle_frequency: 0.25,
            sim: SimConfig::default(),
            composite: None,
            stiffness_estimation: None,
            guard: SingularityGuard::default(),
            tool_axis: Vector3::z(),
            tool_direction: -Vector3::z(),
        }
    }
}

/// The description's effort limits (N·m or N), which the demo clamps torques to; every joint
/// must have one.
pub(crate) fn effort_limits<R: Kinematics<N>, const N: usize>() -> Result<SVector<f64, N>, ConfigError> {
    for (name, limit) in R::JOINT_NAMES.iter().zip(R::JOINT_LIMITS.iter()) {
        if !(limit.effort.is_finite() && limit.effort > 0.0) {
            return Err(ConfigError::Invalid {
                name: "torque limit",
                detail: format!(
                    "joint '{name}' of {} has no effort limit in its description (give `limit: {{ effort: … }}`)",
                    R::NAME
                ),
            });
        }
    }
    Ok(SVector::from_fn(|i, _| R::JOINT_LIMITS[i].effort))
}

/// The demo for the robot of parameterisation `Z` (`arm7::Base`, the default of the example,
/// or `arm7::Standard`) and the task dimension `T` (3, 5 or 6).
pub struct Demo<Z, const N: usize, const M: usize, const T: usize = 3> {
    pub options: DemoOptions,
    pub plant: Plant<Z, N, M>,
    pub scenario: PressAndCircle<N>,
    pub q0: SVector<f64, N>,
    pub torque_limit: SVector<f64, N>,
    pub task: ContactTask<T>,
    /// `θ̂(0)` of the adaptive run and of the run without adaptation.
    pub theta_hat0: SVector<f64, M>,
    /// `Φ(θ_true)`.
    pub theta_true: SVector<f64, M>,
    pub g: SMatrix<f64, N, N>,
    pub gamma: SVector<f64, M>,
    /// `Γ` with the joint-level gain 0: the run [`RunKind::AdaptiveJointTermsHeld`].
    pub gamma_joint_terms_held: SVector<f64, M>,
    /// The frame the controllers control and the plant touches the table with.
    frame: ControlledFrame<N>,
    _z: std::marker::PhantomData<fn() -> Z>,
}

impl<Z, const N: usize, const M: usize, const T: usize> Demo<Z, N, M, T>
where
    Z: Parameterization<N, M>,
{
    /// Builds and checks the set-up at the end-effector (through `Kinematics`, for every
    /// robot): the table is `start_height` below the end-effector at `q0`; the target
    /// orientation turns the tool axis onto `tool_direction` by the shortest rotation;
    /// `G = κ D̂(q₀)` from the adaptive run's initial estimate, shared by all runs; the torques
    /// are clamped to the description's effort limits.
    pub fn new(options: DemoOptions, q0: SVector<f64, N>) -> Result<Self, ConfigError> {
        Self::build(options, q0, ControlledFrame::END_EFFECTOR)
    }

    /// The same set-up at `frame` instead of the end-effector: the table is `start_height`
    /// below that frame's origin at `q0`, every controller controls it
    /// ([`HybridController::with_controlled_frame`]), the plant touches the table with it
    /// ([`Plant::with_contact_frame`]) and the tool axis is in its axes. Only for robots
    /// generated with the group `frames`; [`crate::controller::frame_named`] finds a frame by
    /// its name. The payload stays on the end-effector's body.
    pub fn new_at_frame(
        options: DemoOptions,
        q0: SVector<f64, N>,
        frame: <Z::Robot as FrameKinematics<N>>::Frame,
    ) -> Result<Self, ConfigError>
    where
        Z::Robot: FrameKinematics<N>,
    {
        Self::build(options, q0, ControlledFrame::of::<Z::Robot>(frame))
    }

    /// The name of the frame given to [`Self::new_at_frame`]; `None` for the end-effector of
    /// [`Self::new`].
    pub fn controlled_frame(&self) -> Option<&'static str> {
        self.frame.name()
    }

    fn build(
        options: DemoOptions,
        q0: SVector<f64, N>,
        frame: ControlledFrame<N>,
    ) -> Result<Self, ConfigError> {
        let torque_limit = effort_limits::<Z::Robot, N>()?;
        let pose = frame.pose::<Z::Robot>(&JointTrig::new(&q0));
        let start = pose.translation;
        if !start.iter().all(|x| x.is_finite()) {
            return Err(ConfigError::Invalid {
                name: "q0",
                detail: "start posture is not finite".into(),
            });
        }
        let table = start.z - options.start_height;
        // Where the controller's model puts the undeformed surface: on a rigid table,
        // `F_target / k` above it (see `SurfaceKind::Rigid`).
        let (contact, surface): (Surface, f64) = match options.surface {
            SurfaceKind::Compliant => (PlaneContact::table(table, options.stiffness).into(), table),
            SurfaceKind::Rigid => (
                RigidPlane::table(table).into(),
                table + options.target_force / options.stiffness,
            ),
        };
        let plant = Plant::<Z, N, M>::with_payload_and_joint_terms(
            &options.payload,
            &options.true_joint_terms,
            contact,
        )
        .at_frame(frame);
        let unit = |v: Vector3<f64>, name: &'static str| {
            v.try_normalize(1e-9).ok_or_else(|| ConfigError::Invalid {
                name,
                detail: "must be a nonzero vector".into(),
            })
        };
        let tool_axis = unit(options.tool_axis, "tool axis")?;
        let tool_direction = unit(options.tool_direction, "tool direction")?;
        let task = ContactTask::plane(
            Vector3::new(0.0, 0.0, surface),
            contact.normal(),
            options.stiffness,
        )?
        .with_task_dimension::<T>(tool_axis);
        task.validate()?;
        let axis0 = pose.rotation * tool_axis;
        let turn = Rotation3::rotation_between(&axis0, &tool_direction).unwrap_or_else(|| {
            // Opposite: any half turn about an axis perpendicular to the tool axis.
            let perp = crate::controller::orientation::perpendicular_basis(&axis0)
                .row(0)
                .transpose();
            Rotation3::from_axis_angle(&nalgebra::Unit::new_normalize(perp), std::f64::consts::PI)
        });
        let target_orientation = turn.into_inner() * pose.rotation;
        // The desired force is consistent with the controller's own contact model (eq. 39): with
        // stiffness estimation that is the initial estimate k̂(0) (it matters in free space,
        // where `F_d < 0` is a desired distance `−F_d / k̂`).
        let model_k = options.stiffness * options.stiffness_estimation.map_or(1.0, |(f, _)| f);
        let scenario = {
            let mut s =
                PressAndCircle::new(task.rotation * start, surface, model_k, options.target_force, q0)
                    .with_orientation(pose.rotation, target_orientation);
            s.circle_time = options.circle_time;
            s.frequency = options.circle_frequency;
            s
        };
        let model_task = ContactTask::<T> {
            stiffness: task.stiffness * (model_k / options.stiffness),
            ..task
        };
        scenario.validate(&model_task)?;
        let penetration = options.target_force / options.stiffness;
        if penetration > 0.05 {
            return Err(ConfigError::ForceContradictsContact(format!(
                "{} N on k = {} N/m needs {:.1} mm of penetration (> 50 mm)",
                options.target_force,
                options.stiffness,
                penetration * 1e3
            )));
        }
        if !(options.kappa.is_finite() && options.kappa > 0.0) {
            return Err(ConfigError::NotPositiveDefinite {
                name: "G",
                detail: format!("κ = {} must be > 0", options.kappa),
            });
        }
        options.gamma.validate()?;
        for (name, scale) in [
            ("initial_estimate_scale", options.initial_estimate_scale),
            ("joint_estimate_scale", options.joint_estimate_scale),
        ] {
            // A negative scale makes masses, inertias and friction negative: no physical robot.
            if !(scale.is_finite() && scale >= 0.0) {
                return Err(ConfigError::Invalid {
                    name,
                    detail: format!(
                        "{scale} must be finite and ≥ 0 (a multiple of the description's values)"
                    ),
                });
            }
        }
        let theta_hat0 = Z::description_scaled_by_kind(|kind| {
            if kind.is_joint_level() {
                options.joint_estimate_scale
            } else {
                options.initial_estimate_scale
            }
        });
        let theta_true = *plant.parameters();
        let g = mass_matrix_shaped_gain::<Z, N, M>(options.kappa, &q0, &theta_hat0);
        let gamma = options.gamma.carried_to::<Z, N, M>();
        let gamma_joint_terms_held = GammaByKind {
            joint: 0.0,
            ..options.gamma
        }
        .carried_to::<Z, N, M>();
        let demo = Demo {
            options,
            plant,
            scenario,
            q0,
            torque_limit,
            task,
            theta_hat0,
            theta_true,
            g,
            gamma,
            gamma_joint_terms_held,
            frame,
            _z: std::marker::PhantomData,
        };
        // Every configuration error shows up here, before any run.
        for kind in demo.run_kinds() {
            demo.controller(kind)?;
        }
        if let Surface::Rigid(_) = demo.plant.contact {
            // Every run shares `G`, `λ`, `K` and the task, hence the gain.
            let controller = demo.controller(RunKind::Adaptive)?;
            let gain =
                rigid_force_loop_gain(&demo.plant, &controller, &demo.q0, &demo.scenario.desired(0.0))?;
            // A NaN gain is refused too.
            if gain.is_nan() || gain >= RIGID_FORCE_LOOP_LIMIT {
                let stiffness = controller.stiffness().fixed_columns::<3>(0).norm();
                return Err(ConfigError::RigidForceLoop {
                    gain,
                    limit: RIGID_FORCE_LOOP_LIMIT,
                    stiffness,
                    needed: stiffness * gain / RIGID_FORCE_LOOP_LIMIT,
                    unit: stiffness * gain,
                });
            }
        }
        Ok(demo)
    }

    /// Whether the robot's regressor has joint-level columns (armature, friction, offset).
    pub fn has_joint_terms() -> bool {
        Z::gain_by_kind(|kind| f64::from(u8::from(kind.is_joint_level()))).amax() > 0.0
    }

    /// The runs of the comparison: adaptive, adaptation off, known parameters; with
    /// [`DemoOptions::composite`], also the composite run; on a robot with joint-level columns
    /// whose joint-level gain is not 0, also the adaptive (and composite) run with the joint
    /// terms held at their `θ̂(0)`.
    pub fn run_kinds(&self) -> Vec<RunKind> {
        let with_held = Self::has_joint_terms() && self.options.gamma.joint > 0.0;
        let with_composite = self.options.composite.is_some();
        RunKind::ALL
            .into_iter()
            .filter(|k| match k {
                RunKind::Composite => with_composite,
                RunKind::AdaptiveJointTermsHeld => with_held,
                RunKind::CompositeJointTermsHeld => with_held && with_composite,
                RunKind::Adaptive | RunKind::AdaptationOff | RunKind::KnownParameters => true,
            })
            .collect()
    }

    /// The controller of one run, checked (gains, `K`, start posture, sampling limit).
    pub fn controller(&self, kind: RunKind) -> Result<HybridController<Z, N, M, T>, ConfigError> {
        let composite = Adaptation::Composite(self.options.composite.unwrap_or_default());
        let (adaptation, theta, gamma) = match kind {
            RunKind::Adaptive => (Adaptation::On, self.theta_hat0, self.gamma),
            RunKind::Composite => (composite, self.theta_hat0, self.gamma),
            RunKind::AdaptiveJointTermsHeld => (Adaptation::On, self.theta_hat0, self.gamma_joint_terms_held),
            RunKind::CompositeJointTermsHeld => (composite, self.theta_hat0, self.gamma_joint_terms_held),
            RunKind::AdaptationOff => (Adaptation::Off, self.theta_hat0, self.gamma),
            RunKind::KnownParameters => (Adaptation::Off, self.theta_true, self.gamma),
        };
        let gains = Gains {
            lambda: self.options.lambda,
            lambda_null: self.options.lambda_null,
            g: self.g,
            gamma,
        };
        let mut c = HybridController::<Z, N, M, T>::new(ControllerConfig {
            gains,
            task: self.task,
            guard: self.options.guard,
            torque_limit: self.torque_limit,
            adaptation,
            theta_hat0: theta,
        })?
        .at_frame(self.frame);
        c.check_start(&self.q0, &self.scenario.desired(0.0))?;
        let d_hat = crate::controller::mass_matrix_estimate::<Z, N, M>(&self.q0, &theta);
        let value = gains.stiffest_mode(&d_hat)? * self.options.sim.control_period;
        let limit = 2.0;
        if value > limit {
            return Err(ConfigError::SamplingLimit { value, limit });
        }
        if let Some((factor, rate)) = self.options.stiffness_estimation {
            if !(factor.is_finite() && factor > 0.0) {
                return Err(ConfigError::Invalid {
                    name: "initial stiffness estimate",
                    detail: format!("k̂(0)/k = {factor} must be > 0"),
                });
            }
            let k: SMatrix<f64, 1, 3> = self.task.stiffness.fixed_columns::<3>(0) * factor;
            c = c.with_stiffness_estimation(&k, rate)?;
        }
        Ok(c)
    }

    /// Runs one law over the scenario.
    pub fn run(&self, kind: RunKind, progress: &mut dyn FnMut(f64)) -> Result<RunResult, ConfigError> {
        let mut c = self.controller(kind)?;
        Ok(simulate(
            &self.plant,
            &mut c,
            &self.scenario,
            &self.q0,
            &self.options.sim,
            progress,
        ))
    }

    /// Start of the window the thresholds are measured over: the last 4 s.
    pub fn metrics_from(&self) -> f64 {
        self.scenario.duration() - 4.0
    }
}
