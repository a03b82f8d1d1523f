//! The plant on a rigid plane, against oracles that use only the kinematics and the plant's
//! own `D` and `C q̇ + g`: a held point's height along the motion accelerates as the
//! Baumgarte terms ask (so the row and its drift are the point's), `τ + Jᵀ n λ` is the torque
//! the motion needs, a pulling torque opens the contact (the free dynamics), a tool dropped on
//! the plane lands once and never enters it by more than 1e-10 m, and a plane the plant cannot
//! simulate, or a posture that cannot press on it, is an error. On arm7 with a heavy tool, the
//! UR5 (light links, base parameters) and the Panda pressing with its flange.

use dyngen_control::sim::{Gaussian, Payload, Plant, PlantError, PlantState, RigidPlane};
use dyngen_generated::{arm7, panda, ur5, Arm7, Panda};
use dyngen_runtime::nalgebra::{SMatrix, SVector, Vector3};
use dyngen_runtime::{FrameKinematics, JointTrig, Kinematics, Parameterization};

/// What the tests need of one robot: the plant and where its contact point is.
struct Case<Z: Parameterization<N, M>, const N: usize, const M: usize> {
    plant: Plant<Z, N, M>,
    point: fn(&SVector<f64, N>) -> Vector3<f64>,
    jacobian: fn(&SVector<f64, N>) -> SMatrix<f64, 3, N>,
}

fn heavy_tool() -> Payload {
    Payload {
        mass: 20.0,
        com: Vector3::new(0.03, 0.0, 0.15),
        size: Vector3::new(0.2, 0.2, 0.3),
    }
}

fn arm7_heavy_tool() -> Case<arm7::Base, 7, { arm7::BASE_PARAMETER_COUNT }> {
    Case {
        plant: Plant::with_payload(&heavy_tool(), RigidPlane::table(0.0)),
        point: |q| Arm7::forward_kinematics(&JointTrig::new(q)).translation,
        jacobian: |q| Arm7::jacobian(&JointTrig::new(q)).fixed_rows::<3>(0).into_owned(),
    }
}

fn ur5_light() -> Case<ur5::Base, 6, { ur5::BASE_PARAMETER_COUNT }> {
    Case {
        plant: Plant::new(ur5::Base::description(), RigidPlane::table(0.0)),
        point: |q| ur5::Ur5::forward_kinematics(&JointTrig::new(q)).translation,
        jacobian: |q| {
            ur5::Ur5::jacobian(&JointTrig::new(q))
                .fixed_rows::<3>(0)
                .into_owned()
        },
    }
}

fn panda_flange() -> Case<panda::Base, 7, { panda::BASE_PARAMETER_COUNT }> {
    Case {
        plant: Plant::new(panda::Base::description(), RigidPlane::table(0.0))
            .with_contact_frame(panda::Frame::PandaLink8),
        point: |q| Panda::frame_pose(panda::Frame::PandaLink8, &JointTrig::new(q)).translation,
        jacobian: |q| {
            Panda::frame_jacobian(
                panda::Frame::PandaLink8,
                dyngen_runtime::ReferenceFrame::LocalWorldAligned,
                &JointTrig::new(q),
            )
            .fixed_rows::<3>(0)
            .into_owned()
        },
    }
}

/// A random state and a plane through its contact point, turned to a random normal, the
/// point `height` above it (negative: inside) and moving along the normal at `rate`.
fn state_on_a_plane<Z: Parameterization<N, M>, const N: usize, const M: usize>(
    case: &mut Case<Z, N, M>,
    rng: &mut Gaussian,
    height: f64,
    rate: f64,
) -> (PlantState<N>, Vector3<f64>) {
    let q = rng.vector::<N>(1.0);
    let normal = rng.vector::<3>(1.0).normalize();
    let row = normal.transpose() * (case.jacobian)(&q);
    let qd = rng.vector::<N>(1.0);
    let qd = qd + row.transpose() * ((rate - (row * qd)[0]) / row.norm_squared());
    case.plant.contact = RigidPlane {
        point: (case.point)(&q) - normal * height,
        normal,
        ..RigidPlane::table(0.0)
    }
    .into();
    (PlantState { q, qd }, normal)
}

/// `g̈` of the contact point's height along `q(t) = q + q̇ t + ½ q̈ t²`, by central differences.
fn height_acceleration<const N: usize>(
    point: fn(&SVector<f64, N>) -> Vector3<f64>,
    s: &PlantState<N>,
    qdd: &SVector<f64, N>,
    normal: &Vector3<f64>,
) -> f64 {
    let g = |t: f64| normal.dot(&point(&(s.q + s.qd * t + qdd * (0.5 * t * t))));
    let d2 = |h: f64| (g(h) - 2.0 * g(0.0) + g(-h)) / (h * h);
    // Richardson: the O(h²) error of the central difference cancels.
    (4.0 * d2(1e-3) - d2(2e-3)) / 3.0
}

fn held_rows_follow_baumgarte<Z: Parameterization<N, M>, const N: usize, const M: usize>(
    mut case: Case<Z, N, M>,
) {
    let mut rng = Gaussian::new(11);
    // On the plane and still along its normal; and inside it, leaving.
    for (height, rate) in [(0.0, 0.0), (-1e-4, 0.01)] {
        for _ in 0..10 {
            let (s, normal) = state_on_a_plane(&mut case, &mut rng, height, rate);
            let t = JointTrig::new(&s.q);
            let row = normal.transpose() * (case.jacobian)(&s.q);
            let bias = case.plant.slotine_li(&t, &s.qd, &s.qd);
            // Pressing into the plane with 2 kN more than the motion needs (more than the
            // heavy tool's effective mass times the point's classical acceleration).
            let tau = bias - row.transpose() * 2000.0;
            let (qdd, force) = case.plant.acceleration(&s, &tau).expect("held");
            let push = -normal.dot(&force);
            assert!(push > 0.0, "the plane pushes: {push}");
            assert!(
                (force + normal * push).norm() <= 1e-12 * push,
                "F̄ is along the normal"
            );
            let asked = -RigidPlane::KP * height - RigidPlane::KD * rate;
            let got = height_acceleration(case.point, &s, &qdd, &normal);
            assert!((got - asked).abs() < 1e-7, "g̈ = {got}, Baumgarte asks {asked}");
            // τ + Jᵀ n λ is what the motion needs: D q̈ + C q̇ + g.
            let needed = case.plant.mass_matrix(&t) * qdd + bias;
            let residual = (needed - tau - row.transpose() * push).amax();
            assert!(residual <= 1e-10 * tau.amax(), "residual {residual}");
        }
    }
}

#[test]
fn a_held_point_accelerates_along_the_normal_as_the_baumgarte_terms_ask() {
    held_rows_follow_baumgarte(arm7_heavy_tool());
    held_rows_follow_baumgarte(ur5_light());
    held_rows_follow_baumgarte(panda_flange());
}

fn pulling_opens<Z: Parameterization<N, M>, const N: usize, const M: usize>(mut case: Case<Z, N, M>) {
    let mut rng = Gaussian::new(12);
    for _ in 0..10 {
        let (s, normal) = state_on_a_plane(&mut case, &mut rng, 0.0, 0.0);
        let t = JointTrig::new(&s.q);
        let row = normal.transpose() * (case.jacobian)(&s.q);
        let bias = case.plant.slotine_li(&t, &s.qd, &s.qd);
        let tau = bias + row.transpose() * 2000.0;
        let (qdd, force) = case.plant.acceleration(&s, &tau).expect("free");
        assert_eq!(force, Vector3::zeros());
        let free = case
            .plant
            .mass_matrix(&t)
            .cholesky()
            .expect("D > 0")
            .solve(&(tau - bias));
        assert!((qdd - free).amax() <= 1e-10 * free.amax(), "the free dynamics");
        // And the point leaves the plane.
        assert!(height_acceleration(case.point, &s, &qdd, &normal) > 0.0);
    }
}

#[test]
fn a_pulling_torque_opens_the_contact() {
    pulling_opens(arm7_heavy_tool());
    pulling_opens(ur5_light());
    pulling_opens(panda_flange());
}

/// Dropped from 1 mm above the plane, pressed down with 10 N beyond gravity and pushed
/// sideways, for 0.3 s at the simulator's 5 kHz. Returns the deepest penetration.
fn drop_on_the_plane<Z: Parameterization<N, M>, const N: usize, const M: usize>(
    mut case: Case<Z, N, M>,
    q0: SVector<f64, N>,
) -> f64 {
    let drop = 1e-3;
    let x0 = (case.point)(&q0);
    let plane = RigidPlane::table(x0.z - drop);
    case.plant.contact = plane.into();
    let row = Vector3::z().transpose() * (case.jacobian)(&q0);
    let gravity = case.plant.gravity(&JointTrig::new(&q0));
    let mut sideways = SVector::<f64, N>::zeros();
    sideways[0] = 0.5;
    let tau = gravity - row.transpose() * 10.0 + sideways;
    let h = 2e-4;
    let mut s = PlantState::at_rest(q0);
    let (mut deepest, mut landed) = (f64::NEG_INFINITY, None);
    for step in 0..1500 {
        s = case.plant.step(&s, &tau, h).expect("step");
        let x = (case.point)(&s.q);
        deepest = deepest.max(plane.point.z - x.z);
        let force = case.plant.contact_force(&s, &tau).expect("force");
        match landed {
            None if force.z < 0.0 => landed = Some(step),
            // Landed once, stays: a plastic impact does not bounce.
            Some(first) => assert!(
                force.z < 0.0,
                "lifted off at step {step} after landing at {first}"
            ),
            None => {}
        }
    }
    let first = landed.expect("the tool lands");
    println!("landed at {:.1} ms", first as f64 * h * 1e3);
    deepest
}

#[test]
fn a_tool_dropped_on_the_plane_lands_once_and_never_enters_it() {
    let arm7_q0 = SVector::<f64, 7>::from_column_slice(&[0.0, 0.6, 0.0, -1.3, 0.0, 1.0, 0.0]);
    let ur5_q0 = SVector::<f64, 6>::from_column_slice(&[0.0, -1.3, 1.6, -1.87, -1.57, 0.0]);
    let panda_q0 = SVector::<f64, 7>::from_column_slice(&[0.0, -0.1, 0.0, -2.0, 0.0, 1.9, 0.785]);
    for (name, deepest) in [
        ("arm7, heavy tool", drop_on_the_plane(arm7_heavy_tool(), arm7_q0)),
        ("ur5", drop_on_the_plane(ur5_light(), ur5_q0)),
        ("panda flange", drop_on_the_plane(panda_flange(), panda_q0)),
    ] {
        println!("{name}: deepest penetration {deepest:.3e} m");
        assert!(deepest <= 1e-10, "{name}: {deepest:.3e} m inside the plane");
    }
}

#[test]
fn a_plane_the_plant_cannot_simulate_is_an_error() {
    let q = SVector::<f64, 7>::from_column_slice(&[0.0, 0.6, 0.0, -1.3, 0.0, 1.0, 0.0]);
    let s = PlantState::at_rest(q);
    let tau = SVector::zeros();
    let plant = |plane: RigidPlane| {
        Plant::<arm7::Base, 7, { arm7::BASE_PARAMETER_COUNT }>::new(arm7::Base::description(), plane)
    };
    let long_normal = RigidPlane {
        normal: Vector3::new(0.0, 0.0, 2.0),
        ..RigidPlane::table(0.0)
    };
    let err = plant(long_normal).step(&s, &tau, 1e-3).expect_err("refused");
    assert_eq!(err.to_string(), "the rigid plane's normal must be a unit vector");
    let nan_gain = RigidPlane {
        kd: f64::NAN,
        ..RigidPlane::table(0.0)
    };
    let err = plant(nan_gain).acceleration(&s, &tau).expect_err("refused");
    assert_eq!(
        err.to_string(),
        "the rigid plane's Baumgarte gains must be finite and ≥ 0"
    );
    // Stretched straight up, the flange cannot move vertically: nothing can press it on a
    // table at its height.
    let up = PlantState::at_rest(SVector::zeros());
    let top = Arm7::forward_kinematics(&JointTrig::new(&up.q)).translation.z;
    let err = plant(RigidPlane::table(top))
        .step(&up, &tau, 1e-3)
        .expect_err("singular");
    assert_eq!(err, PlantError::SingularContact);
    assert_eq!(
        err.to_string(),
        "the contact point cannot move along the rigid plane's normal (a singular posture)"
    );
}
