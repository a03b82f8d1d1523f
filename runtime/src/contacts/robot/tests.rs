//! The solves over a robot that implements only the rows (the trait's provided one-call
//! methods): a point mass held at one point by two contacts, whose rows are the same three
//! twice. The exact solves refuse them naming the first repeated row; the proximal solve splits
//! the force evenly (the smallest forces), through the generated-style call and, where its
//! four steps do not meet the accuracy, through the iterations at run time.

use super::*;
use nalgebra::{Matrix3, Vector3};

/// A point mass of 2 kg, free in space, gravity-free; `τ` a force on it.
struct TwiceHeldPoint;

const MASS: f64 = 2.0;

impl ContactDynamics<3, 6> for TwiceHeldPoint {
    type Trig = ();
    const CONTACT_FRAMES: &'static [&'static str] = &["point", "point"];
    const CONTACT_KINDS: &'static [ContactKind] = &[ContactKind::Point, ContactKind::Point];
    const CONTACT_REFERENCES: &'static [ReferenceFrame] = &[
        ReferenceFrame::LocalWorldAligned,
        ReferenceFrame::LocalWorldAligned,
    ];
    const CONTACT_TO: &'static [Option<&'static str>] = &[None, None];

    fn contact_jacobian(_: &()) -> SMatrix<f64, 6, 3> {
        let mut j = SMatrix::<f64, 6, 3>::zeros();
        j.fixed_view_mut::<3, 3>(0, 0).copy_from(&Matrix3::identity());
        j.fixed_view_mut::<3, 3>(3, 0).copy_from(&Matrix3::identity());
        j
    }
    fn contact_drift(_: &(), _: &SVector<f64, 3>) -> SVector<f64, 6> {
        SVector::zeros()
    }
    fn contact_response(t: &()) -> SMatrix<f64, 3, 6> {
        Self::contact_jacobian(t).transpose() / MASS
    }
    fn free_acceleration(_: &(), _: &SVector<f64, 3>, tau: &SVector<f64, 3>) -> SVector<f64, 3> {
        tau / MASS
    }
    fn torque_response(_: &()) -> SMatrix<f64, 3, 3> {
        Matrix3::identity() / MASS
    }
    fn contact_forward_dynamics_derivatives(
        _: &(),
        _: &SVector<f64, 3>,
        _: &SVector<f64, 3>,
        _: &SVector<f64, 6>,
    ) -> (SMatrix<f64, 3, 3>, SMatrix<f64, 3, 3>) {
        (SMatrix::zeros(), SMatrix::zeros())
    }
    fn contact_acceleration_derivatives(
        _: &(),
        _: &SVector<f64, 3>,
        _: &SVector<f64, 3>,
    ) -> (SMatrix<f64, 6, 3>, SMatrix<f64, 6, 3>) {
        (SMatrix::zeros(), SMatrix::zeros())
    }
    fn contact_local_jacobian(_: &(), _: usize) -> SMatrix<f64, 6, 3> {
        let mut j = SMatrix::<f64, 6, 3>::zeros();
        j.fixed_view_mut::<3, 3>(0, 0).copy_from(&Matrix3::identity());
        j
    }
    fn contact_pose(_: &(), _: usize) -> Pose {
        Pose::identity()
    }
    fn contact_to_pose(_: &(), _: usize) -> Pose {
        Pose::identity()
    }
}

const TAU: [f64; 3] = [3.0, -4.0, 1.5];

#[test]
fn repeated_rows_are_refused_by_every_exact_solve_naming_the_first_repeat() {
    let (v, tau) = (Vector3::new(0.5, 0.0, -1.0), Vector3::from(TAU));
    let exact = ProximalSettings::default();
    let redundant = Some(ContactError::Redundant { row: 3 });
    let solved = constrained_forward_dynamics::<TwiceHeldPoint, 3, 6>(&(), &v, &tau, None, &exact, None);
    assert_eq!(solved.err(), redundant);
    assert_eq!(
        impulse_dynamics::<TwiceHeldPoint, 3, 6>(&(), &v, 0.5, 0.0).err(),
        redundant
    );
    assert_eq!(
        operational_space_inertia::<TwiceHeldPoint, 3, 6>(&(), 0.0).err(),
        redundant
    );
}

#[test]
fn the_proximal_solve_splits_the_force_between_the_repeated_rows() {
    let (v, tau) = (Vector3::new(0.5, 0.0, -1.0), Vector3::from(TAU));
    // A small μ converges within the call's four steps; a large one (each step closes a third
    // of the gap) iterates on at run time.
    for (mu, iterations_past_the_call) in [(1e-4, false), (0.5, true)] {
        let settings = ProximalSettings {
            mu,
            max_iterations: 200,
            accuracy: 1e-12,
        };
        let solved =
            constrained_forward_dynamics::<TwiceHeldPoint, 3, 6>(&(), &v, &tau, None, &settings, None)
                .expect("a regularised solve of repeated rows");
        assert_eq!(
            solved.iterations > ProximalSettings::UNROLLED_ITERATIONS,
            iterations_past_the_call,
            "μ = {mu}: {} iterations",
            solved.iterations
        );
        assert!(solved.iterations >= ProximalSettings::UNROLLED_ITERATIONS);
        // Held still, the two points share the force that cancels τ.
        for k in 0..6 {
            assert!(
                (solved.forces[k] + TAU[k % 3] / 2.0).abs() < 1e-9,
                "μ = {mu}: {}",
                solved.forces
            );
        }
        assert!(
            solved.acceleration.amax() < 1e-9,
            "μ = {mu}: {}",
            solved.acceleration
        );
        assert!(solved.residual <= 1e-12, "μ = {mu}: {}", solved.residual);
    }
}

#[test]
fn damping_makes_the_inertia_of_repeated_rows_finite() {
    let damping = 0.1;
    let inertia = operational_space_inertia::<TwiceHeldPoint, 3, 6>(&(), damping).expect("damped");
    let k = TwiceHeldPoint::contact_jacobian(&()) * TwiceHeldPoint::contact_response(&());
    let damped = k + SMatrix::<f64, 6, 6>::identity() * damping;
    assert!((inertia * damped - SMatrix::<f64, 6, 6>::identity()).amax() < 1e-12);
}
