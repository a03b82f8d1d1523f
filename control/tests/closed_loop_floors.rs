//! The floors on the demo scenario (arm7, no noise), measured over the last 4 s of the
//! real scenario: adaptive RMS normal-force error ≤ 0.02 N and RMS in-plane error ≤ 0.01 mm;
//! adaptation off at least 100× worse in RMS force error; the known-parameter law beside them.
//! On the base parameters, which the demo adapts by default. The same with task dimension 6
//! (position and orientation, the tool turned to vertical during the approach and held
//! there), where the adaptive RMS orientation error must also be ≤ 0.1 mrad.

use dyngen_control::sim::{start_posture, Demo, DemoOptions, RunKind, RunStatus, Summary};
use dyngen_generated::arm7;

fn run(kind: RunKind) -> Summary {
    run_task::<3>(kind)
}

fn run_task<const T: usize>(kind: RunKind) -> Summary {
    let q0 = start_posture::<7>("arm7").expect("arm7 start posture");
    let demo = Demo::<arm7::Base, 7, { arm7::BASE_PARAMETER_COUNT }, T>::new(DemoOptions::default(), q0)
        .expect("valid demo");
    let res = demo.run(kind, &mut |_| {}).expect("valid controller");
    assert_eq!(res.status, RunStatus::Completed, "{kind:?}");
    assert!((res.samples.last().expect("samples").t - demo.scenario.duration()).abs() < 1e-9);
    let s = res.summary(demo.metrics_from());
    println!("T = {T}, {kind:?}: {s:?}");
    s
}

#[test]
fn adaptive_meets_the_floors_and_adaptation_off_is_far_worse() {
    let adaptive = run(RunKind::Adaptive);
    let off = run(RunKind::AdaptationOff);
    let known = run(RunKind::KnownParameters);
    assert_position_and_force_floors(&adaptive);
    assert_adaptation_matters(&adaptive, &off);
    // The known-parameter law has only the sampling to fight: it must do better still.
    assert!(known.rms_force_error <= adaptive.rms_force_error);
    assert!(known.rms_in_plane_error <= 1e-5);
    // Null space regulated: the posture error's projection is small at the end.
    assert!(adaptive.final_null_error < 1e-3, "{}", adaptive.final_null_error);
}

#[test]
fn with_orientation_rows_the_floors_hold_and_the_tool_stays_vertical() {
    let adaptive = run_task::<6>(RunKind::Adaptive);
    let off = run_task::<6>(RunKind::AdaptationOff);
    assert_position_and_force_floors(&adaptive);
    assert!(
        adaptive.rms_orientation_error <= 1e-4,
        "RMS orientation error {} rad",
        adaptive.rms_orientation_error
    );
    assert_adaptation_matters(&adaptive, &off);
}

/// The floors over the last 4 s: RMS force error ≤ 0.02 N, in-plane ≤ 0.01 mm.
fn assert_position_and_force_floors(adaptive: &Summary) {
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
