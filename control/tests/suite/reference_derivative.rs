//! `q̈_r` (computed analytically from q, q̇ and F̄) is the time derivative of `q̇_r` along the
//! motion: compared with central differences of `q̇_r` at `q ± h q̇`, `t ± h`, with the measured
//! force from the contact model at each point. In contact, in free space, and inside the
//! damped region of the singularity guard (where the derivative of the damping counts); for
//! every task dimension: 3 (position), 5 (position and tool axis), 6 (position and
//! orientation), with the desired orientation turning (`ω_d ≠ 0`, `ω̇_d ≠ 0`) and away from
//! the actual one.

use dyngen_control::controller::{HybridController, Measurement};
use dyngen_control::sim::{start_posture, Demo, DemoOptions, Gaussian, PlantState, RunKind};
use dyngen_generated::arm7;
use dyngen_runtime::nalgebra::{SVector, Vector3};
use dyngen_runtime::Kinematics;

type Ctrl<const T: usize> = HybridController<arm7::Standard, 7, 70, T>;
type Arm7Demo<const T: usize> = Demo<arm7::Standard, 7, 70, T>;

/// The compliant table's force at `q` (a function of the position alone).
fn compliant_force<const T: usize>(d: &Arm7Demo<T>, q: SVector<f64, 7>) -> Vector3<f64> {
    d.plant
        .contact_force(&PlantState::at_rest(q), &SVector::zeros())
        .expect("compliant")
}

/// Largest relative mismatch between `q̈_r` and the differenced `q̇_r`, and the damping seen.
fn mismatch<const T: usize>(
    d: &Arm7Demo<T>,
    c: &Ctrl<T>,
    q: SVector<f64, 7>,
    qd: SVector<f64, 7>,
    t: f64,
) -> (f64, f64, f64) {
    let eval = |q: SVector<f64, 7>, t: f64| {
        let force = compliant_force(d, q);
        let m = Measurement { q, qd, force };
        c.evaluate(&m, &d.scenario.desired(t), &d.theta_hat0)
            .expect("evaluate")
    };
    let h = 1e-6;
    let out = eval(q, t);
    let fd = (eval(q + qd * h, t + h).reference.qd_r - eval(q - qd * h, t - h).reference.qd_r) / (2.0 * h);
    let err = (fd - out.reference.qdd_r).amax() / out.reference.qdd_r.amax().max(1e-3);
    (err, out.damping, out.reference.orientation_error.norm())
}

#[test]
fn reference_acceleration_is_the_derivative_of_the_reference_velocity() {
    in_contact_and_free_space::<3>();
}

#[test]
fn also_with_tool_axis_rows() {
    in_contact_and_free_space::<5>();
    damped_region::<5>();
}

#[test]
fn also_with_orientation_rows() {
    in_contact_and_free_space::<6>();
    damped_region::<6>();
}

fn in_contact_and_free_space<const T: usize>() {
    let q0 = start_posture::<7>("arm7").expect("arm7 start posture");
    let mut rng = Gaussian::new(3);
    // In contact (start 3 mm into the table) and in free space (1 cm above).
    for (height, in_contact) in [(-0.003, true), (0.01, false)] {
        let d = Arm7Demo::<T>::new(
            DemoOptions {
                start_height: height,
                ..DemoOptions::default()
            },
            q0,
        )
        .expect("valid demo");
        let c = d.controller(RunKind::Adaptive).expect("controller");
        let mut worst_orientation = 0.0f64;
        for k in 0..20 {
            let q = q0 + rng.vector::<7>(1e-4);
            let qd = rng.vector::<7>(0.3);
            // Half of the times inside the turn of the desired orientation (ω_d, ω̇_d ≠ 0).
            let t = if k % 2 == 0 {
                0.09 * k as f64 + 0.01
            } else {
                0.37 * k as f64 + 0.01
            };
            let penetration = compliant_force(&d, q).norm();
            assert_eq!(penetration > 0.0, in_contact);
            let (err, damping, e_o) = mismatch(&d, &c, q, qd, t);
            worst_orientation = worst_orientation.max(e_o);
            assert_eq!(damping, 0.0);
            assert!(
                err < 1e-6,
                "T = {T}, contact {in_contact}, t = {t}: relative mismatch {err:.2e}"
            );
        }
        // With orientation rows, the states are away from the desired orientation (the error
        // and its rate enter q̈_r), not on it.
        assert!(
            T == 3 || worst_orientation > 1e-2,
            "orientation error {worst_orientation}"
        );
    }
}

#[test]
fn also_inside_the_damped_region_near_a_singularity() {
    damped_region::<3>();
}

fn damped_region<const T: usize>() {
    let q0 = start_posture::<7>("arm7").expect("arm7 start posture");
    let d = Arm7Demo::<T>::new(DemoOptions::default(), q0).expect("valid demo");
    let c = d.controller(RunKind::Adaptive).expect("controller");
    let mut rng = Gaussian::new(5);
    // Near the stretched-up posture q = 0, where the position Jacobian has rank 1.
    let mut damped = 0;
    for k in 0..20 {
        let q = rng.vector::<7>(0.02 + 0.002 * k as f64);
        let qd = rng.vector::<7>(0.3);
        let (err, damping, _) = mismatch(&d, &c, q, qd, 0.5);
        if damping > 0.0 {
            damped += 1;
        }
        assert!(err < 1e-5, "T = {T}, q = {q:?}: relative mismatch {err:.2e}");
    }
    assert!(
        damped >= 10,
        "the guard should be active near q4 = 0 ({damped} of 20)"
    );
}

#[test]
fn torques_stay_finite_and_bounded_at_an_exact_singularity() {
    let q0 = start_posture::<7>("arm7").expect("arm7 start posture");
    let d = Arm7Demo::<3>::new(DemoOptions::default(), q0).expect("valid demo");
    let mut c = d.controller(RunKind::Adaptive).expect("controller");
    // Stretched straight up (rank 1), with and without turns about the vertical axes.
    for q in [
        SVector::<f64, 7>::zeros(),
        SVector::<f64, 7>::from_column_slice(&[0.3, 0.0, -0.2, 0.0, 0.5, 0.0, 1.0]),
    ] {
        let m = Measurement {
            q,
            qd: SVector::from_element(0.1),
            force: compliant_force(&d, q),
        };
        let out = c
            .tick(&m, &d.scenario.desired(3.0), 1e-3)
            .expect("a guarded tick");
        assert!(out.damping > 0.0);
        assert!(out.tau.iter().all(|t| t.is_finite()));
        assert!(out
            .tau
            .iter()
            .zip(arm7::Arm7::JOINT_LIMITS.iter())
            .all(|(t, l)| t.abs() <= l.effort));
        assert!(out.reference.qd_r.iter().all(|x| x.is_finite()));
    }
}
