//! The impact when the contact point strikes a rigid plane, against the velocity-jump
//! equations `D (q̇⁺ − q̇⁻) = Jᵀ n Λ`, `nᵀ J q̇⁺ = 0`, with only the kinematics and the plant's
//! own `D`: the generalised momentum changes along the row alone, the normal velocity is zero
//! after, the impulse pushes, the positions do not jump, and the kinetic energy falls by exactly
//! what a plastic impact loses, `½ Λ |ġ⁻|`. A point leaving the plane, one above it, and a
//! compliant plane give no jump. On arm7 with a heavy tool, the UR5 and the Panda's flange.

use dyngen_control::sim::{Gaussian, Payload, PlaneContact, Plant, PlantState, RigidPlane};
use dyngen_generated::{arm7, panda, ur5, Arm7, Panda, Ur5};
use dyngen_runtime::nalgebra::{SMatrix, SVector, Vector3};
use dyngen_runtime::{FrameKinematics, JointTrig, Kinematics, Parameterization, ReferenceFrame};

fn strikes<Z: Parameterization<N, M>, const N: usize, const M: usize>(
    mut plant: Plant<Z, N, M>,
    point: fn(&JointTrig<N>) -> Vector3<f64>,
    linear: fn(&JointTrig<N>) -> SMatrix<f64, 3, N>,
) {
    let mut rng = Gaussian::new(21);
    for k in 0..20 {
        let q = rng.vector::<N>(1.0);
        let qd = rng.vector::<N>(1.0);
        let t = JointTrig::new(&q);
        let normal = rng.vector::<3>(1.0).normalize();
        let row = normal.transpose() * linear(&t);
        // Into the plane: flip the normal if the point moves out along it.
        let normal = if (row * qd)[0] > 0.0 { -normal } else { normal };
        let row = normal.transpose() * linear(&t);
        // On the plane, or just inside it (a crossing found to within rounding).
        let depth = if k % 2 == 0 { 0.0 } else { 1e-12 };
        plant.contact = RigidPlane {
            point: point(&t) + normal * depth,
            normal,
            ..RigidPlane::table(0.0)
        }
        .into();
        let before = PlantState { q, qd };
        let (after, impulse) = plant.impact(&before).expect("impact");
        let rate = (row * qd)[0];
        assert!(rate < 0.0 && impulse > 0.0, "ġ⁻ = {rate}, Λ = {impulse}");
        assert_eq!(after.q, before.q, "positions do not jump");
        let d = plant.mass_matrix(&t);
        let momentum = d * (after.qd - before.qd);
        let along_row = row.transpose() * impulse;
        assert!(
            (momentum - along_row).amax() <= 1e-10 * along_row.amax(),
            "D Δq̇ = {momentum}, Jᵀ n Λ = {along_row}"
        );
        let normal_after = (row * after.qd)[0];
        assert!(normal_after.abs() <= 1e-12 * rate.abs(), "ġ⁺ = {normal_after}");
        let energy = |v: &SVector<f64, N>| 0.5 * v.dot(&(d * v));
        let lost = energy(&before.qd) - energy(&after.qd);
        let plastic = 0.5 * impulse * rate.abs();
        assert!(
            (lost - plastic).abs() <= 1e-10 * energy(&before.qd),
            "lost {lost}, plastic {plastic}"
        );

        // Leaving the plane, or above it: nothing happens.
        let leaving = PlantState { q, qd: -qd };
        assert_eq!(plant.impact(&leaving).expect("no impact"), (leaving, 0.0));
        plant.contact = RigidPlane {
            point: point(&t) - normal * 1e-6,
            normal,
            ..RigidPlane::table(0.0)
        }
        .into();
        assert_eq!(plant.impact(&before).expect("no impact"), (before, 0.0));
        plant.contact = PlaneContact {
            point: point(&t) + normal * 1e-3,
            normal,
            stiffness: 1e4,
        }
        .into();
        assert_eq!(plant.impact(&before).expect("no impact"), (before, 0.0));
    }
}

#[test]
fn an_impact_changes_the_momentum_along_the_row_only_and_stops_the_normal_velocity() {
    let heavy_tool = Payload {
        mass: 20.0,
        com: Vector3::new(0.03, 0.0, 0.15),
        size: Vector3::new(0.2, 0.2, 0.3),
    };
    strikes(
        Plant::<arm7::Base, 7, { arm7::BASE_PARAMETER_COUNT }>::with_payload(
            &heavy_tool,
            RigidPlane::table(0.0),
        ),
        |t| Arm7::forward_kinematics(t).translation,
        |t| Arm7::jacobian(t).fixed_rows::<3>(0).into_owned(),
    );
    strikes(
        Plant::<ur5::Base, 6, { ur5::BASE_PARAMETER_COUNT }>::new(
            ur5::Base::description(),
            RigidPlane::table(0.0),
        ),
        |t| Ur5::forward_kinematics(t).translation,
        |t| Ur5::jacobian(t).fixed_rows::<3>(0).into_owned(),
    );
    let flange = panda::Frame::PandaLink8;
    strikes(
        Plant::<panda::Standard, 7, 70>::new(panda::Standard::description(), RigidPlane::table(0.0))
            .with_contact_frame(flange),
        |t| Panda::frame_pose(panda::Frame::PandaLink8, t).translation,
        |t| {
            Panda::frame_jacobian(panda::Frame::PandaLink8, ReferenceFrame::LocalWorldAligned, t)
                .fixed_rows::<3>(0)
                .into_owned()
        },
    );
}
