//! Without a payload the plant integrates with the generated forward dynamics; with one it keeps
//! the regressor and a Cholesky solve. Both must solve `D_true q̈ = τ − Jᵀ F̄ − (C q̇ + g)_true`,
//! checked here by the residual of that equation with the plant's own `D_true` and bias.

use dyngen_control::sim::{Gaussian, Payload, PlaneContact, Plant, PlantState};
use dyngen_generated::{arm7, panda, ur5};
use dyngen_runtime::nalgebra::Vector3;
use dyngen_runtime::{JointTrig, Kinematics, Parameterization};

fn residual_is_zero<Z: Parameterization<N, M>, const N: usize, const M: usize>(plant: &Plant<Z, N, M>) {
    let mut rng = Gaussian::new(3);
    for _ in 0..50 {
        let s = PlantState {
            q: rng.vector::<N>(1.5),
            qd: rng.vector::<N>(1.0),
        };
        let tau = rng.vector::<N>(20.0);
        let t = JointTrig::new(&s.q);
        let (qdd, force) = plant.acceleration(&s, &tau).expect("a positive definite D");
        let j = Z::Robot::jacobian(&t).fixed_rows::<3>(0).into_owned();
        let lhs = plant.mass_matrix(&t) * qdd + plant.slotine_li(&t, &s.qd, &s.qd);
        let rhs = tau - j.tr_mul(&force);
        let scale = rhs.amax().max(1.0);
        assert!((lhs - rhs).amax() / scale < 1e-10, "{}", Z::Robot::NAME);
    }
}

#[test]
fn plant_without_payload_solves_the_true_dynamics() {
    let contact = || PlaneContact::table(-10.0, 1e4);
    residual_is_zero(&Plant::<arm7::Standard, 7, 70>::new(
        arm7::Standard::description(),
        contact(),
    ));
    residual_is_zero(&Plant::<panda::Standard, 7, 70>::new(
        panda::Standard::description(),
        contact(),
    ));
    residual_is_zero(&Plant::<ur5::Base, 6, { ur5::BASE_PARAMETER_COUNT }>::new(
        ur5::Base::description(),
        contact(),
    ));
}

#[test]
fn plant_with_payload_solves_the_true_dynamics() {
    let payload = Payload {
        mass: 2.0,
        com: Vector3::new(0.02, 0.0, 0.08),
        size: Vector3::new(0.1, 0.1, 0.1),
    };
    let plant = Plant::<arm7::Standard, 7, 70>::with_payload(&payload, PlaneContact::table(-10.0, 1e4));
    assert_ne!(plant.parameters(), &arm7::Standard::description());
    residual_is_zero(&plant);
}
