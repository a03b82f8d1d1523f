//! The task frame of a tilted plane and the per-kind adaptation gains.

use dyngen_control::controller::{ContactTask, GammaByKind};
use dyngen_control::sim::PlaneContact;
use dyngen_generated::{arm7, ur5, Ur5};
use dyngen_runtime::nalgebra::Vector3;
use dyngen_runtime::{Parameterization, RobotDynamics};

#[test]
fn tilted_plane_model_force_equals_measured_force_component() {
    let k = 2.5e4;
    let normal = Vector3::new(0.3, -0.2, 0.9).normalize();
    let point = Vector3::new(0.4, 0.1, 0.2);
    let plane = PlaneContact {
        point,
        normal,
        stiffness: k,
    };
    let task = ContactTask::plane(point, normal, k).expect("plane");
    let split = task.validate().expect("valid task");
    // R is a rotation taking the normal to the task z axis.
    assert!((task.rotation * normal - Vector3::z()).norm() < 1e-12);
    // K⁺K projects on the normal, K⁻ on the plane.
    assert!(((split.k_plus * split.k) * Vector3::z() - Vector3::z()).norm() < 1e-12);
    assert!((split.k_minus * Vector3::z()).norm() < 1e-12);
    for (dx, dy, depth) in [(0.01, 0.02, 0.001), (-0.03, 0.0, 0.0005), (0.0, 0.05, 0.002)] {
        // A point `depth` below the surface, moved in the plane.
        let tangent = normal.cross(&Vector3::x()).normalize();
        let x = point + tangent * dx + normal.cross(&tangent) * dy - normal * depth;
        let measured = (task.force_selection * (task.rotation * plane.force_on_environment(&x)))[0];
        let model = (split.k * (task.rotation * x - task.contact_point))[0];
        assert!(
            (measured - k * depth).abs() < 1e-9 * k,
            "{measured} vs {}",
            k * depth
        );
        assert!((model - measured).abs() < 1e-9 * k, "{model} vs {measured}");
    }
}

#[test]
fn gamma_by_parameter_kind() {
    let g = GammaByKind::default().carried_to::<arm7::Standard, 7, 70>();
    for body in 0..7 {
        let b = &g.as_slice()[10 * body..10 * body + 10];
        assert_eq!(b, &[100.0, 10.0, 10.0, 10.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0]);
    }
}

/// Base parameters adapt as fast as the standard parameters they combine: `Γ_b` is the diagonal
/// of `Φ Γ Φᵀ`. UR5's folding coefficients are exact geometry (0.39225 m is the forearm's
/// length), so the expected gains are arithmetic on the names.
#[test]
fn base_parameter_gains_carry_the_gains_of_what_they_combine() {
    const B: usize = ur5::BASE_PARAMETER_COUNT;
    let kinds = GammaByKind::default();
    let gamma = kinds.carried_to::<ur5::Base, 6, B>();
    let names = <ur5::Base as Parameterization<6, B>>::NAMES;
    let at = |name: &str| {
        let k = names
            .iter()
            .position(|n| *n == name)
            .unwrap_or_else(|| panic!("no base parameter {name}"));
        gamma[k]
    };
    let forearm =
        "mcz[forearm_link] + 0.39225·m[wrist_1_link] + 0.39225·m[wrist_2_link] + 0.39225·m[wrist_3_link]";
    assert!((at(forearm) - (10.0 + 3.0 * 0.39225f64.powi(2) * 100.0)).abs() < 1e-9);
    assert!((at("Ixx[wrist_2_link] − Iyy[wrist_2_link] + Izz[wrist_3_link]") - 3.0).abs() < 1e-12);
    // The standard parameters keep the per-kind gains.
    let standard = kinds.carried_to::<ur5::Standard, 6, 60>();
    for (gain, kind) in standard.iter().zip(Ur5::PARAMETER_KINDS) {
        assert_eq!(*gain, kinds.of(kind));
    }
}
