//! The compiled Solo-12's one-call rows (`contact_delassus`, `contact_matrices`,
//! `contact_system`) against the rows one by one, and the runtime's solves over them against the
//! same solves over a robot that generates only the rows (`RowsOnly`, which takes
//! `ContactDynamics`' provided methods: `K` formed as `J (M⁻¹ Jᵀ)` at run time): equal to
//! 1e-12, exact and proximal, stabilised or not, at random states including feet far from
//! their anchors and near-singular legs.

use dyngen_testkit as common;

use common::assert_close;
use dyngen_generated::solo12::{self, Solo12, Velocity, NV};
use dyngen_runtime::nalgebra::{DMatrix, Matrix3, SMatrix, SVector, Vector3};
use dyngen_runtime::{
    constrained_forward_dynamics, impulse_dynamics, operational_space_inertia, ContactDynamics, ContactKind,
    FloatingTrig, Pose, ProximalSettings, ReferenceFrame, SplitMix64, Stabilisation,
};

const NC: usize = 12;
const TOL: f64 = 1e-12;

fn dm<const R: usize, const C: usize>(m: &SMatrix<f64, R, C>) -> DMatrix<f64> {
    DMatrix::from_column_slice(R, C, m.as_slice())
}

/// Solo-12's generated rows, and nothing else: the trait's provided methods assemble `K`, the
/// matrices and the system from them.
struct RowsOnly;

impl ContactDynamics<NV, NC> for RowsOnly {
    type Trig = FloatingTrig<12>;
    const CONTACT_FRAMES: &'static [&'static str] = Solo12::CONTACT_FRAMES;
    const CONTACT_KINDS: &'static [ContactKind] = Solo12::CONTACT_KINDS;
    const CONTACT_REFERENCES: &'static [ReferenceFrame] = Solo12::CONTACT_REFERENCES;
    const CONTACT_TO: &'static [Option<&'static str>] = Solo12::CONTACT_TO;

    fn contact_jacobian(t: &Self::Trig) -> SMatrix<f64, NC, NV> {
        Solo12::contact_jacobian(t)
    }
    fn contact_drift(t: &Self::Trig, v: &SVector<f64, NV>) -> SVector<f64, NC> {
        Solo12::contact_drift(t, v)
    }
    fn contact_response(t: &Self::Trig) -> SMatrix<f64, NV, NC> {
        Solo12::contact_response(t)
    }
    fn free_acceleration(t: &Self::Trig, v: &SVector<f64, NV>, tau: &SVector<f64, NV>) -> SVector<f64, NV> {
        Solo12::free_acceleration(t, v, tau)
    }
    fn torque_response(t: &Self::Trig) -> SMatrix<f64, NV, NV> {
        Solo12::torque_response(t)
    }
    fn contact_forward_dynamics_derivatives(
        t: &Self::Trig,
        v: &SVector<f64, NV>,
        a: &SVector<f64, NV>,
        lambda: &SVector<f64, NC>,
    ) -> (SMatrix<f64, NV, NV>, SMatrix<f64, NV, NV>) {
        Solo12::contact_forward_dynamics_derivatives(t, v, a, lambda)
    }
    fn contact_acceleration_derivatives(
        t: &Self::Trig,
        v: &SVector<f64, NV>,
        a: &SVector<f64, NV>,
    ) -> (SMatrix<f64, NC, NV>, SMatrix<f64, NC, NV>) {
        Solo12::contact_acceleration_derivatives(t, v, a)
    }
    fn contact_local_jacobian(t: &Self::Trig, contact: usize) -> SMatrix<f64, 6, NV> {
        Solo12::contact_local_jacobian(t, contact)
    }
    fn contact_pose(t: &Self::Trig, contact: usize) -> Pose {
        Solo12::contact_pose(t, contact)
    }
    fn contact_to_pose(t: &Self::Trig, contact: usize) -> Pose {
        Solo12::contact_to_pose(t, contact)
    }
}

/// A configuration: the base anywhere, the joints in `±reach` (near 0 the legs are stretched,
/// close to singular).
fn configuration(rng: &mut SplitMix64, reach: f64) -> FloatingTrig<12> {
    let mut q: Vec<f64> = (0..19).map(|_| rng.uniform((-reach, reach))).collect();
    for x in &mut q[..3] {
        *x = rng.uniform((-3.0, 3.0));
    }
    let norm = q[3..7].iter().map(|x| x * x).sum::<f64>().sqrt();
    q[3..7].iter_mut().for_each(|x| *x /= norm);
    solo12::trig(&solo12::Configuration::from_column_slice(&q)).unwrap()
}

#[test]
fn the_one_call_rows_are_the_rows() {
    let mut rng = SplitMix64::new(91);
    for k in 0..40 {
        let what = |q: &str| format!("state {k}: {q}");
        let t = configuration(&mut rng, if k % 4 == 0 { 0.05 } else { 3.0 });
        let [v, tau] = [0; 2].map(|_| Velocity::from_fn(|_, _| rng.uniform((-4.0, 4.0))));
        let system = Solo12::contact_system(&t, &v, &tau);
        let matrices = Solo12::contact_matrices(&t);
        assert_eq!(system.matrices, matrices, "{}", what("matrices"));
        assert_eq!(matrices.delassus, Solo12::contact_delassus(&t), "{}", what("K"));
        assert_eq!(
            matrices.delassus,
            matrices.delassus.transpose(),
            "{}",
            what("K symmetric")
        );
        let rows = RowsOnly::contact_system(&t, &v, &tau);
        let pairs = [
            ("J", dm(&matrices.jacobian), dm(&rows.matrices.jacobian)),
            ("M⁻¹ Jᵀ", dm(&matrices.response), dm(&rows.matrices.response)),
            ("K", dm(&matrices.delassus), dm(&rows.matrices.delassus)),
            ("drift", dm(&system.drift), dm(&rows.drift)),
            ("free", dm(&system.free_acceleration), dm(&rows.free_acceleration)),
        ];
        for (name, ours, theirs) in pairs {
            assert_close(&what(name), &ours, &theirs, TOL);
        }
    }
}

#[test]
fn the_solves_are_those_of_the_rows() {
    let mut rng = SplitMix64::new(92);
    let exact = ProximalSettings::default();
    let proximal = ProximalSettings {
        mu: 1e-4,
        max_iterations: 50,
        accuracy: 1e-10,
    };
    for k in 0..40 {
        let what = |q: &str| format!("state {k}: {q}");
        let t = configuration(&mut rng, if k % 4 == 0 { 0.05 } else { 3.0 });
        let [v, tau] = [0; 2].map(|_| Velocity::from_fn(|_, _| rng.uniform((-4.0, 4.0))));
        // Each foot held up to 10 cm from where it is, turned a little.
        let anchors: Vec<Pose> = (0..4)
            .map(|c| {
                let at = Solo12::contact_pose(&t, c);
                Pose {
                    rotation: at.rotation * Matrix3::new_rotation(rng.uniform((-0.3, 0.3))),
                    translation: at.translation + Vector3::from_fn(|_, _| rng.uniform((-0.1, 0.1))),
                }
            })
            .collect();
        let stabilisation = Stabilisation {
            anchors: &anchors,
            kp: 50.0,
            kd: 14.0,
        };
        for (name, held, settings) in [
            ("exact", None, &exact),
            ("Baumgarte", Some(stabilisation), &exact),
            ("proximal", Some(stabilisation), &proximal),
        ] {
            let ours =
                constrained_forward_dynamics::<Solo12, NV, NC>(&t, &v, &tau, held, settings, None).unwrap();
            let theirs =
                constrained_forward_dynamics::<RowsOnly, NV, NC>(&t, &v, &tau, held, settings, None).unwrap();
            assert_close(
                &what(&format!("{name} a")),
                &dm(&ours.acceleration),
                &dm(&theirs.acceleration),
                TOL,
            );
            assert_close(
                &what(&format!("{name} λ")),
                &dm(&ours.forces),
                &dm(&theirs.forces),
                TOL,
            );
            assert_eq!(ours.iterations, theirs.iterations, "{}", what(name));
        }
        let ours = impulse_dynamics::<Solo12, NV, NC>(&t, &v, 0.3, 0.0).unwrap();
        let theirs = impulse_dynamics::<RowsOnly, NV, NC>(&t, &v, 0.3, 0.0).unwrap();
        assert_close(&what("ν⁺"), &dm(&ours.0), &dm(&theirs.0), TOL);
        assert_close(&what("impulses"), &dm(&ours.1), &dm(&theirs.1), TOL);
        for damping in [0.0, 1e-6] {
            let ours = operational_space_inertia::<Solo12, NV, NC>(&t, damping).unwrap();
            let theirs = operational_space_inertia::<RowsOnly, NV, NC>(&t, damping).unwrap();
            assert_close(&what("Λ"), &dm(&ours), &dm(&theirs), TOL);
        }
    }
}
