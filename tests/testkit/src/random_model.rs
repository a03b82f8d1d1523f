//! Random kinematic trees and joint states for property tests.
//!
//! The trees look like real robots often enough to hit the special cases that generated code
//! folds (exact coordinate axes, quarter-turn origins, diagonal inertias, zero offsets) and are
//! general often enough to catch convention errors that those cases hide (skew axes, products
//! of inertia, branches, prismatic joints, gravity not along −z).
//!
//! Public API: [`arb_model`], [`arb_state`], [`arb_model_and_state`] (proptest strategies) and
//! [`random_state`] with the tiny deterministic [`SplitMix64`] for fixed-seed loops.

use dyngen_codegen::model::{
    from_xyz_rpy, Body, Frame, Inertia, Joint, JointKind, Limits, Mimic, Model, Pose,
};
use nalgebra::{Matrix3, Vector3};
use proptest::prelude::*;
use proptest::sample::Index;
use proptest::test_runner::{Config, RngAlgorithm, RngSeed, TestRunner};
use std::f64::consts::{FRAC_PI_2, PI, TAU};

/// Joint positions, velocities and accelerations at which a model is evaluated.
///
/// `qd`, `qdd` are the actual joint velocity and acceleration; `v`, `a` the reference velocity
/// and acceleration of the Slotine–Li quantities `Y(q, q̇, v, a)`.
#[derive(Clone, Debug, PartialEq)]
pub struct JointState {
    pub q: Vec<f64>,
    pub qd: Vec<f64>,
    pub qdd: Vec<f64>,
    pub v: Vec<f64>,
    pub a: Vec<f64>,
}

/// Range of revolute joint positions (rad): a full turn, so every quadrant is visited.
pub const REVOLUTE_RANGE: (f64, f64) = (-PI, PI);
/// Range of prismatic joint positions (m): about a link length, so links stay robot-sized.
pub const PRISMATIC_RANGE: (f64, f64) = (-0.4, 0.4);
/// Range of every velocity component (rad/s or m/s).
pub const VELOCITY_RANGE: (f64, f64) = (-2.0, 2.0);
/// Range of every acceleration component (rad/s² or m/s²).
pub const ACCELERATION_RANGE: (f64, f64) = (-5.0, 5.0);

fn position_range(joint: &Joint) -> (f64, f64) {
    match joint.kind {
        JointKind::Revolute => REVOLUTE_RANGE,
        JointKind::Prismatic => PRISMATIC_RANGE,
    }
}

pub use dyngen_runtime::SplitMix64;

/// `n` draws uniform in `range`.
fn vector(rng: &mut SplitMix64, n: usize, range: (f64, f64)) -> Vec<f64> {
    (0..n).map(|_| rng.uniform(range)).collect()
}

/// A random state of `model`, the same for the same `seed`.
pub fn random_state(model: &Model, seed: u64) -> JointState {
    let mut rng = SplitMix64::new(seed);
    let n = model.dof();
    // One position per coordinate, within its joint's range (mimic joints follow).
    let coordinates = model.coordinate_joints();
    JointState {
        q: coordinates
            .iter()
            .map(|&k| rng.uniform(position_range(&model.joints()[k])))
            .collect(),
        qd: vector(&mut rng, n, VELOCITY_RANGE),
        qdd: vector(&mut rng, n, ACCELERATION_RANGE),
        v: vector(&mut rng, n, VELOCITY_RANGE),
        a: vector(&mut rng, n, ACCELERATION_RANGE),
    }
}

/// Random states of `model`, with the ranges of [`random_state`].
pub fn arb_state(model: &Model) -> impl Strategy<Value = JointState> {
    let n = model.dof();
    let range = |(lo, hi): (f64, f64)| lo..hi;
    let q: Vec<_> = (model.coordinate_joints().into_iter())
        .map(|k| range(position_range(&model.joints()[k])))
        .collect();
    let vector = move |r| proptest::collection::vec(range(r), n);
    (
        q,
        vector(VELOCITY_RANGE),
        vector(ACCELERATION_RANGE),
        vector(VELOCITY_RANGE),
        vector(ACCELERATION_RANGE),
    )
        .prop_map(|(q, qd, qdd, v, a)| JointState { q, qd, qdd, v, a })
}

/// A random tree of 1 to `max_dof` joints together with a random state of it.
pub fn arb_model_and_state(max_dof: usize) -> impl Strategy<Value = (Model, JointState)> {
    arb_model(max_dof).prop_flat_map(|model| {
        let state = arb_state(&model);
        (Just(model), state)
    })
}

/// A random kinematic tree with 1 to `max_dof` moving joints (see the module documentation).
pub fn arb_model(max_dof: usize) -> impl Strategy<Value = Model> {
    assert!(max_dof >= 1, "a model has at least one joint");
    (1..=max_dof)
        .prop_flat_map(|n| {
            (
                proptest::collection::vec(arb_joint(), n),
                proptest::collection::vec(arb_inertia(), n),
                arb_gravity(),
                any::<Index>(),
                arb_pose(),
            )
        })
        .prop_map(|(joints, inertias, gravity, ee_body, ee_placement)| {
            let n = joints.len();
            let joints = joints
                .into_iter()
                .enumerate()
                .map(|(i, spec)| Joint {
                    name: format!("joint{i}"),
                    parent: spec.parent.resolve(i),
                    kind: spec.kind,
                    origin: spec.origin,
                    axis: spec.axis,
                    limits: spec.limits,
                })
                .collect();
            let bodies = inertias
                .into_iter()
                .enumerate()
                .map(|(i, inertia)| Body {
                    name: format!("link{i}"),
                    inertia,
                })
                .collect();
            let end_effector = Frame {
                name: "tool".into(),
                parent: Some(ee_body.index(n)),
                placement: ee_placement,
            };
            Model::new(
                format!("random_tree_{n}dof"),
                joints,
                bodies,
                gravity,
                end_effector,
            )
            .expect("random trees are valid models")
        })
}

/// How a joint picks its parent. Mostly the previous joint (chains, as in arms), sometimes the
/// base or any earlier joint (branches, as in hands, legs and dual arms).
#[derive(Clone, Debug)]
enum ParentChoice {
    Previous,
    Base,
    Any(Index),
}

impl ParentChoice {
    fn resolve(&self, joint: usize) -> Option<usize> {
        match self {
            _ if joint == 0 => None,
            ParentChoice::Previous => Some(joint - 1),
            ParentChoice::Base => None,
            // Index over the base and the `joint` earlier joints.
            ParentChoice::Any(ix) => ix.index(joint + 1).checked_sub(1),
        }
    }
}

#[derive(Clone, Debug)]
struct JointSpec {
    parent: ParentChoice,
    kind: JointKind,
    axis: Vector3<f64>,
    origin: Pose,
    limits: Option<Limits>,
}

fn arb_joint() -> impl Strategy<Value = JointSpec> {
    let parent = prop_oneof![
        4 => Just(ParentChoice::Previous),
        1 => Just(ParentChoice::Base),
        2 => any::<Index>().prop_map(ParentChoice::Any),
    ];
    let kind = prop_oneof![3 => Just(JointKind::Revolute), 1 => Just(JointKind::Prismatic)];
    (parent, kind, arb_axis(), arb_pose(), any::<bool>()).prop_map(
        |(parent, kind, axis, origin, continuous)| {
            let (lower, upper) = match kind {
                JointKind::Revolute => REVOLUTE_RANGE,
                JointKind::Prismatic => PRISMATIC_RANGE,
            };
            // Continuous joints (no limits) exist only for revolute joints.
            let limited = kind == JointKind::Prismatic || !continuous;
            let limits = limited.then_some(Limits {
                lower,
                upper,
                velocity: 2.0,
                effort: 100.0,
            });
            JointSpec {
                parent,
                kind,
                axis,
                origin,
                limits,
            }
        },
    )
}

/// Unit axes: an exact ±x/±y/±z half of the time (real robots), otherwise uniform on the sphere.
pub fn arb_axis() -> impl Strategy<Value = Vector3<f64>> {
    let coordinate = (0..3usize, any::<bool>()).prop_map(|(k, negative)| {
        let mut axis = Vector3::zeros();
        axis[k] = if negative { -1.0 } else { 1.0 };
        axis
    });
    // Uniform on the sphere: z uniform in [−1, 1], longitude uniform (Archimedes).
    let general = (-1.0..=1.0f64, 0.0..TAU).prop_map(|(z, phi): (f64, f64)| {
        let r = (1.0 - z * z).max(0.0).sqrt();
        Vector3::new(r * phi.cos(), r * phi.sin(), z).normalize()
    });
    prop_oneof![coordinate, general]
}

/// Rotations: identity, exact quarter turns about fixed axes (as URDFs write them), or general.
pub fn arb_rotation() -> impl Strategy<Value = Matrix3<f64>> {
    let rpy = |rpy: [f64; 3]| from_xyz_rpy([0.0; 3], rpy).rotation;
    let quarter_turns = |k: i32| f64::from(k) * FRAC_PI_2;
    prop_oneof![
        1 => Just(Matrix3::identity()),
        // `from_xyz_rpy` makes multiples of π/2 exact (0, ±1 entries).
        2 => [0..4i32, 0..4i32, 0..4i32].prop_map(move |k| rpy(k.map(quarter_turns))),
        3 => [-PI..PI, -FRAC_PI_2..FRAC_PI_2, -PI..PI].prop_map(rpy),
    ]
}

/// Translations up to about 0.5 m: zero, along one coordinate axis, or general.
pub fn arb_translation() -> impl Strategy<Value = Vector3<f64>> {
    prop_oneof![
        1 => Just(Vector3::zeros()),
        2 => (0..3usize, -0.5..0.5f64).prop_map(|(k, d)| {
            let mut t = Vector3::zeros();
            t[k] = d;
            t
        }),
        3 => [-0.3..0.3f64, -0.3..0.3f64, -0.3..0.3f64].prop_map(Vector3::from),
    ]
}

/// Joint origins and frame placements.
pub fn arb_pose() -> impl Strategy<Value = Pose> {
    (arb_rotation(), arb_translation()).prop_map(|(rotation, translation)| Pose {
        rotation,
        translation,
    })
}

/// Physically valid rigid-body inertias.
///
/// Mass 0.1–10 kg, centre of mass within 0.2 m of the joint frame (inside a link of about
/// 0.5 m). The principal moments come from radii of gyration `r_k` along the principal axes,
/// `I_1 = m (r_2² + r_3²)` and cyclically, so they satisfy the triangle inequality by
/// construction (equality in the limit of a rod or a plate, which small radii approach). A
/// random principal frame gives non-zero products of inertia; sometimes the inertia stays
/// diagonal, as URDF authors often write it.
pub fn arb_inertia() -> impl Strategy<Value = Inertia> {
    let com = prop_oneof![
        1 => Just(Vector3::zeros()),
        4 => [-0.2..0.2f64, -0.2..0.2f64, -0.2..0.2f64].prop_map(Vector3::from),
    ];
    let principal_frame = prop_oneof![1 => Just(Matrix3::identity()), 3 => arb_rotation()];
    (
        0.1..=10.0f64,
        com,
        [0.01..0.2f64, 0.01..0.2f64, 0.01..0.2f64],
        principal_frame,
    )
        .prop_map(|(mass, com, radii, rot)| {
            let [r1, r2, r3] = radii.map(|r| r * r);
            let principal = Vector3::new(r2 + r3, r1 + r3, r1 + r2) * mass;
            let inertia = rot * Matrix3::from_diagonal(&principal) * rot.transpose();
            // Exactly symmetric, as a description file would state it.
            let inertia_com = (inertia + inertia.transpose()) * 0.5;
            Inertia {
                mass,
                com,
                inertia_com,
            }
        })
}

/// Gravity of magnitude about 9.81 m/s²: mostly −z, sometimes tilted (a robot mounted on a
/// wall or a slope), so that no code may assume it.
pub fn arb_gravity() -> impl Strategy<Value = Vector3<f64>> {
    let tilted = (arb_axis(), 9.7..9.9f64).prop_map(|(direction, magnitude)| direction * magnitude);
    prop_oneof![3 => Just(Vector3::new(0.0, 0.0, -9.81)), 1 => tilted]
}

/// A proptest runner with a fixed seed and no failure files: every run checks the same `cases`
/// random trees, so CI is reproducible.
pub fn deterministic_runner(cases: u32) -> TestRunner {
    TestRunner::new(Config {
        cases,
        failure_persistence: None,
        source_file: None,
        rng_algorithm: RngAlgorithm::ChaCha,
        rng_seed: RngSeed::Fixed(0x0D1A_6E11_0AC1_E500),
        ..Config::default()
    })
}

/// `inertia` with its mass set to `mass`, the same radii of gyration (the rotational inertia
/// scaled with the mass), so it stays physical.
fn with_mass(inertia: Inertia, mass: f64) -> Inertia {
    let scale = mass / inertia.mass;
    Inertia {
        mass,
        com: inertia.com,
        inertia_com: inertia.inertia_com * scale,
    }
}

/// A random tree of 1 to `max_dof` joints ([`arb_model`]) on a free-flying base, with masses
/// that differ by orders of magnitude, as on real floating robots: a base body of 0.1 to 100 kg
/// (log-uniform, the inertia of [`arb_inertia`] scaled with it), about one link in four light
/// (1 to 100 g), and half of the time a heavy tool (20 to 50 kg) on the end-effector's body.
/// Frame `1 + i` sits at body `i`'s origin (frame 0 is the end-effector, `tool`), so
/// `FloatingDynamics::frame_pose` gives every body's world pose.
pub fn arb_floating_model(max_dof: usize) -> impl Strategy<Value = Model> {
    arb_model(max_dof)
        .prop_flat_map(|model| {
            let n = model.joints().len();
            let link_masses = proptest::collection::vec(
                prop_oneof![3 => Just(None), 1 => (-3.0..-1.0f64).prop_map(Some)],
                n,
            );
            let tool = prop_oneof![Just(None), (20.0..50.0f64).prop_map(Some)];
            (Just(model), arb_inertia(), -1.0..2.0f64, link_masses, tool)
        })
        .prop_map(|(model, base, log_base_mass, link_masses, tool)| {
            let tool_body = model.end_effector_body();
            let bodies: Vec<Body> = model
                .bodies()
                .iter()
                .zip(&link_masses)
                .enumerate()
                .map(|(i, (body, light))| {
                    let inertia = match (i == tool_body, tool, light) {
                        (true, Some(mass), _) => with_mass(body.inertia, mass),
                        (_, _, Some(log_mass)) => with_mass(body.inertia, 10f64.powf(*log_mass)),
                        _ => body.inertia,
                    };
                    Body {
                        name: body.name.clone(),
                        inertia,
                    }
                })
                .collect();
            let frames = (0..bodies.len())
                .map(|i| Frame {
                    name: format!("origin{i}"),
                    parent: Some(i),
                    placement: Pose::identity(),
                })
                .collect();
            let base = Body {
                name: "base".into(),
                inertia: with_mass(base, 10f64.powf(log_base_mass)),
            };
            model
                .with_bodies(bodies)
                .and_then(|m| m.with_frames(frames))
                .and_then(|m| m.with_floating_base(base))
                .expect("random floating trees are valid models")
        })
}

/// A floating-base state: a configuration `q` (random position within 1 m, uniformly random
/// orientation, joints over their ranges), a velocity `v`, an acceleration `a` and reference
/// ones `vr`, `ar` ([`random_floating_sample`]).
#[derive(Clone, Debug)]
pub struct FloatingSample {
    pub q: Vec<f64>,
    pub v: Vec<f64>,
    pub a: Vec<f64>,
    pub vr: Vec<f64>,
    pub ar: Vec<f64>,
}

/// A uniformly random unit quaternion `x y z w`.
pub fn random_quaternion(rng: &mut SplitMix64) -> [f64; 4] {
    loop {
        let q: [f64; 4] = std::array::from_fn(|_| rng.uniform((-1.0, 1.0)));
        let n = q.iter().map(|x| x * x).sum::<f64>().sqrt();
        // Uniform in the unit ball, then on the sphere: a uniformly random rotation.
        if n > 0.1 && n <= 1.0 {
            return q.map(|x| x / n);
        }
    }
}

/// The floating-base state of `seed`: the joints as [`random_state`], the base's twist and
/// acceleration of a walking robot's size.
pub fn random_floating_sample(model: &Model, seed: u64) -> FloatingSample {
    let joints = random_state(model, seed);
    let mut rng = SplitMix64::new(seed ^ 0x5EED_F10A_7000_0001);
    let mut q: Vec<f64> = (0..3).map(|_| rng.uniform((-1.0, 1.0))).collect();
    q.extend(random_quaternion(&mut rng));
    q.extend(&joints.q);
    let mut twist = |lin: f64, ang: f64, rest: &[f64]| -> Vec<f64> {
        let mut out: Vec<f64> = (0..3).map(|_| rng.uniform((-lin, lin))).collect();
        out.extend((0..3).map(|_| rng.uniform((-ang, ang))));
        out.extend(rest);
        out
    };
    FloatingSample {
        v: twist(1.0, 1.5, &joints.qd),
        a: twist(3.0, 5.0, &joints.qdd),
        vr: twist(1.0, 1.5, &joints.v),
        ar: twist(3.0, 5.0, &joints.a),
        q,
    }
}

/// `model` with some joints made mimic joints of others: multipliers ±1 (angle sums) or in
/// ±[0.3, 2], offsets in [−0.5, 0.5].
pub fn with_random_mimics(model: Model, seed: u64) -> Model {
    let mut rng = SplitMix64::new(seed);
    let n = model.joints().len();
    let mut mimics: Vec<Option<Mimic>> = vec![None; n];
    for j in 0..n {
        let masters: Vec<usize> = (0..n).filter(|&k| k != j && mimics[k].is_none()).collect();
        let is_master = mimics.iter().flatten().any(|m| m.master == j);
        if masters.is_empty() || is_master || rng.uniform((0.0, 1.0)) < 0.6 {
            continue;
        }
        let master = masters[(rng.uniform((0.0, masters.len() as f64)) as usize).min(masters.len() - 1)];
        let sign = if rng.uniform((0.0, 1.0)) < 0.5 { -1.0 } else { 1.0 };
        let multiplier = match rng.uniform((0.0, 1.0)) < 0.4 {
            true => sign,
            false => sign * rng.uniform((0.3, 2.0)),
        };
        let offset = rng.uniform((-0.5, 0.5));
        mimics[j] = Some(Mimic {
            master,
            multiplier,
            offset,
        });
    }
    model.with_mimics(mimics).expect("valid couplings")
}
