//! The plant computes the true dynamics through the regressor. With the description's
//! parameters it must equal the generated `D`, `C q̇ + g`, `g`; with a point payload at the
//! end-effector it must add exactly `m Jᵀ J` to `D` and `Jᵀ (m g₀)` to `g` (an oracle that
//! uses only the Jacobian).

use dyngen_generated::{Arm7, Panda, Ur5};
use dyngen_runtime::nalgebra::{SVector, Vector3};
use dyngen_runtime::sim::{Gaussian, Payload, PlaneContact, Plant};
use dyngen_runtime::{JointTrig, RobotDynamics};

fn rel(a: f64, scale: f64) -> f64 {
    a / scale.max(1.0)
}

fn matches_generated<R: RobotDynamics<N, P>, const N: usize, const P: usize>() {
    let plant = Plant::<R, N, P>::new(R::parameters(), PlaneContact::table(-10.0, 1e4));
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
    matches_generated::<Arm7, 7, 70>();
    matches_generated::<Panda, 7, 70>();
    matches_generated::<Ur5, 6, 60>();
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
    let plant = Plant::<Arm7, 7, 70>::with_payload(&payload, PlaneContact::table(-10.0, 1e4));
    let mut rng = Gaussian::new(11);
    for _ in 0..50 {
        let q: SVector<f64, 7> = rng.vector(1.5);
        let t = JointTrig::new(&q);
        let jp = Arm7::jacobian(&t).fixed_rows::<3>(0).into_owned();
        let dd = plant.mass_matrix(&t) - Arm7::mass_matrix(&t);
        assert!((dd - jp.transpose() * jp * m).amax() < 1e-10);
        let dg = plant.gravity(&t) - Arm7::gravity(&t);
        assert!((dg - jp.transpose() * Vector3::new(0.0, 0.0, m * 9.81)).amax() < 1e-9);
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
