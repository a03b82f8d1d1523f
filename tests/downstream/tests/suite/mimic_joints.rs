//! Generated code of a robot with mimic joints (`codegen/tests/data/mimic/mimic_arm.urdf`:
//! `elbow` follows `shoulder` with multiplier 1.5 and offset 0.3, `counterweight` follows
//! `base_yaw` with multiplier −1 and offset 0.2), compiled by this crate's build script, against
//! the generic dynamics at random states: every function takes the three coordinates.

use dyngen_codegen::description::load;
use dyngen_codegen::dynamics::NumericDynamics;
use dyngen_downstream_example::{mimic_arm, MimicArm};
use dyngen_runtime::nalgebra::SVector;
use dyngen_runtime::prelude::*;
use dyngen_runtime::{f64x4, pack, unpack, JointTrigLanes, SplitMix64};
use std::path::Path;

fn assert_close(what: &str, generated: &[f64], generic: &[f64]) {
    assert_within(what, generated, generic, 1e-10);
}

/// `generated` equals `generic` to `tol` relative to the largest entry of `generic` (at least 1).
pub(super) fn assert_within(what: &str, generated: &[f64], generic: &[f64], tol: f64) {
    assert_eq!(generated.len(), generic.len(), "{what}: sizes");
    let scale = generic.iter().fold(1.0_f64, |m, x| m.max(x.abs()));
    let err = generated
        .iter()
        .zip(generic)
        .fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()));
    assert!(err <= tol * scale, "{what}: {err:e} (scale {scale:e})");
}

#[test]
fn generated_mimic_arm_matches_generic_dynamics() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../codegen/tests/data/mimic/mimic_arm.yaml");
    let model = load(&path).unwrap_or_else(|e| panic!("{e}")).model;
    let generic = NumericDynamics::new(&model);
    assert_eq!(mimic_arm::DOF, 3);
    assert_eq!(
        mimic_arm::PARAMETER_COUNT,
        50,
        "ten per body, mimic joints' bodies included"
    );
    assert_eq!(mimic_arm::JOINT_NAMES, ["base_yaw", "shoulder", "slider"]);
    assert_eq!(mimic_arm::JOINT_LIMITS[1].upper, 1.2);
    assert_eq!(MimicArm::parameters().as_slice(), model.parameters().as_slice());
    let mut rng = SplitMix64::new(13);
    for _ in 0..50 {
        let mut draw = |r: f64| SVector::<f64, 3>::from_fn(|_, _| rng.uniform((-r, r)));
        let (q, qd, v, a) = (draw(1.2), draw(2.0), draw(2.0), draw(5.0));
        let t = JointTrig::new(&q);
        let (q, qd_s, v_s, a_s) = (q.as_slice(), qd.as_slice(), v.as_slice(), a.as_slice());
        let pose = MimicArm::forward_kinematics(&t);
        let (rot, pos) = generic.end_effector_pose(q);
        assert_close("pose rotation", pose.rotation.as_slice(), rot.as_slice());
        assert_close("pose translation", pose.translation.as_slice(), pos.as_slice());
        assert_close(
            "J",
            MimicArm::jacobian(&t).as_slice(),
            generic.jacobian(q).as_slice(),
        );
        assert_close(
            "J̇",
            MimicArm::jacobian_dot(&t, &qd).as_slice(),
            generic.jacobian_dot(q, qd_s).as_slice(),
        );
        assert_close(
            "D",
            MimicArm::mass_matrix(&t).as_slice(),
            generic.mass_matrix(q).as_slice(),
        );
        let c = generic.coriolis_matrix(q, qd_s);
        assert_close("C", MimicArm::coriolis_matrix(&t, &qd).as_slice(), c.as_slice());
        assert_close(
            "g",
            MimicArm::gravity(&t).as_slice(),
            generic.gravity_torque(q).as_slice(),
        );
        let tau = generic.inverse_dynamics(q, qd_s, a_s);
        assert_close(
            "τ",
            MimicArm::inverse_dynamics(&t, &qd, &a).as_slice(),
            tau.as_slice(),
        );
        let sl = generic.slotine_li(q, qd_s, v_s, a_s, true);
        assert_close(
            "Slotine–Li",
            MimicArm::slotine_li(&t, &qd, &v, &a).as_slice(),
            sl.as_slice(),
        );
        let y = generic.regressor(q, qd_s, v_s, a_s);
        assert_close("Y", MimicArm::regressor(&t, &qd, &v, &a).as_slice(), y.as_slice());
        let y_b =
            MimicArm::base_regressor(&t, &qd, &v, &a) * MimicArm::base_parameters(&MimicArm::parameters());
        assert_close("Y_b θ_b", y_b.as_slice(), sl.as_slice());
        // The adaptive law's products without the regressor (with r = a).
        let theta = MimicArm::parameters();
        let (y_theta, y_tr_r) = MimicArm::regressor_products(&t, &qd, &v, &a, &theta, &a);
        assert_close("Y θ", y_theta.as_slice(), sl.as_slice());
        let y_tr_a: Vec<f64> = (0..y.ncols())
            .map(|c| (0..y.nrows()).map(|i| y[(i, c)] * a_s[i]).sum())
            .collect();
        assert_close("Yᵀ r", y_tr_r.as_slice(), &y_tr_a);
        let theta_b = MimicArm::base_parameters(&theta);
        let (y_b_theta, _) = MimicArm::base_regressor_products(&t, &qd, &v, &a, &theta_b, &a);
        assert_close("Y_b θ_b without Y_b", y_b_theta.as_slice(), sl.as_slice());
        let tau_v = SVector::<f64, 3>::from_column_slice(tau.as_slice());
        assert_close("FD", MimicArm::forward_dynamics(&t, &qd, &tau_v).as_slice(), a_s);
        let minv = generic.mass_matrix_inverse(q);
        assert_close(
            "D⁻¹",
            MimicArm::mass_matrix_inverse(&t).as_slice(),
            minv.as_slice(),
        );
        let (dq, dv) = MimicArm::inverse_dynamics_derivatives(&t, &qd, &a);
        let (gq, gv) = generic.inverse_dynamics_derivatives(q, qd_s, a_s);
        assert_close("∂τ/∂q", dq.as_slice(), gq.as_slice());
        assert_close("∂τ/∂q̇", dv.as_slice(), gv.as_slice());
        let (dq, dv) = MimicArm::forward_dynamics_derivatives(&t, &qd, &tau_v);
        let (gq, gv) = generic.forward_dynamics_derivatives(q, qd_s, tau.as_slice());
        assert_close("∂q̈/∂q", dq.as_slice(), gq.as_slice());
        assert_close("∂q̈/∂q̇", dv.as_slice(), gv.as_slice());
    }
}

/// The lane functions (four states per call) equal the scalar ones, mimic joints' own sines
/// (multiplier 1.5) taken lane by lane: `τ` bit for bit, the base regressor to rounding (the
/// scalar function computes its columns four rows at a time).
#[test]
fn generated_mimic_arm_lanes_equal_the_scalar_functions() {
    let mut rng = SplitMix64::new(29);
    let mut draw = |r: f64| -> Vec<SVector<f64, 3>> {
        (0..4)
            .map(|_| SVector::<f64, 3>::from_fn(|_, _| rng.uniform((-r, r))))
            .collect()
    };
    let (q, qd, qdd) = (draw(1.2), draw(2.0), draw(5.0));
    let t = JointTrigLanes::new(&pack::<f64x4, 3>(&q));
    let (qd_l, qdd_l) = (pack::<f64x4, 3>(&qd), pack::<f64x4, 3>(&qdd));
    let tau = MimicArm::inverse_dynamics_lanes(&t, &qd_l, &qdd_l);
    let y_b = MimicArm::base_torque_regressor_lanes(&t, &qd_l, &qdd_l);
    for k in 0..4 {
        let scalar = JointTrig::new(&q[k]);
        assert_eq!(
            unpack(&tau, k),
            MimicArm::inverse_dynamics(&scalar, &qd[k], &qdd[k]),
            "lane {k}"
        );
        let y_b_scalar = MimicArm::base_torque_regressor(&scalar, &qd[k], &qdd[k]);
        let scale = y_b_scalar.amax().max(1.0);
        for (c, column) in y_b.iter().enumerate() {
            let gap = (unpack(column, k) - y_b_scalar.column(c)).amax();
            assert!(gap <= 1e-13 * scale, "lane {k}, column {c}: {gap:e} off");
        }
    }
}
