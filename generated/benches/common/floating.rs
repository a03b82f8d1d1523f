//! A floating-base robot's generated functions, timed alike for every robot: Solo-12 from
//! `benches/floating.rs`, the G1 from its own crate (`tools/anchors/floating-cg/dyngen/`), which
//! includes this file. Groups are named `<robot>/<function>` as the numeric Pinocchio anchors
//! name their algorithms (`tools/compare_anchors.py` and `tools/compare_floating.py` set them
//! side by side): each call includes preparing the configuration
//! (`FloatingTrig::from_configuration`: the rotation of the base quaternion and the joint sines
//! and cosines), as Pinocchio's calls include its joint transforms. Inputs cycle through the
//! 256 states of `floating_states` (seed 18), which the anchors draw too.
//!
//! One function per group of generated functions, so that a robot generated with fewer groups
//! (the G1: no regressors, no frames) times what it has.

use crate::common::{cycle, floating_states, FloatingState};
use criterion::Criterion;
use dyngen_runtime::nalgebra::SVector;
use dyngen_runtime::{
    BasePose, FloatingBaseDynamics, FloatingBaseParameters, FloatingDynamicsDerivatives,
    FloatingForwardDynamics, FloatingFrameKinematics, FloatingTrig, JointTrig, ReferenceFrame, ResultBuffer,
};
use std::hint::black_box;

/// The seed of the states, which the anchors use too.
pub const SEED: u64 = 18;

/// The states of every floating-base bench.
pub fn states<const NQ: usize, const NV: usize>() -> Vec<FloatingState<NQ, NV>> {
    floating_states::<NQ, NV>(SEED)
}

fn trig<const N: usize>(q: &[f64]) -> FloatingTrig<N> {
    // The states are unit quaternions by construction.
    FloatingTrig::from_configuration(q).unwrap_or_else(|e| panic!("{e}"))
}

/// What a call starts from: the whole configuration's trigonometry, the joints' alone, the
/// base pose alone.
pub fn preparation<const N: usize, const NQ: usize, const NV: usize>(
    c: &mut Criterion,
    robot: &str,
    inputs: &[FloatingState<NQ, NV>],
) {
    let g = |f: &str| format!("{robot}/{f}");
    cycle(c, &g("floating_trig"), "generated", inputs, |(q, _)| {
        black_box(trig::<N>(q.as_slice()));
    });
    cycle(c, &g("joint_trig"), "generated", inputs, |(q, _)| {
        black_box(JointTrig::new(&q.fixed_rows::<N>(7).into_owned()));
    });
    cycle(c, &g("base_pose"), "generated", inputs, |(q, _)| {
        black_box(BasePose::from_configuration(q.as_slice()).unwrap());
    });
}

/// The foot's pose, Jacobian and its time variation (`fk`, `jacobian`, `jacobian_dot`), in
/// `LOCAL_WORLD_ALIGNED`.
pub fn frames<R, const N: usize, const NQ: usize, const NV: usize>(
    c: &mut Criterion,
    robot: &str,
    inputs: &[FloatingState<NQ, NV>],
    foot: R::Frame,
) where
    R: FloatingFrameKinematics<N, NV>,
    R::Frame: Copy,
{
    let g = |f: &str| format!("{robot}/{f}");
    let lwa = ReferenceFrame::LocalWorldAligned;
    cycle(c, &g("fk"), "generated", inputs, |(q, _)| {
        black_box(R::frame_pose(foot, &trig(q.as_slice())));
    });
    cycle(c, &g("jacobian"), "generated", inputs, |(q, _)| {
        black_box(R::frame_jacobian(foot, lwa, &trig(q.as_slice())));
    });
    cycle(c, &g("jacobian_dot"), "generated", inputs, |(q, [v, ..])| {
        black_box(R::frame_jacobian_time_variation(
            foot,
            lwa,
            &trig(q.as_slice()),
            v,
        ));
    });
}

/// The dynamics the anchors time: `D`, `C`, `g`, inverse and forward dynamics, `D⁻¹`, both
/// derivatives, the centre of mass and the centroidal map and bias; the `_into` forms write
/// into a result kept between calls (`ResultBuffer`).
pub fn dynamics<R, const N: usize, const NQ: usize, const NV: usize, const P: usize>(
    c: &mut Criterion,
    robot: &str,
    inputs: &[FloatingState<NQ, NV>],
) where
    R: FloatingBaseDynamics<N, NV, P>
        + FloatingForwardDynamics<N, NV, P>
        + FloatingDynamicsDerivatives<N, NV, P>,
{
    let g = |f: &str| format!("{robot}/{f}");
    let t = |q: &SVector<f64, NQ>| trig::<N>(q.as_slice());
    cycle(c, &g("mass_matrix"), "generated", inputs, |(q, _)| {
        black_box(R::mass_matrix(&t(q)));
    });
    let mut d = ResultBuffer::new();
    cycle(c, &g("mass_matrix"), "generated_into", inputs, |(q, _)| {
        R::mass_matrix_into(&t(q), &mut d);
        black_box(&d);
    });
    cycle(c, &g("coriolis"), "generated", inputs, |(q, [v, ..])| {
        black_box(R::coriolis_matrix(&t(q), v));
    });
    let mut cm = ResultBuffer::new();
    cycle(c, &g("coriolis"), "generated_into", inputs, |(q, [v, ..])| {
        R::coriolis_matrix_into(&t(q), v, &mut cm);
        black_box(&cm);
    });
    cycle(c, &g("gravity"), "generated", inputs, |(q, _)| {
        black_box(R::gravity(&t(q)));
    });
    cycle(c, &g("rnea"), "generated", inputs, |(q, [v, a, _])| {
        black_box(R::inverse_dynamics(&t(q), v, a));
    });
    cycle(c, &g("aba"), "generated", inputs, |(q, [v, _, tau])| {
        black_box(R::forward_dynamics(&t(q), v, tau));
    });
    cycle(
        c,
        &g("rnea_derivatives"),
        "generated",
        inputs,
        |(q, [v, a, _])| {
            black_box(R::inverse_dynamics_derivatives(&t(q), v, a));
        },
    );
    let mut d_tau = ResultBuffer::new();
    cycle(
        c,
        &g("rnea_derivatives"),
        "generated_into",
        inputs,
        |(q, [v, a, _])| {
            R::inverse_dynamics_derivatives_into(&t(q), v, a, &mut d_tau);
            black_box(&d_tau);
        },
    );
    cycle(
        c,
        &g("aba_derivatives"),
        "generated",
        inputs,
        |(q, [v, _, tau])| {
            black_box(R::forward_dynamics_derivatives(&t(q), v, tau));
        },
    );
    let mut d_nu = ResultBuffer::new();
    cycle(
        c,
        &g("aba_derivatives"),
        "generated_into",
        inputs,
        |(q, [v, _, tau])| {
            R::forward_dynamics_derivatives_into(&t(q), v, tau, &mut d_nu);
            black_box(&d_nu);
        },
    );
    cycle(c, &g("minv"), "generated", inputs, |(q, _)| {
        black_box(R::mass_matrix_inverse(&t(q)));
    });
    let mut minv = ResultBuffer::new();
    cycle(c, &g("minv"), "generated_into", inputs, |(q, _)| {
        R::mass_matrix_inverse_into(&t(q), &mut minv);
        black_box(&minv);
    });
    cycle(c, &g("com"), "generated", inputs, |(q, _)| {
        black_box(R::center_of_mass(&t(q)));
    });
    cycle(c, &g("ccrba"), "generated", inputs, |(q, _)| {
        black_box(R::centroidal_momentum_matrix(&t(q)));
    });
    cycle(c, &g("dccrba"), "generated", inputs, |(q, [v, ..])| {
        black_box(R::centroidal_bias(&t(q), v));
    });
}

/// The torque-form regressors, standard and base parameters.
pub fn regressors<R, const N: usize, const NQ: usize, const NV: usize, const P: usize, const B: usize>(
    c: &mut Criterion,
    robot: &str,
    inputs: &[FloatingState<NQ, NV>],
) where
    R: FloatingBaseParameters<N, NV, P, B>,
{
    let g = |f: &str| format!("{robot}/{f}");
    let t = |q: &SVector<f64, NQ>| trig::<N>(q.as_slice());
    cycle(
        c,
        &g("torque_regressor"),
        "generated",
        inputs,
        |(q, [v, a, _])| {
            black_box(R::torque_regressor(&t(q), v, a));
        },
    );
    let mut y = ResultBuffer::new();
    cycle(
        c,
        &g("torque_regressor"),
        "generated_into",
        inputs,
        |(q, [v, a, _])| {
            R::torque_regressor_into(&t(q), v, a, &mut y);
            black_box(&y);
        },
    );
    cycle(
        c,
        &g("base_torque_regressor"),
        "generated",
        inputs,
        |(q, [v, a, _])| {
            black_box(R::base_torque_regressor(&t(q), v, a));
        },
    );
    let mut yb = ResultBuffer::new();
    cycle(
        c,
        &g("base_torque_regressor"),
        "generated_into",
        inputs,
        |(q, [v, a, _])| {
            R::base_torque_regressor_into(&t(q), v, a, &mut yb);
            black_box(&yb);
        },
    );
}
