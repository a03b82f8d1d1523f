//! Functions emitted in chunks compute exactly what the same functions emitted whole compute.
//!
//! Only very large robots (a humanoid, a long chain) have functions over
//! `CHUNK_VALUES` values, too slow to compile here; so the Kinova arm is traced once and
//! emitted twice, whole and with chunks of 64 values (every function of more than 64 values
//! becomes chunk functions handing scalars and lane vectors on to each other, in the scalar and
//! the lane form, for every result shape), into one fresh crate whose test calls every function
//! of both (and the `_into` forms, on a buffer written at another state first) at several states
//! and compares the results bit for bit.

use super::generated_crate::{cargo, workspace_root, write_crate};
use dyngen_codegen::description::load;
use dyngen_codegen::internals::generate::{emit, emit_with, trace, Provenance, Sizes, SIZES};

/// Values per chunk in the chunked copy: small enough that every function of more than a few
/// dozen operations is split, several times over.
const SMALL_CHUNKS: usize = 64;

/// The test of the temporary crate: every generated function of `whole` and `chunked` at the
/// same states, flattened, compared bit for bit.
const COMPARISON: &str = r#"//! Written by `chunked_code.rs` of dyngen's downstream tests.

use dyngen_runtime::nalgebra::{SMatrix, SVector};
use dyngen_runtime::prelude::*;
use dyngen_runtime::{f64x4, JointTrigLanes, Lanes, Pose, ResultBuffer, SplitMix64};
use generated_chunks::{chunked, whole};

const N: usize = whole::DOF;
const P: usize = whole::PARAMETER_COUNT;
const B: usize = whole::BASE_PARAMETER_COUNT;

fn push<const R: usize, const C: usize>(out: &mut Vec<f64>, m: &SMatrix<f64, R, C>) {
    out.extend(m.iter().copied());
}

fn push_pose(out: &mut Vec<f64>, p: &Pose) {
    out.extend(p.rotation.iter().copied());
    out.extend(p.translation.iter().copied());
}

/// Every function of `R` at the state `k`, flattened.
fn everything<R>(k: u64) -> Vec<f64>
where
    R: Kinematics<N>
        + RobotDynamics<N, P>
        + Regressors<N, P>
        + BaseParameters<N, P, B>
        + ForwardDynamics<N, P>
        + DynamicsDerivatives<N, P>
        + FrameKinematics<N>
        + LaneDynamics<N, B>,
{
    let mut rng = SplitMix64::new(k);
    let mut draw = |bound: f64| SVector::<f64, N>::from_fn(|_, _| rng.uniform((-bound, bound)));
    let (q, qd, v, a, tau) = (draw(3.0), draw(2.0), draw(2.0), draw(5.0), draw(10.0));
    let r = draw(1.0);
    // The `_into` forms write a buffer last written at another state.
    let earlier = JointTrig::new(&draw(3.0));
    let theta = SVector::<f64, P>::from_fn(|i, _| 0.5 + 0.01 * i as f64);
    let t = JointTrig::new(&q);
    let mut out = Vec::new();
    push_pose(&mut out, &R::forward_kinematics(&t));
    push(&mut out, &R::jacobian(&t));
    push(&mut out, &R::jacobian_dot(&t, &qd));
    let (pose, j, jd) = R::kinematics(&t, &qd);
    push_pose(&mut out, &pose);
    push(&mut out, &j);
    push(&mut out, &jd);
    push(&mut out, &R::mass_matrix(&t));
    push(&mut out, &R::coriolis_matrix(&t, &qd));
    push(&mut out, &R::gravity(&t));
    push(&mut out, &R::inverse_dynamics(&t, &qd, &a));
    push(&mut out, &R::slotine_li(&t, &qd, &v, &a));
    push(&mut out, &R::regressor(&t, &qd, &v, &a));
    push(&mut out, &R::torque_regressor(&t, &qd, &a));
    let (y_theta, y_t_r) = R::regressor_products(&t, &qd, &v, &a, &theta, &r);
    push(&mut out, &y_theta);
    push(&mut out, &y_t_r);
    let theta_b = R::base_parameters(&theta);
    push(&mut out, &theta_b);
    push(&mut out, &R::base_regressor(&t, &qd, &v, &a));
    push(&mut out, &R::base_torque_regressor(&t, &qd, &a));
    let (yb_theta, yb_t_r) = R::base_regressor_products(&t, &qd, &v, &a, &theta_b, &r);
    push(&mut out, &yb_theta);
    push(&mut out, &yb_t_r);
    push(&mut out, &R::forward_dynamics(&t, &qd, &tau));
    push(&mut out, &R::mass_matrix_inverse(&t));
    let (dq, dqd) = R::inverse_dynamics_derivatives(&t, &qd, &a);
    push(&mut out, &dq);
    push(&mut out, &dqd);
    let (dq, dqd) = R::forward_dynamics_derivatives(&t, &qd, &tau);
    push(&mut out, &dq);
    push(&mut out, &dqd);
    let mut d = ResultBuffer::new();
    for t in [&earlier, &t] {
        R::mass_matrix_into(t, &mut d);
    }
    push(&mut out, &d);
    let mut c = ResultBuffer::new();
    for t in [&earlier, &t] {
        R::coriolis_matrix_into(t, &qd, &mut c);
    }
    push(&mut out, &c);
    let mut y = ResultBuffer::new();
    for t in [&earlier, &t] {
        R::regressor_into(t, &qd, &v, &a, &mut y);
    }
    push(&mut out, &y);
    for t in [&earlier, &t] {
        R::torque_regressor_into(t, &qd, &a, &mut y);
    }
    push(&mut out, &y);
    let mut yb = ResultBuffer::new();
    for t in [&earlier, &t] {
        R::base_regressor_into(t, &qd, &v, &a, &mut yb);
    }
    push(&mut out, &yb);
    for t in [&earlier, &t] {
        R::base_torque_regressor_into(t, &qd, &a, &mut yb);
    }
    push(&mut out, &yb);
    for t in [&earlier, &t] {
        R::mass_matrix_inverse_into(t, &mut d);
    }
    push(&mut out, &d);
    let mut pair = ResultBuffer::new();
    for t in [&earlier, &t] {
        R::inverse_dynamics_derivatives_into(t, &qd, &a, &mut pair);
    }
    push(&mut out, &pair.0);
    push(&mut out, &pair.1);
    for t in [&earlier, &t] {
        R::forward_dynamics_derivatives_into(t, &qd, &tau, &mut pair);
    }
    push(&mut out, &pair.0);
    push(&mut out, &pair.1);
    for &frame in <R as FrameKinematics<N>>::Frame::ALL {
        push_pose(&mut out, &R::frame_pose(frame, &t));
        for reference in [ReferenceFrame::Local, ReferenceFrame::World, ReferenceFrame::LocalWorldAligned] {
            push(&mut out, &R::frame_jacobian(frame, reference, &t));
            push(&mut out, &R::frame_jacobian_time_variation(frame, reference, &t, &qd));
            push(&mut out, &R::frame_velocity(frame, reference, &t, &qd));
            push(&mut out, &R::frame_classical_acceleration(frame, reference, &t, &qd, &a));
        }
        let (pose, j, jd) = R::frame_kinematics(frame, &t, &qd);
        push_pose(&mut out, &pose);
        push(&mut out, &j);
        push(&mut out, &jd);
    }
    // Four states in the lanes: this one and three others.
    let lanes = |x: &SVector<f64, N>| -> [f64x4; N] {
        core::array::from_fn(|i| f64x4::from_fn(|l| x[i] * (1.0 - 0.1 * l as f64)))
    };
    let tl = JointTrigLanes::new(&lanes(&q));
    for x in R::inverse_dynamics_lanes(&tl, &lanes(&qd), &lanes(&a)) {
        out.extend((0..4).map(|l| x.lane(l)));
    }
    for column in R::base_torque_regressor_lanes(&tl, &lanes(&qd), &lanes(&a)) {
        for x in column {
            out.extend((0..4).map(|l| x.lane(l)));
        }
    }
    out
}

#[test]
fn chunked_functions_compute_what_whole_ones_do() {
    for k in 0..4 {
        let (whole, chunked) = (everything::<whole::Robot>(k), everything::<chunked::Robot>(k));
        assert_eq!(whole.len(), chunked.len());
        assert!(whole.iter().filter(|x| **x != 0.0).count() > whole.len() / 2, "a state that exercises the code");
        for (i, (w, c)) in whole.iter().zip(&chunked).enumerate() {
            assert_eq!(w.to_bits(), c.to_bits(), "state {k}, value {i}: whole {w}, chunked {c}");
        }
    }
}
"#;

#[test]
fn chunked_functions_compute_what_whole_ones_do() {
    let root = workspace_root();
    let description = root.join("codegen/tests/data/example-robot-data/kinova_description/kinova.urdf");
    let model = load(&description).unwrap_or_else(|e| panic!("{e}")).model;
    let robot = trace(&model);
    let provenance = Provenance {
        source: "kinova.urdf".into(),
        source_hash: "0".into(),
        regenerate: "the downstream test `chunked_code`".into(),
        type_name: "Robot".into(),
    };
    let whole = emit(&model, &robot, &provenance);
    let small = Sizes {
        chunk_values: SMALL_CHUNKS,
        ..SIZES
    };
    let chunked = emit_with(&model, &robot, &provenance, &small);
    // The chunked copy has what this test is for: chunks of both forms, handing on scalars and
    // lane vectors, and results written in place as well as built by the caller.
    for (what, needle) in [
        ("a derivative in chunks", "fn inverse_dynamics_derivatives_part1("),
        (
            "a lane-form function in chunks",
            "fn inverse_dynamics_lanes_part1<C: Lanes>(",
        ),
        ("lane vectors handed on", "&mut [[f64; 8];"),
        ("a pose built from chunks", "fn forward_kinematics_part1("),
    ] {
        assert!(
            chunked.contains(needle),
            "{what}: no `{needle}` in the chunked module"
        );
    }
    // Emitted whole, a module splits only the derivatives of forward dynamics (into their two
    // stages: each a definition of `…_part0(` and a call in each of the two forms, by value and
    // `_into`).
    let stages = whole.matches("fn forward_dynamics_derivatives_part0(").count();
    assert!(
        whole.matches("_part0(").count() == 3 * stages,
        "the whole module has chunks"
    );

    let dir = tempfile::tempdir().expect("temp dir");
    let krate = dir.path();
    for sub in ["src", "tests"] {
        std::fs::create_dir_all(krate.join(sub)).expect("crate directory");
    }
    std::fs::write(krate.join("src/whole.rs"), whole).expect("whole.rs");
    std::fs::write(krate.join("src/chunked.rs"), chunked).expect("chunked.rs");
    write_crate(krate, "generated-chunks", &["chunked", "whole"]);
    std::fs::write(krate.join("tests/chunks.rs"), COMPARISON).expect("test");
    // Optimised: the kernels run through the same dispatch as a user's release build.
    let (success, stdout, stderr) = cargo(krate, &["test", "--release"]);
    assert!(success, "the chunked crate's test fails:\n{stdout}\n{stderr}");
    assert!(
        stdout.contains("test chunked_functions_compute_what_whole_ones_do ... ok"),
        "the comparison ran:\n{stdout}"
    );
}
