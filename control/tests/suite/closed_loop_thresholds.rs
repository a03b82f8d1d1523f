//! The acceptance thresholds on the demo scenario (arm7, no noise), measured over the last 4 s of the
//! real scenario: adaptive RMS normal-force error ≤ 0.02 N and RMS in-plane error ≤ 0.01 mm;
//! adaptation off at least 100× worse in RMS force error; the known-parameter law beside them.
//! On the base parameters, which the demo adapts by default. The same with task dimension 6
//! (position and orientation, the tool turned to vertical during the approach and held
//! there), where the adaptive RMS orientation error must also be ≤ 0.1 mrad.
//!
//! With true joint friction and armature (arm7_friction: the true robot's at 1.25× / 2× its
//! nominal values), the pose task: adapting the joint terms against holding them, from no
//! friction model at all (the acceptance threshold: the force error at least 5× lower) and from the
//! nominal values. With the composite adaptation, adapting the joint terms lowers the force
//! error at least 10× against the rigid-body law alone and at least 2× against the nominal
//! joint terms held; with its weight 0 it is the Slotine–Li law, to the bit.

use dyngen_control::controller::Composite;
use dyngen_control::sim::{start_posture_for, Demo, DemoOptions, RunKind, RunStatus, Summary};
use dyngen_generated::{arm7, arm7_friction};
use dyngen_runtime::Parameterization;
use std::sync::OnceLock;

fn run(kind: RunKind) -> Summary {
    run_task::<3>(kind)
}

fn run_task<const T: usize>(kind: RunKind) -> Summary {
    run_on::<arm7::Base, { arm7::BASE_PARAMETER_COUNT }, T>(kind)
}

/// One run of the demo (default options) on the robot of `Z`.
fn run_on<Z: Parameterization<7, M>, const M: usize, const T: usize>(kind: RunKind) -> Summary {
    run_with::<Z, M, T>(kind, DemoOptions::default())
}

fn run_with<Z: Parameterization<7, M>, const M: usize, const T: usize>(
    kind: RunKind,
    options: DemoOptions,
) -> Summary {
    let q0 = start_posture_for::<Z::Robot, 7>(None).expect("start posture");
    let demo = Demo::<Z, 7, M, T>::new(options, q0).expect("valid demo");
    let res = demo.run(kind, &mut |_| {}).expect("valid controller");
    assert_eq!(res.status, RunStatus::Completed, "{kind:?}");
    assert!((res.samples.last().expect("samples").t - demo.scenario.duration()).abs() < 1e-9);
    let s = res.summary(demo.metrics_from());
    println!("T = {T}, {kind:?}: {s:?}");
    s
}

#[test]
fn adaptive_meets_the_thresholds_and_adaptation_off_is_far_worse() {
    let adaptive = run(RunKind::Adaptive);
    let off = run(RunKind::AdaptationOff);
    let known = run(RunKind::KnownParameters);
    assert_position_and_force_thresholds(&adaptive);
    assert_adaptation_matters(&adaptive, &off);
    // The known-parameter law has only the sampling to fight: it must do better still.
    assert!(known.rms_force_error <= adaptive.rms_force_error);
    assert!(known.rms_in_plane_error <= 1e-5);
    // Null space regulated: the posture error's projection is small at the end.
    assert!(adaptive.final_null_error < 1e-3, "{}", adaptive.final_null_error);
}

#[test]
fn with_orientation_rows_the_thresholds_hold_and_the_tool_stays_vertical() {
    let adaptive = run_task::<6>(RunKind::Adaptive);
    let off = run_task::<6>(RunKind::AdaptationOff);
    assert_position_and_force_thresholds(&adaptive);
    assert!(
        adaptive.rms_orientation_error <= 1e-4,
        "RMS orientation error {} rad",
        adaptive.rms_orientation_error
    );
    assert_adaptation_matters(&adaptive, &off);
}

/// The acceptance threshold: a controller that starts with no joint friction or armature in its model
/// (`θ̂(0)` of the joint terms 0), pose task (m = 6: the tool held vertical, so the wrist
/// joints move and their friction matters). Adapting the joint terms (default gain) lowers the
/// RMS force error at least 5× against the same controller with them held at 0 (the rigid-body
/// law alone), the orientation error at least 100× and the in-plane error at least 5×.
#[test]
fn with_true_friction_adapting_the_joint_terms_lowers_the_force_error_5x() {
    type Z = arm7_friction::Base;
    const M: usize = arm7_friction::BASE_PARAMETER_COUNT;
    let options = DemoOptions {
        joint_estimate_scale: 0.0,
        ..DemoOptions::default()
    };
    let adapted = run_with::<Z, M, 6>(RunKind::Adaptive, options);
    let unmodelled = joint_terms_held(0.0);
    assert_lowered(
        &unmodelled,
        &adapted,
        [5.0, 100.0, 5.0],
        "friction unmodelled ÷ adapted",
    );
    assert!(
        adapted.rms_force_error <= 0.05,
        "RMS force error {} N",
        adapted.rms_force_error
    );
}

/// Starting from the description's nominal joint terms (half the true friction), pose task.
/// Adapting them lowers the RMS orientation error at least 5× and the in-plane error at least
/// 3× against holding them at nominal; the force error stays within 0.05 N in both. (Here the
/// force error is not lowered: a half-right friction model held is already as good as the
/// inertial adaptation allows; see the README.)
#[test]
fn with_true_friction_adapting_nominal_joint_terms_lowers_the_tracking_errors() {
    type Z = arm7_friction::Base;
    const M: usize = arm7_friction::BASE_PARAMETER_COUNT;
    let adapted = run_on::<Z, M, 6>(RunKind::Adaptive);
    let nominal = joint_terms_held(1.0);
    assert!(
        nominal.rms_orientation_error >= 5.0 * adapted.rms_orientation_error,
        "orientation: joint terms nominal {} rad vs adapted {} rad",
        nominal.rms_orientation_error,
        adapted.rms_orientation_error
    );
    assert!(
        nominal.rms_in_plane_error >= 3.0 * adapted.rms_in_plane_error,
        "in-plane: joint terms nominal {} m vs adapted {} m",
        nominal.rms_in_plane_error,
        adapted.rms_in_plane_error
    );
    for s in [&adapted, &nominal] {
        assert!(
            s.rms_force_error <= 0.05,
            "RMS force error {} N",
            s.rms_force_error
        );
    }
}

/// The composite adaptation from no friction model at all (pose task, as above): the force
/// error at least 10× lower than the rigid-body law's alone (the joint terms held at 0, the
/// Slotine–Li law), the orientation error at least 100× and the in-plane error at least 5×.
#[test]
fn with_true_friction_the_composite_adaptation_lowers_the_force_error_10x() {
    type Z = arm7_friction::Base;
    const M: usize = arm7_friction::BASE_PARAMETER_COUNT;
    let options = DemoOptions {
        joint_estimate_scale: 0.0,
        ..composite()
    };
    let adapted = run_with::<Z, M, 6>(RunKind::Composite, options);
    let unmodelled = joint_terms_held(0.0);
    assert_lowered(
        &unmodelled,
        &adapted,
        [10.0, 100.0, 5.0],
        "friction unmodelled ÷ composite",
    );
}

/// The composite adaptation from the nominal joint terms (half the true friction), pose task:
/// adapting them lowers the force error at least 2× against holding them at nominal (the
/// Slotine–Li law, which adapting them with does not lower it; see the test above), and the
/// orientation error at least 5×.
#[test]
fn with_true_friction_the_composite_adaptation_of_nominal_joint_terms_halves_the_force_error() {
    type Z = arm7_friction::Base;
    const M: usize = arm7_friction::BASE_PARAMETER_COUNT;
    let adapted = run_with::<Z, M, 6>(RunKind::Composite, composite());
    let nominal = joint_terms_held(1.0);
    let ratio = nominal.rms_force_error / adapted.rms_force_error;
    assert!(
        ratio >= 2.0,
        "force: joint terms nominal {} N ÷ composite {} N = {ratio:.2} < 2",
        nominal.rms_force_error,
        adapted.rms_force_error
    );
    assert!(
        nominal.rms_orientation_error >= 5.0 * adapted.rms_orientation_error,
        "orientation: joint terms nominal {} rad vs composite {} rad",
        nominal.rms_orientation_error,
        adapted.rms_orientation_error
    );
}

/// The composite adaptation with `R = 0` is the Slotine–Li law: the same run to the bit (the
/// prediction filter runs, its error is weighted by 0). Arm7 with joint friction, pose task,
/// every regressor column in use; a short circle.
#[test]
fn the_composite_adaptation_with_zero_weight_is_the_slotine_li_law() {
    type Z = arm7_friction::Base;
    const M: usize = arm7_friction::BASE_PARAMETER_COUNT;
    let options = DemoOptions {
        composite: Some(Composite {
            weight: 0.0,
            ..Composite::default()
        }),
        circle_time: 1.0,
        ..DemoOptions::default()
    };
    let q0 = start_posture_for::<<Z as Parameterization<7, M>>::Robot, 7>(None).expect("start posture");
    let demo = Demo::<Z, 7, M, 6>::new(options, q0).expect("valid demo");
    let slotine_li = demo
        .run(RunKind::Adaptive, &mut |_| {})
        .expect("valid controller");
    let composite = demo
        .run(RunKind::Composite, &mut |_| {})
        .expect("valid controller");
    assert_eq!(slotine_li.status, RunStatus::Completed);
    assert_eq!(slotine_li.samples.len(), composite.samples.len());
    // The prediction error is computed (and not 0) but weighted by 0.
    assert!(composite.samples.iter().any(|s| s.prediction_error > 1e-3));
    for (a, b) in slotine_li.samples.iter().zip(&composite.samples) {
        let strip = |s: &dyngen_control::sim::Sample| dyngen_control::sim::Sample {
            tick_ns: 0.0,
            prediction_error: 0.0,
            ..*s
        };
        assert_eq!(strip(a), strip(b), "at t = {}", a.t);
    }
}

/// The run [`RunKind::AdaptiveJointTermsHeld`] on arm7_friction, pose task, with the joint
/// terms held at `scale` × nominal (0: the rigid-body law alone): run once for the tests that
/// compare the Slotine–Li and the composite adaptation with it (the harness runs them in one
/// process).
/// `held`'s force, orientation and in-plane errors are at least `thresholds` times `adapted`'s.
fn assert_lowered(held: &Summary, adapted: &Summary, thresholds: [f64; 3], what: &str) {
    let ratios = [
        ("force", held.rms_force_error / adapted.rms_force_error),
        (
            "orientation",
            held.rms_orientation_error / adapted.rms_orientation_error,
        ),
        ("in-plane", held.rms_in_plane_error / adapted.rms_in_plane_error),
    ];
    for ((error, ratio), threshold) in ratios.into_iter().zip(thresholds) {
        assert!(ratio >= threshold, "{error}: {what} = {ratio:.2} < {threshold}");
    }
}

fn joint_terms_held(scale: f64) -> Summary {
    static FROM_ZERO: OnceLock<Summary> = OnceLock::new();
    static FROM_NOMINAL: OnceLock<Summary> = OnceLock::new();
    let cell = if scale == 0.0 {
        &FROM_ZERO
    } else {
        assert_eq!(scale, 1.0, "only the two starts of the tests are kept");
        &FROM_NOMINAL
    };
    *cell.get_or_init(|| {
        let options = DemoOptions {
            joint_estimate_scale: scale,
            ..DemoOptions::default()
        };
        run_with::<arm7_friction::Base, { arm7_friction::BASE_PARAMETER_COUNT }, 6>(
            RunKind::AdaptiveJointTermsHeld,
            options,
        )
    })
}

/// [`DemoOptions::default`] with the composite adaptation at its default filter and weight.
fn composite() -> DemoOptions {
    DemoOptions {
        composite: Some(Composite::default()),
        ..DemoOptions::default()
    }
}

/// The acceptance thresholds over the last 4 s: RMS force error ≤ 0.02 N, in-plane ≤ 0.01 mm.
fn assert_position_and_force_thresholds(adaptive: &Summary) {
    assert!(
        adaptive.rms_force_error <= 0.02,
        "RMS force error {} N",
        adaptive.rms_force_error
    );
    assert!(
        adaptive.rms_in_plane_error <= 1e-5,
        "RMS in-plane error {} m",
        adaptive.rms_in_plane_error
    );
}

/// Without adaptation the force error is at least 100× the adaptive one.
fn assert_adaptation_matters(adaptive: &Summary, off: &Summary) {
    assert!(
        off.rms_force_error >= 100.0 * adaptive.rms_force_error,
        "adaptation off {} N vs adaptive {} N",
        off.rms_force_error,
        adaptive.rms_force_error
    );
}
