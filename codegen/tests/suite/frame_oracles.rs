//! Named frames and external wrenches on random kinematic trees, against oracles that use no
//! frame algorithm: each convention's `J` from differenced poses of a point or frame carried by
//! the body, each `J̇` from the differenced `J`, the classical acceleration from the second
//! difference of the frame origin along a trajectory, and a wrench against the mass it stands
//! for (a force `m g` at a frame origin is a point mass there: it changes `g(q)` by `−Jᵀ [m g; 0]`).

use dyngen_codegen::dynamics::NumericDynamics;
use dyngen_codegen::model::{Body, Frame, Inertia, Model, Pose};
use dyngen_runtime::ReferenceFrame;
use dyngen_testkit::oracles::{
    along, directional_derivative, extrapolate, rotation_log, Pose as PoseOf, STEP,
};
use dyngen_testkit::random_model::{arb_model_and_state, arb_pose, deterministic_runner};
use nalgebra::{DMatrix, Matrix3, Vector3};
use proptest::prelude::*;
use proptest::sample::Index;

/// Differenced values against the subject, relative to the larger of 1 and the expected size.
const DIFFERENCED: f64 = 1e-7;
const IDENTITY: f64 = 1e-10;

fn close(what: &str, actual: &DMatrix<f64>, expected: &DMatrix<f64>, tol: f64) -> Result<(), TestCaseError> {
    let err = (actual - expected).amax() / expected.amax().max(1.0);
    prop_assert!(
        err <= tol,
        "{what}: error {err:.2e}\nactual {actual:.6}\nexpected {expected:.6}"
    );
    Ok(())
}

fn column(x: &[f64]) -> DMatrix<f64> {
    DMatrix::from_column_slice(x.len(), 1, x)
}

fn unit(n: usize, k: usize) -> Vec<f64> {
    let mut e = vec![0.0; n];
    e[k] = 1.0;
    e
}

/// `[v; ω]` of a moving frame `(R, p)` from its poses at `x ± t u`, both halves expressed by
/// `express` (base axes, or the frame's own at `x`), `v` the velocity of the body point at
/// `point` (a point fixed in the frame, given by its position at `x`).
fn differenced_velocity(
    pose: &dyn Fn(&[f64]) -> PoseOf,
    q: &[f64],
    dir: &[f64],
    point: Vector3<f64>,
    express: Matrix3<f64>,
) -> DMatrix<f64> {
    let (r0, p0) = pose(q);
    let local_point = r0.transpose() * (point - p0);
    along(q, dir, |plus, minus, t| {
        let ((rp, pp), (rm, pm)) = (pose(plus), pose(minus));
        let v = (rp * local_point + pp - (rm * local_point + pm)) / (2.0 * t);
        let w = rotation_log(&(rp * rm.transpose())) / (2.0 * t);
        let (v, w) = (express.transpose() * v, express.transpose() * w);
        column(&[v.x, v.y, v.z, w.x, w.y, w.z])
    })
}

fn with_frames(model: Model, frames: &[(Index, Pose)]) -> Model {
    let n = model.joints().len();
    let frames = frames
        .iter()
        .enumerate()
        .map(|(k, (body, pose))| Frame {
            name: format!("frame{k}"),
            parent: Some(body.index(n)),
            placement: *pose,
        })
        .collect();
    model.with_frames(frames).expect("valid frames")
}

fn check(model: &Model, q: &[f64], qd: &[f64], qdd: &[f64]) -> Result<(), TestCaseError> {
    let dynamics = NumericDynamics::new(model);
    let n = model.dof();
    for frame in model.frames() {
        let name = frame.name.as_str();
        let at = |what: &str| format!("{} frame {name}: {what}", model.name());
        let values = |x: &[f64], xd: &[f64]| dynamics.frame_motion(name, x, xd).expect("the frame");
        let pose = |x: &[f64]| values(x, &vec![0.0; n]).pose();
        let here = values(q, qd);
        let (r, p) = here.pose();
        for reference in ReferenceFrame::ALL {
            let j = here.jacobian(reference);
            // 1. Each column of J: the differenced motion of a point of the body.
            let (point, express) = match reference {
                ReferenceFrame::LocalWorldAligned => (p, Matrix3::identity()),
                ReferenceFrame::World => (Vector3::zeros(), Matrix3::identity()),
                ReferenceFrame::Local => (p, r),
            };
            let mut j_fd = DMatrix::zeros(6, n);
            for k in 0..n {
                j_fd.set_column(
                    k,
                    &differenced_velocity(&pose, q, &unit(n, k), point, express).column(0),
                );
            }
            close(&at(&format!("J {}", reference.keyword())), &j, &j_fd, DIFFERENCED)?;
            // 2. J̇ is the time derivative of the same J.
            let j_dot = here.jacobian_time_variation(reference);
            let j_dot_fd = directional_derivative(|x| values(x, qd).jacobian(reference), q, qd);
            close(
                &at(&format!("J̇ {}", reference.keyword())),
                &j_dot,
                &j_dot_fd,
                DIFFERENCED,
            )?;
            // 3. The velocity is J q̇.
            let v = DMatrix::from_column_slice(6, 1, here.velocity(reference).as_slice());
            close(&at("velocity = J q̇"), &v, &(&j * column(qd)), IDENTITY)?;
        }
        // 4. The classical acceleration at the origin in base axes: p̈ from the second difference
        // along q(t) = q + q̇ t + q̈ t²/2; ω̇ from the differenced ω(t) = J_ω(q(t)) q̇(t).
        let path = |t: f64| -> (Vec<f64>, Vec<f64>) {
            let x = (0..n).map(|i| q[i] + qd[i] * t + 0.5 * qdd[i] * t * t).collect();
            let xd = (0..n).map(|i| qd[i] + qdd[i] * t).collect();
            (x, xd)
        };
        let p_ddot = extrapolate(
            |t| {
                let (plus, minus) = (pose(&path(t).0).1, pose(&path(-t).0).1);
                column(((plus - 2.0 * p + minus) / (t * t)).as_slice())
            },
            STEP,
        );
        let omega = |t: f64| -> Vector3<f64> {
            let (x, xd) = path(t);
            let v = values(&x, &xd).velocity(ReferenceFrame::LocalWorldAligned);
            Vector3::new(v[3], v[4], v[5])
        };
        let omega_dot = extrapolate(|t| column(((omega(t) - omega(-t)) / (2.0 * t)).as_slice()), STEP);
        let lwa = here.classical_acceleration(ReferenceFrame::LocalWorldAligned, qdd);
        close(&at("p̈"), &column(&lwa.as_slice()[..3]), &p_ddot, DIFFERENCED)?;
        close(&at("ω̇"), &column(&lwa.as_slice()[3..]), &omega_dot, DIFFERENCED)?;
        // The other two: the same motion in the frame's axes, and at the base origin.
        let (a, w) = (
            Vector3::new(lwa[0], lwa[1], lwa[2]),
            Vector3::new(lwa[3], lwa[4], lwa[5]),
        );
        let local = here.classical_acceleration(ReferenceFrame::Local, qdd);
        let expected: Vec<f64> = (r.transpose() * a)
            .iter()
            .chain((r.transpose() * w).iter())
            .copied()
            .collect();
        close(
            &at("classical acceleration, local"),
            &column(local.as_slice()),
            &column(&expected),
            IDENTITY,
        )?;
        // World: the acceleration of the body point at the base origin, ω × v added as
        // Pinocchio does: p̈ + p × ω̇ + ω × (p × ω).
        let world = here.classical_acceleration(ReferenceFrame::World, qdd);
        let omega0 = omega(0.0);
        let lin = a + p.cross(&w) + omega0.cross(&p.cross(&omega0));
        let expected: Vec<f64> = lin.iter().chain(w.iter()).copied().collect();
        close(
            &at("classical acceleration, world"),
            &column(world.as_slice()),
            &column(&expected),
            IDENTITY,
        )?;

        // 5. A force m g at the frame origin is a point mass m there.
        let mass = 0.7;
        let gravity = model.gravity();
        let mut bodies: Vec<Body> = model.bodies().to_vec();
        let at_origin = Inertia {
            mass,
            com: frame.placement.translation,
            inertia_com: Matrix3::zeros(),
        };
        let carrier = &mut bodies[frame.parent.unwrap()];
        carrier.inertia = carrier.inertia.merged(&at_origin);
        let loaded = model.clone().with_bodies(bodies).expect("a heavier body");
        let g_change = NumericDynamics::new(&loaded).gravity_torque(q) - dynamics.gravity_torque(q);
        let weight = gravity * mass;
        let wrench = [weight.x, weight.y, weight.z, 0.0, 0.0, 0.0];
        let from_wrench = -(here.jacobian(ReferenceFrame::LocalWorldAligned).transpose() * column(&wrench));
        close(
            &at("g change = −Jᵀ [m g; 0]"),
            &column(g_change.as_slice()),
            &from_wrench,
            IDENTITY,
        )?;
        // The same wrench in the other two reference frames produces the same torques.
        let local_wrench: Vec<f64> = (r.transpose() * weight)
            .iter()
            .chain([0.0; 3].iter())
            .copied()
            .collect();
        let moment = p.cross(&weight);
        let world_wrench = [weight.x, weight.y, weight.z, moment.x, moment.y, moment.z];
        for (reference, w) in [
            (ReferenceFrame::Local, local_wrench.as_slice()),
            (ReferenceFrame::World, &world_wrench[..]),
        ] {
            let torques = -(here.jacobian(reference).transpose() * column(w));
            close(
                &at(&format!("wrench in {}", reference.keyword())),
                &torques,
                &from_wrench,
                IDENTITY,
            )?;
        }
    }
    Ok(())
}

/// The second formulations the generator may choose instead (the local `J` carried back from
/// the frame, velocity and acceleration by the forward recursion) give the same values.
fn check_other_forms(model: &Model, q: &[f64], qd: &[f64], qdd: &[f64]) -> Result<(), TestCaseError> {
    use dyngen_codegen::internals::dynamics::{
        body_poses, joint_transforms, local_jacobian, FrameMotion, FrameRates,
    };
    let x = joint_transforms(model, q);
    let world = body_poses(model, &x);
    for frame in model.frames() {
        let at = |what: &str| format!("{} frame {}: {what}", model.name(), frame.name);
        let motion = FrameMotion::new(model, &world, qd, frame);
        let rates = FrameRates::new(model, &x, qd, qdd, frame);
        close(
            &at("local J carried back"),
            &local_jacobian(model, &x, frame),
            &motion.jacobian_in(ReferenceFrame::Local),
            IDENTITY,
        )?;
        for r in ReferenceFrame::ALL {
            close(
                &at(&format!("velocity by recursion, {}", r.keyword())),
                &column(&rates.velocity_in(r, &motion.pose)),
                &column(&motion.velocity_in(r, qd)),
                IDENTITY,
            )?;
            close(
                &at(&format!("classical acceleration by recursion, {}", r.keyword())),
                &column(&rates.classical_acceleration_in(r, &motion.pose)),
                &column(&motion.classical_acceleration_in(r, qd, qdd)),
                IDENTITY,
            )?;
        }
    }
    Ok(())
}

#[test]
fn frames_on_random_trees_match_their_oracles() {
    let strategy = arb_model_and_state(7).prop_flat_map(|(model, state)| {
        (
            Just(model),
            Just(state),
            proptest::collection::vec((any::<Index>(), arb_pose()), 1..4),
        )
    });
    deterministic_runner(64)
        .run(&strategy, |(model, state, frames)| {
            let model = with_frames(model, &frames);
            check(&model, &state.q, &state.qd, &state.qdd)?;
            check_other_forms(&model, &state.q, &state.qd, &state.qdd)
        })
        .unwrap();
}
