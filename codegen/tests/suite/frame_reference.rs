//! Every link frame of the Panda and the UR5 (`frames: all`) against Pinocchio 4.1: pose, `J`,
//! `J̇`, velocity and classical acceleration in the three reference frames, and inverse and
//! forward dynamics with external wrenches at frames (`rnea`/`aba` with `fext`), through the
//! generic dynamics (`NumericDynamics`).

use dyngen_codegen::description::load;
use dyngen_codegen::dynamics::NumericDynamics;
use dyngen_runtime::ReferenceFrame;
use dyngen_testkit::{assert_close, frame_fixture, workspace_root};
use nalgebra::{DMatrix, DVector};

const TOL: f64 = 1e-9;

fn as_matrix<R: nalgebra::Dim, C: nalgebra::Dim, S: nalgebra::storage::Storage<f64, R, C>>(
    m: &nalgebra::Matrix<f64, R, C, S>,
) -> DMatrix<f64> {
    DMatrix::from_fn(m.nrows(), m.ncols(), |i, j| m[(i, j)])
}

fn check(robot: &str) {
    let model = load(&workspace_root().join(format!("robots/{robot}.yaml")))
        .unwrap_or_else(|e| panic!("{e}"))
        .model;
    let dynamics = NumericDynamics::new(&model);
    let states = frame_fixture::load(robot);
    let names: Vec<&str> = model.frames().iter().map(|f| f.name.as_str()).collect();
    for f in &states[0].frames {
        assert!(names.contains(&f.name.as_str()), "{robot}: no frame {}", f.name);
    }
    for (k, s) in states.iter().enumerate() {
        for f in &s.frames {
            let at = |what: &str| format!("{robot} state {k} frame {}: {what}", f.name);
            let values = dynamics.frame_motion(&f.name, &s.q, &s.v).expect("the frame");
            let (rotation, translation) = values.pose();
            assert_close(
                &at("rotation"),
                &as_matrix(&rotation),
                &as_matrix(&f.rotation),
                TOL,
            );
            assert_close(
                &at("translation"),
                &as_matrix(&translation),
                &as_matrix(&f.translation),
                TOL,
            );
            for (i, reference) in ReferenceFrame::ALL.into_iter().enumerate() {
                let r = reference.keyword();
                assert_close(
                    &at(&format!("J {r}")),
                    &values.jacobian(reference),
                    &f.jacobian[i],
                    TOL,
                );
                assert_close(
                    &at(&format!("dJ {r}")),
                    &values.jacobian_time_variation(reference),
                    &f.jacobian_time_variation[i],
                    TOL,
                );
                assert_close(
                    &at(&format!("velocity {r}")),
                    &as_matrix(&values.velocity(reference)),
                    &as_matrix(&f.velocity[i]),
                    TOL,
                );
                assert_close(
                    &at(&format!("classical acceleration {r}")),
                    &as_matrix(&values.classical_acceleration(reference, &s.a)),
                    &as_matrix(&f.classical_acceleration[i]),
                    TOL,
                );
            }
        }
        // Wrenches act through each frame's Jacobian in the wrench's reference frame.
        let mut wrench_torques = DVector::zeros(model.dof());
        for w in &s.wrenches {
            let values = dynamics.frame_motion(&w.frame, &s.q, &s.v).expect("the frame");
            wrench_torques += values.jacobian(w.reference).tr_mul(&w.wrench);
        }
        let tau = dynamics.inverse_dynamics(&s.q, &s.v, &s.a) - &wrench_torques;
        assert_close(
            &format!("{robot} state {k}: rnea with fext"),
            &as_matrix(&tau),
            &as_matrix(&s.tau_fext),
            TOL,
        );
        let qdd = dynamics.forward_dynamics(&s.q, &s.v, (&s.tau_aba + &wrench_torques).as_slice());
        assert_close(
            &format!("{robot} state {k}: aba with fext"),
            &as_matrix(&qdd),
            &as_matrix(&s.qdd_fext),
            TOL,
        );
    }
}

#[test]
fn panda_frames_and_wrenches_match_pinocchio() {
    check("panda");
}

#[test]
fn ur5_frames_and_wrenches_match_pinocchio() {
    check("ur5");
}
