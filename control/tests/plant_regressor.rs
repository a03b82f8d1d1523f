//! The plant computes the true dynamics through the regressor. With the description's
//! parameters it must equal the generated `D`, `C q̇ + g`, `g`; with a point payload at the
//! end-effector it must add exactly `m Jᵀ J` to `D` and `Jᵀ (m g₀)` to `g` (an oracle that
//! uses only the Jacobian). Both in the standard and in the base parameters.

use dyngen_control::sim::{Gaussian, Payload, PlaneContact, Plant};
use dyngen_generated::{arm7, panda, ur5, Arm7, Panda, Ur5};
use dyngen_runtime::nalgebra::{SVector, Vector3};
use dyngen_runtime::{JointTrig, Kinematics, Parameterization, RobotDynamics};

fn rel(a: f64, scale: f64) -> f64 {
    a / scale.max(1.0)
}

fn matches_generated<R, Z, const N: usize, const P: usize, const M: usize>()
where
    R: RobotDynamics<N, P>,
    Z: Parameterization<N, M, Robot = R>,
{
    let plant = Plant::<Z, N, M>::new(Z::description(), PlaneContact::table(-10.0, 1e4));
    let mut rng = Gaussian::new(7);
    for _ in 0..50 {
        let q = rng.vector::<N>(1.5);
        let qd = rng.vector::<N>(1.0);
        let v = rng.vector::<N>(1.0);
        let t = JointTrig::new(&q);
        let d = R::mass_matrix(&t);
        assert!(
            rel((plant.mass_matrix(&t) - d).amax(), d.amax()) < 1e-10,
            "{}",
            R::NAME
        );
        let c = R::coriolis_matrix(&t, &qd);
        let g = R::gravity(&t);
        let sl = plant.slotine_li(&t, &qd, &v);
        assert!(rel((sl - (c * v + g)).amax(), g.amax()) < 1e-10, "{}", R::NAME);
        assert!(
            rel((plant.gravity(&t) - g).amax(), g.amax()) < 1e-10,
            "{}",
            R::NAME
        );
    }
}

#[test]
fn plant_through_the_regressor_equals_generated_at_description_parameters() {
    matches_generated::<Arm7, arm7::Standard, 7, 70, 70>();
    matches_generated::<Panda, panda::Standard, 7, 70, 70>();
    matches_generated::<Ur5, ur5::Standard, 6, 60, 60>();
    matches_generated::<Arm7, arm7::Base, 7, 70, { arm7::BASE_PARAMETER_COUNT }>();
    matches_generated::<Panda, panda::Base, 7, 70, { panda::BASE_PARAMETER_COUNT }>();
    matches_generated::<Ur5, ur5::Base, 6, 60, { ur5::BASE_PARAMETER_COUNT }>();
}

#[test]
fn point_payload_at_the_flange_adds_m_jt_j_and_its_weight() {
    // arm7's end-effector (flange) is 0.0549 m along z of the last body frame.
    let m = 1.5;
    let payload = Payload {
        mass: m,
        com: Vector3::new(0.0, 0.0, 0.0549),
        size: Vector3::zeros(),
    };
    let standard = Plant::<arm7::Standard, 7, 70>::with_payload(&payload, PlaneContact::table(-10.0, 1e4));
    let base = Plant::<arm7::Base, 7, { arm7::BASE_PARAMETER_COUNT }>::with_payload(
        &payload,
        PlaneContact::table(-10.0, 1e4),
    );
    let mut rng = Gaussian::new(11);
    for _ in 0..50 {
        let q: SVector<f64, 7> = rng.vector(1.5);
        let t = JointTrig::new(&q);
        let jp = Arm7::jacobian(&t).fixed_rows::<3>(0).into_owned();
        for (d, g) in [
            (standard.mass_matrix(&t), standard.gravity(&t)),
            (base.mass_matrix(&t), base.gravity(&t)),
        ] {
            let dd = d - Arm7::mass_matrix(&t);
            assert!((dd - jp.transpose() * jp * m).amax() < 1e-10);
            let dg = g - Arm7::gravity(&t);
            assert!((dg - jp.transpose() * Vector3::new(0.0, 0.0, m * 9.81)).amax() < 1e-9);
        }
    }
}

#[test]
fn box_payload_parameters() {
    // A 2 kg box 0.1 × 0.2 × 0.3 m centred at c = (0.1, 0, 0): I_xx = m(b²+c²)/12, I_yy picks
    // up m·cx² (parallel axis), I_xy stays 0 since c_y = 0.
    let p = Payload {
        mass: 2.0,
        com: Vector3::new(0.1, 0.0, 0.0),
        size: Vector3::new(0.1, 0.2, 0.3),
    }
    .parameters();
    let expect = [
        2.0,
        0.2,
        0.0,
        0.0,
        2.0 * (0.04 + 0.09) / 12.0,
        0.0,
        2.0 * (0.01 + 0.09) / 12.0 + 2.0 * 0.01,
        0.0,
        0.0,
        2.0 * (0.01 + 0.04) / 12.0 + 2.0 * 0.01,
    ];
    for (a, b) in p.iter().zip(expect) {
        assert!((a - b).abs() < 1e-15, "{p:?}");
    }
}
