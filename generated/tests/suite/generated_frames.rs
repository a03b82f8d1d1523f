//! The generated frame functions (`FrameKinematics`) and dynamics with external wrenches
//! (`WrenchDynamics`) of the committed Panda and UR5 (`frames: all`) against Pinocchio 4.1:
//! every link frame that moves, every reference frame, `rnea`/`aba` with `fext`; and the UR5's
//! again with `local` and `world` converted at run time (`frame_references: aligned`).

use dyngen_generated::{Panda, Ur5, Ur5AlignedFrames};
use dyngen_runtime::nalgebra::{DMatrix, SMatrix, SVector};
use dyngen_runtime::{
    ExternalWrench, ForwardDynamics, FrameKinematics, JointTrig, ReferenceFrame, RobotDynamics, RobotFrame,
    WrenchDynamics,
};
use dyngen_testkit::{assert_close, frame_fixture};

const TOL: f64 = 1e-9;

fn dm<const R: usize, const C: usize>(m: &SMatrix<f64, R, C>) -> DMatrix<f64> {
    DMatrix::from_column_slice(R, C, m.as_slice())
}

fn check<R, const N: usize, const P: usize>(robot: &str, end_effector: &str)
where
    R: FrameKinematics<N> + RobotDynamics<N, P> + ForwardDynamics<N, P>,
{
    let states = frame_fixture::load(robot);
    let generated: Vec<&str> = R::Frame::ALL.iter().map(|f| f.name()).collect();
    assert_eq!(
        generated[0], end_effector,
        "{robot}: the end-effector comes first"
    );
    for f in &states[0].frames {
        assert!(
            generated.contains(&f.name.as_str()),
            "{robot}: no generated frame {}",
            f.name
        );
    }
    for (k, s) in states.iter().enumerate() {
        let t = JointTrig::new(&SVector::<f64, N>::from_column_slice(&s.q));
        let qd = SVector::<f64, N>::from_column_slice(&s.v);
        let qdd = SVector::<f64, N>::from_column_slice(&s.a);
        for f in &s.frames {
            let at = |what: &str| format!("{robot} state {k} frame {}: {what}", f.name);
            let frame = R::Frame::from_name(&f.name).expect("a generated frame");
            let pose = R::frame_pose(frame, &t);
            assert_close(&at("rotation"), &dm(&pose.rotation), &dm(&f.rotation), TOL);
            assert_close(
                &at("translation"),
                &dm(&pose.translation),
                &dm(&f.translation),
                TOL,
            );
            for (i, reference) in ReferenceFrame::ALL.into_iter().enumerate() {
                let r = reference.keyword();
                let j = R::frame_jacobian(frame, reference, &t);
                assert_close(&at(&format!("J {r}")), &dm(&j), &f.jacobian[i], TOL);
                assert_close(
                    &at(&format!("dJ {r}")),
                    &dm(&R::frame_jacobian_time_variation(frame, reference, &t, &qd)),
                    &f.jacobian_time_variation[i],
                    TOL,
                );
                assert_close(
                    &at(&format!("velocity {r}")),
                    &dm(&R::frame_velocity(frame, reference, &t, &qd)),
                    &dm(&f.velocity[i]),
                    TOL,
                );
                assert_close(
                    &at(&format!("classical acceleration {r}")),
                    &dm(&R::frame_classical_acceleration(frame, reference, &t, &qd, &qdd)),
                    &dm(&f.classical_acceleration[i]),
                    TOL,
                );
            }
            // The fused form gives the same values as the three functions.
            let (pose_k, j_k, jd_k) = R::frame_kinematics(frame, &t, &qd);
            let lwa = ReferenceFrame::LocalWorldAligned;
            assert_close(
                &at("fused pose"),
                &dm(&pose_k.translation),
                &dm(&pose.translation),
                1e-14,
            );
            assert_close(
                &at("fused J"),
                &dm(&j_k),
                &dm(&R::frame_jacobian(frame, lwa, &t)),
                1e-14,
            );
            assert_close(
                &at("fused dJ"),
                &dm(&jd_k),
                &dm(&R::frame_jacobian_time_variation(frame, lwa, &t, &qd)),
                1e-14,
            );
        }
        // The end-effector is the first frame, and its functions are `Kinematics`' own.
        let ee = R::Frame::ALL[0];
        assert_eq!(
            R::frame_jacobian(ee, ReferenceFrame::LocalWorldAligned, &t),
            R::jacobian(&t)
        );
        assert_eq!(R::frame_pose(ee, &t), R::forward_kinematics(&t));

        let wrenches: Vec<ExternalWrench<R::Frame>> = s
            .wrenches
            .iter()
            .map(|w| ExternalWrench {
                frame: R::Frame::from_name(&w.frame).expect("a generated frame"),
                reference: w.reference,
                force: w.wrench.fixed_rows::<3>(0).into(),
                moment: w.wrench.fixed_rows::<3>(3).into(),
            })
            .collect();
        assert_close(
            &format!("{robot} state {k}: rnea with fext"),
            &dm(&R::inverse_dynamics_with_wrenches(&t, &qd, &qdd, &wrenches)),
            &DMatrix::from_column_slice(N, 1, s.tau_fext.as_slice()),
            TOL,
        );
        let tau = SVector::<f64, N>::from_column_slice(s.tau_aba.as_slice());
        assert_close(
            &format!("{robot} state {k}: aba with fext"),
            &dm(&R::forward_dynamics_with_wrenches(&t, &qd, &tau, &wrenches)),
            &DMatrix::from_column_slice(N, 1, s.qdd_fext.as_slice()),
            TOL,
        );
        // Slotine–Li at (v, a) = (q̇, q̈) is inverse dynamics, with wrenches too.
        assert_close(
            &format!("{robot} state {k}: Slotine–Li with wrenches"),
            &dm(&R::slotine_li_with_wrenches(&t, &qd, &qd, &qdd, &wrenches)),
            &DMatrix::from_column_slice(N, 1, s.tau_fext.as_slice()),
            TOL,
        );
    }
}

#[test]
fn panda_frames_and_wrenches_match_pinocchio() {
    check::<Panda, 7, 70>("panda", "panda_hand_tcp");
}

#[test]
fn ur5_frames_and_wrenches_match_pinocchio() {
    check::<Ur5, 6, 60>("ur5", "tool0");
}

#[test]
fn ur5_frames_converted_from_base_axes_match_pinocchio() {
    check::<Ur5AlignedFrames, 6, 60>("ur5", "tool0");
}
