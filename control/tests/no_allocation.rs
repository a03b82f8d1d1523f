//! A control tick allocates nothing: a counting global allocator sees no allocation while the
//! adaptive controller (with stiffness estimation) runs many ticks, at the end-effector and at
//! a named frame (the Panda's flange), and with the composite adaptation (its prediction
//! filter is fixed-size state of the controller).

use dyngen_control::controller::{Composite, Measurement};
use dyngen_control::sim::{start_posture, Demo, DemoOptions, PlantState, RunKind};
use dyngen_generated::{arm7, arm7_friction, panda};
use dyngen_runtime::nalgebra::SVector;
use dyngen_runtime::Parameterization;
use dyngen_testkit::allocations::{allocations, CountingAllocator};

#[global_allocator]
static GLOBAL: CountingAllocator = CountingAllocator;

/// Every task dimension: position (3), position and the tool axis (5), the full pose (6); and a
/// named frame as the controlled frame (its kinematics through a plain `fn` pointer). One test:
/// the allocation counter is shared by the threads the harness runs tests on.
#[test]
fn a_control_tick_allocates_nothing() {
    ticks_without_allocation::<3>();
    ticks_without_allocation::<5>();
    ticks_without_allocation::<6>();
    ticks_at_a_named_frame_without_allocation();
    composite_ticks_without_allocation();
}

fn composite_ticks_without_allocation() {
    let q0 = start_posture::<7>("arm7_friction").expect("arm7_friction start posture");
    let options = DemoOptions {
        composite: Some(Composite::default()),
        ..options()
    };
    let d = Demo::<arm7_friction::Base, 7, { arm7_friction::BASE_PARAMETER_COUNT }, 6>::new(options, q0)
        .expect("valid demo");
    ticks_of(&d, &q0, RunKind::Composite);
}

fn ticks_at_a_named_frame_without_allocation() {
    let q0 = start_posture::<7>("panda").expect("panda start posture");
    let d = Demo::<panda::Base, 7, { panda::BASE_PARAMETER_COUNT }, 6>::new_at_frame(
        options(),
        q0,
        panda::Frame::PandaLink8,
    )
    .expect("valid demo");
    ticks_of(&d, &q0, RunKind::Adaptive);
}

fn options() -> DemoOptions {
    DemoOptions {
        stiffness_estimation: Some((0.5, 20.0)),
        start_height: -0.001,
        ..DemoOptions::default()
    }
}

fn ticks_without_allocation<const T: usize>() {
    let q0 = start_posture::<7>("arm7").expect("arm7 start posture");
    let d = Demo::<arm7::Base, 7, { arm7::BASE_PARAMETER_COUNT }, T>::new(options(), q0).expect("valid demo");
    ticks_of(&d, &q0, RunKind::Adaptive);
}

fn ticks_of<Z: Parameterization<7, M>, const M: usize, const T: usize>(
    d: &Demo<Z, 7, M, T>,
    q0: &SVector<f64, 7>,
    kind: RunKind,
) {
    let q0 = *q0;
    let mut c = d.controller(kind).expect("valid controller");
    let desired: Vec<_> = (0..200).map(|k| d.scenario.desired(k as f64 * 0.05)).collect();
    let rest = PlantState::at_rest(q0);
    let force = d
        .plant
        .contact_force(&rest, &SVector::zeros())
        .expect("compliant");
    let mut acc = 0.0;
    let counted = allocations(|| {
        for (k, des) in desired.iter().enumerate() {
            let m = Measurement {
                q: q0 + SVector::from_element(1e-3 * k as f64),
                qd: SVector::from_element(0.01),
                force,
            };
            let out = c.tick(&m, des, 1e-3).expect("tick");
            acc += out.tau.sum();
        }
    });
    assert!(acc.is_finite());
    assert_eq!(
        counted, 0,
        "a control tick allocated (task dimension {T}, {kind:?})"
    );
    // The counter sees allocations on this thread: a control case must count one.
    assert_eq!(allocations(|| drop(std::hint::black_box(vec![1u8]))), 1);
}
