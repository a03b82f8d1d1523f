//! Bad input gives a clear error before the run starts; a diverging run stops with the time and
//! the reason and keeps the data logged so far.

use dyngen_control::controller::{
    Adaptation, Composite, ConfigError, ContactTask, ControllerConfig, Gains, HybridController, Orientation,
    SingularityGuard,
};
use dyngen_control::sim::{start_posture, Demo, DemoOptions, RunKind, RunStatus};
use dyngen_generated::arm7;
use dyngen_runtime::nalgebra::{SMatrix, SVector, Vector3};
use dyngen_runtime::{
    ForwardDynamics, JointLimits, JointTrig, Kinematics, ParameterKind, Pose, Regressors, RobotDynamics,
    Standard,
};

type Arm7Demo = Demo<arm7::Standard, 7, 70>;

fn demo(options: DemoOptions) -> Result<Arm7Demo, ConfigError> {
    let q0 = start_posture::<7>("arm7").expect("arm7 start posture");
    Arm7Demo::new(options, q0)
}

fn config<const N: usize, const M: usize, const T: usize, const S: usize>(
    task: ContactTask<T, S>,
) -> ControllerConfig<N, M, T, S> {
    ControllerConfig {
        gains: Gains {
            lambda: 10.0,
            lambda_null: 1.0,
            g: SMatrix::identity(),
            gamma: SVector::from_element(1.0),
        },
        task,
        guard: SingularityGuard::default(),
        torque_limit: SVector::from_element(100.0),
        adaptation: Adaptation::On,
        theta_hat0: SVector::zeros(),
    }
}

fn table() -> ContactTask {
    ContactTask::plane(Vector3::zeros(), Vector3::z(), 1e4).expect("plane")
}

#[test]
fn the_default_demo_is_valid() {
    demo(DemoOptions::default()).expect("default demo");
}

/// The composite adaptation's filter bandwidth must be > 0 and its weight ≥ 0 (0 is the
/// Slotine–Li law); the circle's frequency finite and ≥ 0.
#[test]
fn composite_settings_out_of_range() {
    for (bandwidth, weight, name) in [
        (0.0, 0.5, "λ_f"),
        (f64::NAN, 0.5, "λ_f"),
        (500.0, -0.1, "R"),
        (500.0, f64::INFINITY, "R"),
    ] {
        let e = demo(DemoOptions {
            composite: Some(Composite { bandwidth, weight }),
            ..DemoOptions::default()
        })
        .err();
        assert!(
            matches!(e, Some(ConfigError::NotPositiveDefinite { name: n, .. }) if n == name),
            "{bandwidth} {weight}: {e:?}"
        );
        println!("{}", e.expect("an error"));
    }
    let c = ControllerConfig {
        adaptation: Adaptation::Composite(Composite {
            weight: 0.0,
            ..Composite::default()
        }),
        ..config::<7, 70, 3, 1>(table())
    };
    assert!(HybridController::<arm7::Standard, 7, 70>::new(c).is_ok());

    let e = demo(DemoOptions {
        circle_frequency: -1.0,
        ..DemoOptions::default()
    })
    .err();
    assert!(matches!(e, Some(ConfigError::Invalid { .. })), "{e:?}");
}

#[test]
fn gains_that_are_not_positive_definite() {
    let e = demo(DemoOptions {
        kappa: -5.0,
        ..DemoOptions::default()
    })
    .err();
    assert!(
        matches!(e, Some(ConfigError::NotPositiveDefinite { name: "G", .. })),
        "{e:?}"
    );

    let mut c = config::<7, 70, 3, 1>(table());
    c.gains.g[(3, 3)] = -1.0;
    let e = HybridController::<arm7::Standard, 7, 70>::new(c).err();
    assert!(
        matches!(e, Some(ConfigError::NotPositiveDefinite { name: "G", .. })),
        "{e:?}"
    );

    let mut c = config::<7, 70, 3, 1>(table());
    c.gains.g[(0, 1)] = 0.5; // not symmetric
    let e = HybridController::<arm7::Standard, 7, 70>::new(c).err();
    assert!(
        matches!(e, Some(ConfigError::NotPositiveDefinite { name: "G", .. })),
        "{e:?}"
    );

    let mut options = DemoOptions::default();
    options.gamma.first_moment = 0.0;
    let e = demo(options).err();
    assert!(
        matches!(e, Some(ConfigError::NotPositiveDefinite { name: "Γ", .. })),
        "{e:?}"
    );

    // The joint-level gain may be 0 (joint terms held at nominal), not negative.
    let mut options = DemoOptions::default();
    options.gamma.joint = -1.0;
    let e = demo(options).err();
    assert!(
        matches!(e, Some(ConfigError::NotPositiveDefinite { name: "Γ", .. })),
        "{e:?}"
    );
    let mut options = DemoOptions::default();
    options.gamma.joint = 0.0;
    assert!(demo(options).is_ok());

    // θ̂(0) scales: a multiple of the description's values, never negative or NaN.
    for (scale, joint) in [(-0.5, 1.0), (0.5, -1.0), (f64::NAN, 1.0), (0.5, f64::INFINITY)] {
        let e = demo(DemoOptions {
            initial_estimate_scale: scale,
            joint_estimate_scale: joint,
            ..DemoOptions::default()
        })
        .err();
        assert!(
            matches!(e, Some(ConfigError::Invalid { .. })),
            "{scale} {joint}: {e:?}"
        );
    }

    let e = demo(DemoOptions {
        lambda: 0.0,
        ..DemoOptions::default()
    })
    .err();
    assert!(
        matches!(e, Some(ConfigError::NotPositiveDefinite { name: "λ", .. })),
        "{e:?}"
    );
    println!("{}", e.map(|e| e.to_string()).unwrap_or_default());

    // Positive definite but far beyond what 1 kHz sampling allows.
    let e = demo(DemoOptions {
        kappa: 1e5,
        ..DemoOptions::default()
    })
    .err();
    assert!(matches!(e, Some(ConfigError::SamplingLimit { .. })), "{e:?}");
}

#[test]
fn a_stiffness_that_is_not_full_rank() {
    let mut task = table();
    task.stiffness = SMatrix::zeros();
    let e = HybridController::<arm7::Standard, 7, 70>::new(config(task)).err();
    assert!(
        matches!(e, Some(ConfigError::StiffnessRankDeficient { .. })),
        "{e:?}"
    );

    // Two parallel rows.
    let task2 = ContactTask::<3, 2> {
        rotation: SMatrix::identity(),
        stiffness: SMatrix::<f64, 2, 3>::new(0.0, 0.0, -1e4, 0.0, 0.0, -2e4),
        force_selection: SMatrix::<f64, 2, 3>::new(0.0, 0.0, -1.0, 0.0, 1.0, 0.0),
        contact_point: Vector3::zeros(),
        orientation: Orientation::Free,
    };
    let e = HybridController::<arm7::Standard, 7, 70, 3, 2>::new(config(task2)).err();
    assert!(
        matches!(e, Some(ConfigError::StiffnessRankDeficient { rows: 2, .. })),
        "{e:?}"
    );
    println!("{}", e.map(|e| e.to_string()).unwrap_or_default());
}

/// A two-joint robot: too few joints for a 3-D position task. Only its size matters here.
struct TwoJoints;

impl Kinematics<2> for TwoJoints {
    const NAME: &'static str = "two_joints";
    const JOINT_NAMES: [&'static str; 2] = ["a", "b"];
    const JOINT_LIMITS: [JointLimits; 2] = [JointLimits::NONE; 2];
    const END_EFFECTOR_BODY: usize = 1;
    fn forward_kinematics(_: &JointTrig<2>) -> Pose {
        Pose {
            rotation: SMatrix::identity(),
            translation: Vector3::zeros(),
        }
    }
    fn jacobian(_: &JointTrig<2>) -> SMatrix<f64, 6, 2> {
        SMatrix::zeros()
    }
    fn jacobian_dot(_: &JointTrig<2>, _: &SVector<f64, 2>) -> SMatrix<f64, 6, 2> {
        SMatrix::zeros()
    }
}

impl RobotDynamics<2, 20> for TwoJoints {
    const PARAMETER_NAMES: [&'static str; 20] = [""; 20];
    const PARAMETER_KINDS: [ParameterKind; 20] = [ParameterKind::Mass; 20];
    fn parameters() -> SVector<f64, 20> {
        SVector::zeros()
    }
    fn mass_matrix(_: &JointTrig<2>) -> SMatrix<f64, 2, 2> {
        SMatrix::identity()
    }
    fn coriolis_matrix(_: &JointTrig<2>, _: &SVector<f64, 2>) -> SMatrix<f64, 2, 2> {
        SMatrix::zeros()
    }
    fn gravity(_: &JointTrig<2>) -> SVector<f64, 2> {
        SVector::zeros()
    }
    fn inverse_dynamics(_: &JointTrig<2>, _: &SVector<f64, 2>, a: &SVector<f64, 2>) -> SVector<f64, 2> {
        *a
    }
    fn slotine_li(
        _: &JointTrig<2>,
        _: &SVector<f64, 2>,
        _: &SVector<f64, 2>,
        a: &SVector<f64, 2>,
    ) -> SVector<f64, 2> {
        *a
    }
}

impl Regressors<2, 20> for TwoJoints {
    fn regressor(
        _: &JointTrig<2>,
        _: &SVector<f64, 2>,
        _: &SVector<f64, 2>,
        _: &SVector<f64, 2>,
    ) -> SMatrix<f64, 2, 20> {
        SMatrix::zeros()
    }
}

// D = 1, no bias: q̈ = τ. The controller needs neither its derivatives nor the base parameters.
impl ForwardDynamics<2, 20> for TwoJoints {
    fn forward_dynamics(_: &JointTrig<2>, _: &SVector<f64, 2>, tau: &SVector<f64, 2>) -> SVector<f64, 2> {
        *tau
    }
    fn mass_matrix_inverse(_: &JointTrig<2>) -> SMatrix<f64, 2, 2> {
        SMatrix::identity()
    }
}

#[test]
fn a_task_dimension_larger_than_the_dof() {
    let e = HybridController::<Standard<TwoJoints>, 2, 20>::new(config(table())).err();
    assert_eq!(e, Some(ConfigError::TaskDimension { task: 3, dof: 2 }));
    println!("{}", e.map(|e| e.to_string()).unwrap_or_default());
    // Six directions (position and orientation) on a two-joint robot.
    let e = HybridController::<Standard<TwoJoints>, 2, 20, 6>::new(config(table().with_orientation())).err();
    assert_eq!(e, Some(ConfigError::TaskDimension { task: 6, dof: 2 }));
    println!("{}", e.map(|e| e.to_string()).unwrap_or_default());
    // And through the demo: arm7 has 7 joints, so m = 6 is fine there, but the demo refuses a
    // task dimension that is neither 3, 5 nor 6.
    let q0 = start_posture::<7>("arm7").expect("arm7 start posture");
    let e = Demo::<arm7::Standard, 7, 70, 4>::new(DemoOptions::default(), q0).err();
    assert!(matches!(e, Some(ConfigError::TaskKind { task: 4, .. })), "{e:?}");
    println!("{}", e.map(|e| e.to_string()).unwrap_or_default());
}

#[test]
fn a_contact_stiffness_inconsistent_with_the_task_dimension() {
    // A force on an orientation row: contact acts on positions only.
    let mut task = table().with_orientation();
    task.stiffness[(0, 4)] = 50.0;
    let e = HybridController::<arm7::Standard, 7, 70, 6>::new(config(task)).err();
    assert!(matches!(e, Some(ConfigError::StiffnessShape(_))), "{e:?}");
    let message = e.map(|e| e.to_string()).unwrap_or_default();
    assert!(message.contains("orientation row 4"), "{message}");
    println!("{message}");

    // K given at run time with the wrong shape for the task: 3 entries per row for a 6-row
    // task, or two rows where the task has one force direction.
    let e = ContactTask::<6>::stiffness_from_rows(&[&[0.0, 0.0, -1e4]]).err();
    assert!(matches!(e, Some(ConfigError::StiffnessShape(_))), "{e:?}");
    println!("{}", e.map(|e| e.to_string()).unwrap_or_default());
    let e = ContactTask::<3>::stiffness_from_rows(&[&[0.0, 0.0, -1e4], &[1e4, 0.0, 0.0]]).err();
    assert!(matches!(e, Some(ConfigError::StiffnessShape(_))), "{e:?}");
    let k = ContactTask::<5>::stiffness_from_rows(&[&[0.0, 0.0, -1e4, 0.0, 0.0]]).expect("consistent");
    assert_eq!(k[(0, 2)], -1e4);

    // Four force directions: more than the three position rows.
    let base = table().with_orientation();
    let task4 = ContactTask::<6, 4> {
        rotation: base.rotation,
        stiffness: SMatrix::<f64, 4, 6>::from_fn(|i, j| if i == j { 1e4 } else { 0.0 }),
        force_selection: SMatrix::zeros(),
        contact_point: base.contact_point,
        orientation: Orientation::Full,
    };
    let e = task4.validate().err();
    assert!(matches!(e, Some(ConfigError::StiffnessShape(_))), "{e:?}");

    // The orientation task does not match the task dimension.
    let mut task = table().with_orientation();
    task.orientation = Orientation::ToolAxis { axis: Vector3::z() };
    let e = HybridController::<arm7::Standard, 7, 70, 6>::new(config(task)).err();
    assert!(
        matches!(
            e,
            Some(ConfigError::TaskKind {
                task: 6,
                expected: 5,
                ..
            })
        ),
        "{e:?}"
    );
    println!("{}", e.map(|e| e.to_string()).unwrap_or_default());

    // A tool axis that is not a unit vector.
    let task = table().with_tool_axis(Vector3::new(0.0, 0.0, 2.0));
    let e = HybridController::<arm7::Standard, 7, 70, 5>::new(config(task)).err();
    assert!(
        matches!(
            e,
            Some(ConfigError::Invalid {
                name: "tool axis",
                ..
            })
        ),
        "{e:?}"
    );
}

#[test]
fn a_desired_orientation_too_far_from_the_start() {
    let q0 = start_posture::<7>("arm7").expect("arm7 start posture");
    let d = Demo::<arm7::Standard, 7, 70, 6>::new(DemoOptions::default(), q0).expect("valid m = 6 demo");
    let c = d.controller(RunKind::Adaptive).expect("controller");
    let mut d0 = d.scenario.desired(0.0);
    c.check_start(&q0, &d0)
        .expect("the scenario starts at the start orientation");
    // Turned by 120° about the base x axis.
    let turn = dyngen_runtime::nalgebra::Rotation3::from_axis_angle(&Vector3::x_axis(), 120f64.to_radians());
    d0.orientation = turn.into_inner() * d0.orientation;
    let e = c.check_start(&q0, &d0).err();
    match e {
        Some(ConfigError::OrientationTooFar { angle_deg, .. }) => assert!((angle_deg - 120.0).abs() < 1e-6),
        other => panic!("{other:?}"),
    }
    println!("{}", e.map(|e| e.to_string()).unwrap_or_default());
}

#[test]
fn a_robot_without_effort_limits() {
    let e = Demo::<Standard<TwoJoints>, 2, 20>::new(DemoOptions::default(), SVector::zeros()).err();
    let message = e.map(|e| e.to_string()).unwrap_or_default();
    assert!(
        message.contains("joint 'a' of two_joints has no effort limit in its description"),
        "{message}"
    );
    println!("{message}");
}

#[test]
fn a_desired_force_that_contradicts_the_contact_model() {
    let e = demo(DemoOptions {
        target_force: -5.0,
        ..DemoOptions::default()
    })
    .err();
    assert!(
        matches!(e, Some(ConfigError::ForceContradictsContact(_))),
        "{e:?}"
    );
    println!("{}", e.map(|e| e.to_string()).unwrap_or_default());

    // A K whose force grows when pulling away from the surface.
    let d = demo(DemoOptions::default()).expect("default demo");
    let mut task = d.task;
    task.stiffness = -task.stiffness;
    let e = d.scenario.validate(&task).err();
    assert!(
        matches!(e, Some(ConfigError::ForceContradictsContact(_))),
        "{e:?}"
    );

    // More penetration than a stiff surface allows.
    let e = demo(DemoOptions {
        target_force: 1e4,
        ..DemoOptions::default()
    })
    .err();
    assert!(
        matches!(e, Some(ConfigError::ForceContradictsContact(_))),
        "{e:?}"
    );
}

#[test]
fn a_robot_that_starts_singular() {
    // Stretched straight up: every joint axis passes through the flange or is parallel.
    let e = Arm7Demo::new(DemoOptions::default(), SVector::zeros()).err();
    assert!(matches!(e, Some(ConfigError::SingularStart { .. })), "{e:?}");
    println!("{}", e.map(|e| e.to_string()).unwrap_or_default());
}

#[test]
fn a_diverging_run_says_when_and_why_and_keeps_its_data() {
    // Γ a million times the default: the discrete-time adaptation blows up.
    let mut options = DemoOptions::default();
    options.gamma.mass *= 1e6;
    options.gamma.first_moment *= 1e6;
    options.gamma.inertia *= 1e6;
    let d = demo(options).expect("a valid (if unwise) configuration");
    let res = d.run(RunKind::Adaptive, &mut |_| {}).expect("valid controller");
    match &res.status {
        RunStatus::Diverged { time, reason } => {
            println!("diverged at t = {time} s: {reason}");
            assert!(*time > 0.0 && *time < d.scenario.duration());
            assert!(!reason.is_empty());
            let last = res.samples.last().expect("data logged before the divergence");
            assert!(last.t <= *time && *time - last.t <= 2.0 * d.options.sim.control_period);
            assert!(res.samples.len() > 1);
        }
        RunStatus::Completed => panic!("expected a divergence"),
    }
}

#[test]
fn a_non_finite_measurement_is_an_error_not_a_torque() {
    use dyngen_control::controller::{Measurement, TickError};
    let d = demo(DemoOptions::default()).expect("default demo");
    let mut c = d.controller(RunKind::Adaptive).expect("controller");
    let mut m = Measurement {
        q: d.q0,
        qd: SVector::zeros(),
        force: Vector3::zeros(),
    };
    m.qd[4] = f64::NAN;
    assert_eq!(
        c.tick(&m, &d.scenario.desired(0.0), 1e-3).err(),
        Some(TickError::NonFiniteMeasurement)
    );
    m.qd[4] = 0.0;
    m.force.z = f64::INFINITY;
    assert_eq!(
        c.tick(&m, &d.scenario.desired(0.0), 1e-3).err(),
        Some(TickError::NonFiniteMeasurement)
    );
    // θ̂ untouched by the refused ticks.
    assert_eq!(*c.theta_hat(), d.theta_hat0);
}

/// arm7's kinematics under another name: no committed start posture.
struct Unknown7;

impl Kinematics<7> for Unknown7 {
    const NAME: &'static str = "unknown7";
    const JOINT_NAMES: [&'static str; 7] = arm7::JOINT_NAMES;
    const JOINT_LIMITS: [JointLimits; 7] = arm7::JOINT_LIMITS;
    const END_EFFECTOR_BODY: usize = <arm7::Arm7 as Kinematics<7>>::END_EFFECTOR_BODY;
    fn forward_kinematics(t: &JointTrig<7>) -> Pose {
        arm7::Arm7::forward_kinematics(t)
    }
    fn jacobian(t: &JointTrig<7>) -> SMatrix<f64, 6, 7> {
        arm7::Arm7::jacobian(t)
    }
    fn jacobian_dot(t: &JointTrig<7>, qd: &SVector<f64, 7>) -> SMatrix<f64, 6, 7> {
        arm7::Arm7::jacobian_dot(t, qd)
    }
}

#[test]
fn start_postures_from_a_flag_a_preset_or_the_description() {
    use dyngen_control::sim::start_posture_for;
    // A flag with the wrong number of values.
    let e = start_posture_for::<arm7::Arm7, 7>(Some(&[0.0; 6]))
        .err()
        .unwrap_or_default();
    assert!(e.contains("--start has 6 values; arm7 has 7 joints"), "{e}");
    // The committed preset, by name.
    let q = start_posture_for::<arm7::Arm7, 7>(None).expect("preset");
    assert_eq!(Some(q), start_posture::<7>("arm7"));
    // Another robot: the middle of its joint limits (the demo refuses it, with the reason, if it
    // is singular: `a_robot_that_starts_singular`).
    let q = start_posture_for::<Unknown7, 7>(None).expect("middle of the limits");
    let mid =
        SVector::<f64, 7>::from_fn(|i, _| 0.5 * (arm7::JOINT_LIMITS[i].lower + arm7::JOINT_LIMITS[i].upper));
    assert_eq!(q, mid);
    // A robot without position limits: no posture to take, say so.
    let e = start_posture_for::<TwoJoints, 2>(None).err().unwrap_or_default();
    assert!(e.contains("joint 'a' has no position limits"), "{e}");
    println!("{e}");
}
