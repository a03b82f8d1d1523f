//! The rigid plane is the limit of the compliant one as its stiffness grows. arm7 with the
//! demo's payload presses on a table under a smooth torque (gravity held, 20 N down, joints 1,
//! 4 and 6 driven by sines, so the tool slides 17 mm without leaving the table) from rest on
//! it; the compliant table starts at its static deflection (the rigid plane's force over `k`),
//! so neither starts with an impact. At `k` and `10 k` the compliant runs approach the rigid
//! one: positions as `1/k`, the force as `1/√k` (the compliant table's undamped oscillation
//! about the rigid force, excited by the moving load, has a force amplitude falling as `1/√k`).
//!
//! Not in closed loop: the controller's torque steps every millisecond (sample and hold) and
//! an undamped compliant table rings at `√(k/m)` after each step and after touch-down, which
//! is elastic where the rigid impact is plastic; there the force samples do not converge
//! (`docs/hybrid_force_demo.md`, *A rigid table*).

use dyngen_control::sim::{start_posture_for, Payload, PlaneContact, Plant, PlantState, RigidPlane, Surface};
use dyngen_generated::{arm7, Arm7};
use dyngen_runtime::nalgebra::{SVector, Vector3};
use dyngen_runtime::{JointTrig, Kinematics};

type Z = arm7::Base;
const M: usize = arm7::BASE_PARAMETER_COUNT;

/// The tool's position and the force on the table at each step.
fn press(
    plant: &Plant<Z, 7, M>,
    q0: &SVector<f64, 7>,
    tau: &dyn Fn(f64) -> SVector<f64, 7>,
) -> Vec<(Vector3<f64>, f64)> {
    let h = 1e-4;
    let mut s = PlantState::at_rest(*q0);
    (0..3000)
        .map(|i| {
            let u = tau(i as f64 * h);
            let force = -plant.contact_force(&s, &u).expect("force").z;
            let x = Arm7::forward_kinematics(&JointTrig::new(&s.q)).translation;
            s = plant.step(&s, &u, h).expect("step");
            (x, force)
        })
        .collect()
}

#[test]
fn a_compliant_table_approaches_the_rigid_one_as_its_stiffness_grows() {
    let q0 = start_posture_for::<Arm7, 7>(None).expect("start posture");
    let payload = Payload {
        mass: 1.5,
        com: Vector3::new(0.02, 0.0, 0.1),
        size: Vector3::new(0.08, 0.08, 0.06),
    };
    let t0 = JointTrig::new(&q0);
    let x0 = Arm7::forward_kinematics(&t0).translation;
    let mut plant = Plant::<Z, 7, M>::with_payload(&payload, RigidPlane::table(x0.z));
    let gravity = plant.gravity(&t0);
    let down = Arm7::jacobian(&t0).fixed_rows::<3>(0).transpose() * Vector3::z() * 20.0;
    let tau = move |t: f64| {
        let wave = |amplitude: f64, hz: f64| amplitude * (2.0 * std::f64::consts::PI * hz * t).sin();
        let mut u = gravity - down;
        u[0] += wave(3.0, 4.0);
        u[3] += wave(1.0, 3.0);
        u[5] += wave(1.0, 5.0);
        u
    };
    let rigid = press(&plant, &q0, &tau);
    let (lightest, heaviest) = rigid
        .iter()
        .fold((f64::INFINITY, 0.0_f64), |(a, b), (_, f)| (a.min(*f), b.max(*f)));
    assert!(
        lightest > 10.0,
        "the tool never leaves the table: {lightest} … {heaviest} N"
    );
    let slid = (rigid.last().expect("steps").0 - x0).norm();
    assert!(slid > 0.01, "the tool slides {slid} m");

    let differences = |k: f64, plant: &mut Plant<Z, 7, M>| {
        plant.contact = Surface::Compliant(PlaneContact::table(x0.z + rigid[0].1 / k, k));
        let compliant = press(plant, &q0, &tau);
        let position = rigid
            .iter()
            .zip(&compliant)
            .map(|(a, b)| (a.0 - b.0).norm())
            .fold(0.0, f64::max);
        let squares: f64 = rigid
            .iter()
            .zip(&compliant)
            .map(|(a, b)| (a.1 - b.1).powi(2))
            .sum();
        (position, (squares / rigid.len() as f64).sqrt())
    };
    let (position_1, force_1) = differences(1e6, &mut plant);
    let (position_2, force_2) = differences(1e7, &mut plant);
    println!(
        "k = 1e6: position {position_1:.3e} m, force RMS {force_1:.3e} N; \
         k = 1e7: {position_2:.3e} m, {force_2:.3e} N (rigid force {lightest:.2} … {heaviest:.2} N)"
    );
    assert!(position_2 <= position_1 / 8.0, "positions converge as 1/k");
    assert!(force_2 <= force_1 / 2.5, "the force converges as 1/√k");
    assert!(position_2 < 1e-6 && force_2 < 0.05);
}
