//! The generated named-frame functions (the group `frames`), per frame and reference, on the
//! Panda and the UR5, and on the UR5 with `LOCAL` and `WORLD` converted at run time
//! (`ur5_aligned`: `robots/ur5_aligned_frames.yaml`): the dyngen side of the comparison with
//! numeric Pinocchio 4.1 of `tools/compare_frames.py` (the Pinocchio side:
//! `tools/anchors/frames/`).
//!
//! Per robot, a tool frame (Panda `panda_link8`, the flange; UR5 `ee_link`) and a mid-chain
//! frame (Panda `panda_link4`, UR5 `forearm_link`): the pose, the Jacobian and its time
//! variation in each of the three references, the velocity and the classical acceleration
//! (LOCAL), and `frame_kinematics`; then, at the tool frame, inverse dynamics under one LOCAL
//! wrench, and `Kinematics::jacobian` (the end-effector, LOCAL_WORLD_ALIGNED) for reference.
//!
//! As in `dynamics.rs`, each call includes `JointTrig::new(q)` and inputs cycle through 256
//! precomputed random states. Groups are `<robot>/<function>/<frame>`, id `generated`, e.g.
//! `panda/frame_jacobian_local/panda_link8`; a reference is `local`, `world` or `lwa`
//! (LOCAL_WORLD_ALIGNED).
//! `cargo bench -p dyngen-generated --bench frames`.

// `common::model` is not needed here.
#[allow(dead_code)]
mod common;

use common::{cycle, states};
use criterion::{criterion_group, criterion_main, Criterion};
use dyngen_generated::{Panda, Ur5, Ur5AlignedFrames};
use dyngen_runtime::nalgebra::Vector3;
use dyngen_runtime::{
    ExternalWrench, FrameKinematics, JointTrig, ReferenceFrame, RobotFrame, WrenchDynamics,
};
use std::hint::black_box;

/// The reference's suffix in group names: `local`, `world`, `lwa` (LOCAL_WORLD_ALIGNED).
/// Criterion cuts directory names at 64 characters, which
/// `panda/frame_jacobian_time_variation_local_world_aligned/panda_link4` would exceed, and
/// two groups would then share (and overwrite) one directory.
fn suffix(reference: ReferenceFrame) -> &'static str {
    match reference {
        ReferenceFrame::LocalWorldAligned => "lwa",
        other => other.keyword(),
    }
}

/// The frame named `name` of robot `R`, or a panic naming it.
fn frame<R: FrameKinematics<N>, const N: usize>(name: &str) -> R::Frame {
    R::Frame::from_name(name).unwrap_or_else(|| panic!("no frame {name}"))
}

/// Every timed frame quantity of one frame.
fn bench_frame<R: FrameKinematics<N>, const N: usize>(
    c: &mut Criterion,
    robot: &str,
    name: &str,
    fixed: &[[dyngen_runtime::nalgebra::SVector<f64, N>; 4]],
) {
    let f = frame::<R, N>(name);
    let g = |quantity: &str| format!("{robot}/{quantity}/{name}");

    cycle(c, &g("frame_pose"), "generated", fixed, |[q, ..]| {
        black_box(R::frame_pose(f, &JointTrig::new(q)));
    });
    for reference in ReferenceFrame::ALL {
        let group = g(&format!("frame_jacobian_{}", suffix(reference)));
        cycle(c, &group, "generated", fixed, |[q, ..]| {
            black_box(R::frame_jacobian(f, reference, &JointTrig::new(q)));
        });
    }
    for reference in ReferenceFrame::ALL {
        let group = g(&format!("frame_jacobian_time_variation_{}", suffix(reference)));
        cycle(c, &group, "generated", fixed, |[q, qd, ..]| {
            black_box(R::frame_jacobian_time_variation(
                f,
                reference,
                &JointTrig::new(q),
                qd,
            ));
        });
    }
    cycle(c, &g("frame_velocity_local"), "generated", fixed, |[q, qd, ..]| {
        black_box(R::frame_velocity(
            f,
            ReferenceFrame::Local,
            &JointTrig::new(q),
            qd,
        ));
    });
    cycle(
        c,
        &g("frame_classical_acceleration_local"),
        "generated",
        fixed,
        |[q, qd, _, a]| {
            black_box(R::frame_classical_acceleration(
                f,
                ReferenceFrame::Local,
                &JointTrig::new(q),
                qd,
                a,
            ));
        },
    );
    cycle(c, &g("frame_kinematics"), "generated", fixed, |[q, qd, ..]| {
        black_box(R::frame_kinematics(f, &JointTrig::new(q), qd));
    });
}

fn bench_robot<R: WrenchDynamics<N, P>, const N: usize, const P: usize>(
    c: &mut Criterion,
    robot: &str,
    tool: &str,
    mid: &str,
) {
    // The states of `dynamics.rs`: q in ±π, velocities ±2, accelerations ±5
    // (`tools/anchors/frames/bench_frames.cpp` draws the same ones).
    let (_, fixed) = states::<N>(0x5eed, [(-2.0, 2.0), (-2.0, 2.0), (-5.0, 5.0)]);
    bench_frame::<R, N>(c, robot, tool, &fixed);
    bench_frame::<R, N>(c, robot, mid, &fixed);

    // One wrench at the tool frame, in its own axes (the anchor applies the same one).
    let wrench = [ExternalWrench {
        frame: frame::<R, N>(tool),
        reference: ReferenceFrame::Local,
        force: Vector3::new(10.0, -5.0, 20.0),
        moment: Vector3::new(0.5, -1.0, 0.25),
    }];
    cycle(
        c,
        &format!("{robot}/inverse_dynamics_with_wrenches/{tool}"),
        "generated",
        &fixed,
        |[q, qd, _, a]| {
            black_box(R::inverse_dynamics_with_wrenches(
                &JointTrig::new(q),
                qd,
                a,
                &wrench,
            ));
        },
    );
    // The end-effector's Jacobian (LOCAL_WORLD_ALIGNED), for reference.
    let end_effector = R::Frame::ALL[0].name();
    cycle(
        c,
        &format!("{robot}/jacobian/{end_effector}"),
        "generated",
        &fixed,
        |[q, ..]| {
            black_box(R::jacobian(&JointTrig::new(q)));
        },
    );
}

fn frames(c: &mut Criterion) {
    bench_robot::<Panda, 7, 70>(c, "panda", "panda_link8", "panda_link4");
    bench_robot::<Ur5, 6, 60>(c, "ur5", "ee_link", "forearm_link");
    bench_robot::<Ur5AlignedFrames, 6, 60>(c, "ur5_aligned", "ee_link", "forearm_link");
}

criterion_group! {
    name = benches;
    config = common::config();
    targets = frames
}
criterion_main!(benches);
