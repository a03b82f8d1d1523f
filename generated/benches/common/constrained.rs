//! The constrained functions of a floating-base robot with contacts (`ContactDynamics` and the
//! runtime's solves over it), timed alike for every robot: Solo-12 from `benches/contacts.rs`,
//! the G1 from its own crate (`tools/anchors/contacts/dyngen/`), which includes this file. The
//! numeric Pinocchio anchor (`tools/anchors/contacts/bench_contacts.cpp`) draws the same states
//! and anchors, uses the same settings and names its rows alike; `tools/compare_contacts.py`
//! sets them side by side.
//!
//! Each call includes `FloatingTrig::from_configuration`, as each Pinocchio call includes its
//! joint transforms.

use crate::common::{cycle, floating_states};
use criterion::Criterion;
use dyngen_runtime::nalgebra::{Rotation3, SVector, Vector3};
use dyngen_runtime::{
    constrained_forward_dynamics, constrained_forward_dynamics_derivatives, impulse_dynamics,
    operational_space_inertia, ContactDynamics, FloatingTrig, Pose, ProximalSettings, Stabilisation,
};
use std::hint::black_box;

/// The seed of the states (`floating_states`), the one of `benches/floating.rs`.
pub const SEED: u64 = 18;
/// Baumgarte gains of the stabilised solve: `K_d = 2 √K_p`, critically damped.
pub const KP: f64 = 10.0;
/// The restitution of the impact.
pub const RESTITUTION: f64 = 0.5;
/// Each anchor is its frame's pose at the state, moved by this much along the world axes …
pub const ANCHOR_SHIFT: [f64; 3] = [0.01, -0.02, 0.015];
/// … and turned by this angle (rad) about the frame's own x axis.
pub const ANCHOR_TURN: f64 = 0.02;
/// The proximal solve: Pinocchio's suggested regularisation, iterated until the rows' residual
/// or the change of the forces is at most the accuracy (Pinocchio's `ProximalSettings(accuracy,
/// mu, max_iter)` stops on the same two tests).
pub const PROXIMAL: ProximalSettings = ProximalSettings {
    mu: 1e-4,
    max_iterations: 50,
    accuracy: 1e-10,
};

/// The timed functions, as the criterion groups and the anchor's rows name them, in the order of
/// the check sums.
const FUNCTIONS: [&str; 10] = [
    "constrained_forward_dynamics",
    "constrained_forward_dynamics_baumgarte",
    "constrained_forward_dynamics_proximal",
    "impulse_dynamics",
    "operational_space_inertia",
    "contact_jacobian",
    "contact_drift",
    "contact_response",
    "free_acceleration",
    "constrained_forward_dynamics_derivatives",
];

/// Where a contact is held at a state: near where its frame is, so that the stabilised solve
/// has an error to feed back.
fn anchor(at: &Pose) -> Pose {
    Pose {
        rotation: at.rotation * Rotation3::from_axis_angle(&Vector3::x_axis(), ANCHOR_TURN).into_inner(),
        translation: at.translation + Vector3::from(ANCHOR_SHIFT),
    }
}

fn trig<const N: usize>(q: &[f64]) -> FloatingTrig<N> {
    // The states are unit quaternions by construction.
    FloatingTrig::from_configuration(q).unwrap_or_else(|e| panic!("{e}"))
}

/// A state of the constrained benches: `q`, `ν`, `τ` and the anchors of the contacts at `q`.
type ConstrainedState<const NQ: usize, const NV: usize> =
    (SVector<f64, NQ>, SVector<f64, NV>, SVector<f64, NV>, Vec<Pose>);

/// Times, as criterion groups `<robot>/<function>` (id `generated`): constrained forward
/// dynamics exact, Baumgarte-stabilised and proximal, the impact, the operational-space
/// inertia, the generated rows and the one generated call each solve makes.
pub fn bench<R, const N: usize, const NQ: usize, const NV: usize, const NC: usize>(
    c: &mut Criterion,
    robot: &str,
) where
    R: ContactDynamics<NV, NC, Trig = FloatingTrig<N>>,
{
    assert!(
        R::CONTACT_TO.iter().all(Option::is_none),
        "{robot}: the benches hold every contact to the world"
    );
    let inputs: Vec<ConstrainedState<NQ, NV>> = floating_states::<NQ, NV>(SEED)
        .into_iter()
        .map(|(q, [v, _, tau])| {
            let t = trig::<N>(q.as_slice());
            let anchors = (0..R::CONTACT_FRAMES.len())
                .map(|k| anchor(&R::contact_pose(&t, k)))
                .collect();
            (q, v, tau, anchors)
        })
        .collect();
    report::<R, N, NQ, NV, NC>(robot, &inputs);
    let g = |f: &str| format!("{robot}/{f}");
    let exact = ProximalSettings::default();
    let kd = 2.0 * KP.sqrt();

    cycle(
        c,
        &g("constrained_forward_dynamics"),
        "generated",
        &inputs,
        |(q, v, tau, _)| {
            let t = trig::<N>(q.as_slice());
            black_box(constrained_forward_dynamics::<R, NV, NC>(&t, v, tau, None, &exact, None).unwrap());
        },
    );
    cycle(
        c,
        &g("constrained_forward_dynamics_baumgarte"),
        "generated",
        &inputs,
        |(q, v, tau, anchors)| {
            let t = trig::<N>(q.as_slice());
            let stabilisation = Stabilisation { anchors, kp: KP, kd };
            black_box(
                constrained_forward_dynamics::<R, NV, NC>(&t, v, tau, Some(stabilisation), &exact, None)
                    .unwrap(),
            );
        },
    );
    cycle(
        c,
        &g("constrained_forward_dynamics_proximal"),
        "generated",
        &inputs,
        |(q, v, tau, _)| {
            let t = trig::<N>(q.as_slice());
            black_box(constrained_forward_dynamics::<R, NV, NC>(&t, v, tau, None, &PROXIMAL, None).unwrap());
        },
    );
    cycle(c, &g("impulse_dynamics"), "generated", &inputs, |(q, v, _, _)| {
        let t = trig::<N>(q.as_slice());
        black_box(impulse_dynamics::<R, NV, NC>(&t, v, RESTITUTION, 0.0).unwrap());
    });
    cycle(
        c,
        &g("operational_space_inertia"),
        "generated",
        &inputs,
        |(q, _, _, _)| {
            let t = trig::<N>(q.as_slice());
            black_box(operational_space_inertia::<R, NV, NC>(&t, 0.0).unwrap());
        },
    );
    // The generated pieces, each from the configuration: where the time of the solves goes.
    cycle(c, &g("contact_jacobian"), "generated", &inputs, |(q, _, _, _)| {
        black_box(R::contact_jacobian(&trig::<N>(q.as_slice())));
    });
    cycle(c, &g("contact_drift"), "generated", &inputs, |(q, v, _, _)| {
        black_box(R::contact_drift(&trig::<N>(q.as_slice()), v));
    });
    cycle(c, &g("contact_response"), "generated", &inputs, |(q, _, _, _)| {
        black_box(R::contact_response(&trig::<N>(q.as_slice())));
    });
    cycle(
        c,
        &g("free_acceleration"),
        "generated",
        &inputs,
        |(q, v, tau, _)| {
            black_box(R::free_acceleration(&trig::<N>(q.as_slice()), v, tau));
        },
    );
    // The one generated call each solve makes (the kinematics, the factored mass matrix and the
    // factored Delassus matrix shared within it), with the settings of the solves above.
    let zero = SVector::<f64, NC>::zeros();
    cycle(c, &g("contact_solve"), "generated", &inputs, |(q, v, tau, _)| {
        black_box(R::contact_solve(
            &trig::<N>(q.as_slice()),
            v,
            tau,
            &zero,
            &zero,
            0.0,
            0.0,
        ));
    });
    cycle(
        c,
        &g("contact_proximal_solve"),
        "generated",
        &inputs,
        |(q, v, tau, _)| {
            let t = trig::<N>(q.as_slice());
            black_box(R::contact_proximal_solve(
                &t,
                v,
                tau,
                &zero,
                &zero,
                0.0,
                PROXIMAL.mu,
            ));
        },
    );
    cycle(c, &g("contact_impulse"), "generated", &inputs, |(q, v, _, _)| {
        black_box(R::contact_impulse(&trig::<N>(q.as_slice()), v, RESTITUTION, 0.0));
    });
    cycle(c, &g("contact_inertia"), "generated", &inputs, |(q, _, _, _)| {
        black_box(R::contact_inertia(&trig::<N>(q.as_slice()), 0.0));
    });
    // The derivatives at the exact solution, which the call solves first (as Pinocchio's
    // `constraintDynamics` then `computeConstraintDynamicsDerivatives`).
    cycle(
        c,
        &g("constrained_forward_dynamics_derivatives"),
        "generated",
        &inputs,
        |(q, v, tau, _)| {
            let t = trig::<N>(q.as_slice());
            let solved = constrained_forward_dynamics::<R, NV, NC>(&t, v, tau, None, &exact, None).unwrap();
            black_box(constrained_forward_dynamics_derivatives::<R, NV, NC>(&t, v, &solved, None).unwrap());
        },
    );
}

/// Prints, to stderr as `#` lines as the anchor prints its own, the proximal solve's mean
/// iterations and, per function, the sum over the states of its result's norm: the same on both
/// sides when both compute the same thing on the same states (`tools/compare_contacts.py`
/// compares them).
fn report<R, const N: usize, const NQ: usize, const NV: usize, const NC: usize>(
    robot: &str,
    inputs: &[ConstrainedState<NQ, NV>],
) where
    R: ContactDynamics<NV, NC, Trig = FloatingTrig<N>>,
{
    let kd = 2.0 * KP.sqrt();
    let exact = ProximalSettings::default();
    let solve = |t: &FloatingTrig<N>,
                 v: &SVector<f64, NV>,
                 tau: &SVector<f64, NV>,
                 stabilisation: Option<Stabilisation<'_>>,
                 settings: &ProximalSettings| {
        constrained_forward_dynamics::<R, NV, NC>(t, v, tau, stabilisation, settings, None)
            .unwrap_or_else(|e| panic!("{robot}: {e}"))
    };
    let mut sums = [0.0; 10];
    let mut iterations = 0;
    for (q, v, tau, anchors) in inputs {
        let t = trig::<N>(q.as_slice());
        let stabilisation = Stabilisation { anchors, kp: KP, kd };
        let proximal = solve(&t, v, tau, None, &PROXIMAL);
        iterations += proximal.iterations;
        let impact =
            impulse_dynamics::<R, NV, NC>(&t, v, RESTITUTION, 0.0).unwrap_or_else(|e| panic!("{robot}: {e}"));
        let inertia =
            operational_space_inertia::<R, NV, NC>(&t, 0.0).unwrap_or_else(|e| panic!("{robot}: {e}"));
        let derivatives = |t: &FloatingTrig<N>, v: &SVector<f64, NV>, tau: &SVector<f64, NV>| {
            let solved = solve(t, v, tau, None, &exact);
            let d = constrained_forward_dynamics_derivatives::<R, NV, NC>(t, v, &solved, None)
                .unwrap_or_else(|e| panic!("{robot}: {e}"));
            d.acceleration_q.norm()
        };
        let norms = [
            solve(&t, v, tau, None, &exact).acceleration.norm(),
            solve(&t, v, tau, Some(stabilisation), &exact).acceleration.norm(),
            proximal.acceleration.norm(),
            impact.0.norm(),
            inertia.norm(),
            R::contact_jacobian(&t).norm(),
            R::contact_drift(&t, v).norm(),
            R::contact_response(&t).norm(),
            R::free_acceleration(&t, v, tau).norm(),
            derivatives(&t, v, tau),
        ];
        for (sum, norm) in sums.iter_mut().zip(norms) {
            *sum += norm;
        }
    }
    eprintln!(
        "# {robot} proximal_iterations {:.2}",
        iterations as f64 / inputs.len() as f64
    );
    for (function, sum) in FUNCTIONS.iter().zip(sums) {
        eprintln!("# {robot} check {function} {sum:.12e}");
    }
}
