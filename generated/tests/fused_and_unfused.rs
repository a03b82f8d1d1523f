//! Every generated function runs its multiply-adds fused where the processor has FMA, even in a
//! build that does not target it (`dyngen_runtime::__private::dispatch`), and unfused elsewhere. Both
//! forms agree to rounding, and in a build that chooses at run time both really run: on an FMA
//! processor the fused results differ from the unfused ones in their last bits.
//!
//! On a processor with AVX-512, the functions that run through `dispatch_eight` (the derivatives,
//! with their lanes in one 512-bit register; `C`, the regressors; the lane functions of several
//! states per call) give the same bits in an AVX-512 function as in an AVX2 one
//! (`set_avx512_lanes`).
//!
//! Its own test binary: the choice is process-wide. Optimised builds only (debug builds compile
//! one form): `cargo test --release -p dyngen-generated --test fused_and_unfused`.

use dyngen_generated::{
    arm7, arm7_friction, panda, panda_rounded, ur5, Arm7, Arm7Friction, Panda, PandaRounded, Ur5,
};
use dyngen_runtime::__private::{
    avx512_lanes, fused_multiply_adds, set_avx512_lanes, set_fused_multiply_adds,
};
use dyngen_runtime::nalgebra::SVector;
use dyngen_runtime::{
    f64x4, f64x8, pack, unpack, BaseParameters, DynamicsDerivatives, ForwardDynamics, JointTrig,
    JointTrigLanes, LaneDynamics, Lanes, SplitMix64,
};

/// Every output of every scalar generated function at one state, one after the other.
fn outputs<R, const N: usize, const P: usize, const B: usize>(x: &[SVector<f64, N>; 4]) -> Vec<f64>
where
    R: BaseParameters<N, P, B> + ForwardDynamics<N, P> + DynamicsDerivatives<N, P> + LaneDynamics<N, B>,
{
    let [q, qd, v, a] = x;
    let t = JointTrig::new(q);
    let pose = R::forward_kinematics(&t);
    let (fused_pose, j, jd) = R::kinematics(&t, qd);
    let mut out: Vec<f64> = Vec::new();
    for p in [pose, fused_pose] {
        out.extend(p.rotation.iter().chain(p.translation.iter()));
    }
    out.extend(j.iter().chain(jd.iter()));
    out.extend(R::jacobian(&t).iter().chain(R::jacobian_dot(&t, qd).iter()));
    out.extend(R::mass_matrix(&t).iter().chain(R::coriolis_matrix(&t, qd).iter()));
    out.extend(R::gravity(&t).iter().chain(R::inverse_dynamics(&t, qd, a).iter()));
    out.extend(R::slotine_li(&t, qd, v, a).iter());
    out.extend(R::regressor(&t, qd, v, a).iter());
    out.extend(R::torque_regressor(&t, qd, a).iter());
    out.extend(R::base_regressor(&t, qd, v, a).iter());
    out.extend(R::base_torque_regressor(&t, qd, a).iter());
    let (theta, theta_b) = (R::parameters(), R::base_parameters(&R::parameters()));
    let (y_theta, y_tr_r) = R::regressor_products(&t, qd, v, a, &theta, q);
    let (y_b_theta, y_b_tr_r) = R::base_regressor_products(&t, qd, v, a, &theta_b, q);
    out.extend(y_theta.iter().chain(y_tr_r.iter()));
    out.extend(y_b_theta.iter().chain(y_b_tr_r.iter()));
    out.extend(R::forward_dynamics(&t, qd, a).iter());
    out.extend(R::mass_matrix_inverse(&t).iter());
    let (dq, dv) = R::inverse_dynamics_derivatives(&t, qd, a);
    out.extend(dq.iter().chain(dv.iter()));
    let (dq, dv) = R::forward_dynamics_derivatives(&t, qd, a);
    out.extend(dq.iter().chain(dv.iter()));
    // The lane functions, the state in every lane (lane 0 read back).
    out.extend(lane_outputs::<R, f64x4, N, B>(x));
    out.extend(lane_outputs::<R, f64x8, N, B>(x));
    out
}

/// `τ` and `Y_b` of the lane functions (`dispatch_lanes`) at `x`, from lane 0.
fn lane_outputs<R: LaneDynamics<N, B>, L: Lanes, const N: usize, const B: usize>(
    x: &[SVector<f64, N>; 4],
) -> Vec<f64> {
    let [q, qd, _, a] = x;
    let [q, qd, a] = [q, qd, a].map(|v| pack::<L, N>(&[*v]));
    let t = JointTrigLanes::new(&q);
    let mut out: Vec<f64> = unpack(&R::inverse_dynamics_lanes(&t, &qd, &a), 0)
        .iter()
        .copied()
        .collect();
    for column in R::base_torque_regressor_lanes(&t, &qd, &a) {
        out.extend(unpack(&column, 0).iter());
    }
    out
}

/// Fused against unfused at 20 random states: equal to rounding (relative to the largest
/// entry of each state's outputs); returns how many outputs differed at all.
fn check<R, const N: usize, const P: usize, const B: usize>(robot: &str) -> usize
where
    R: BaseParameters<N, P, B> + ForwardDynamics<N, P> + DynamicsDerivatives<N, P> + LaneDynamics<N, B>,
{
    let mut rng = SplitMix64::new(11);
    let mut differing = 0;
    for k in 0..20 {
        let x = [(-3.0, 3.0), (-2.0, 2.0), (-2.0, 2.0), (-5.0, 5.0)]
            .map(|r| SVector::from_fn(|_, _| rng.uniform(r)));
        set_fused_multiply_adds(true);
        let fused = outputs::<R, N, P, B>(&x);
        // The `dispatch_eight` kernels in an AVX2 function instead of an AVX-512 one where the
        // processor has it (the derivatives' lanes in two registers): the same fused operations.
        set_avx512_lanes(false);
        let two_registers = outputs::<R, N, P, B>(&x);
        set_avx512_lanes(true);
        for (i, (a, b)) in fused.iter().zip(&two_registers).enumerate() {
            assert!(
                a.to_bits() == b.to_bits() || a.is_nan() && b.is_nan(),
                "{robot}, state {k}, output {i}: {a} in AVX-512 lanes, {b} in AVX2 ones"
            );
        }
        set_fused_multiply_adds(false);
        let unfused = outputs::<R, N, P, B>(&x);
        set_fused_multiply_adds(true);
        let scale = unfused.iter().fold(1.0_f64, |m, y| m.max(y.abs()));
        for (i, (f, u)) in fused.iter().zip(&unfused).enumerate() {
            assert!(
                (f - u).abs() <= 1e-11 * scale,
                "{robot}, state {k}, output {i}: fused {f} against unfused {u}"
            );
            differing += usize::from(f.to_bits() != u.to_bits());
        }
    }
    differing
}

#[test]
#[cfg_attr(
    debug_assertions,
    ignore = "debug builds compile the unfused form only: cargo test --release -p dyngen-generated --test fused_and_unfused"
)]
fn fused_and_unfused_multiply_adds_agree_and_both_run_where_the_build_chooses() {
    let differing = [
        check::<Arm7, 7, { arm7::PARAMETER_COUNT }, { arm7::BASE_PARAMETER_COUNT }>("arm7"),
        check::<Arm7Friction, 7, { arm7_friction::PARAMETER_COUNT }, { arm7_friction::BASE_PARAMETER_COUNT }>(
            "arm7_friction",
        ),
        check::<Panda, 7, { panda::PARAMETER_COUNT }, { panda::BASE_PARAMETER_COUNT }>("panda"),
        check::<PandaRounded, 7, { panda_rounded::PARAMETER_COUNT }, { panda_rounded::BASE_PARAMETER_COUNT }>(
            "panda_rounded",
        ),
        check::<Ur5, 6, { ur5::PARAMETER_COUNT }, { ur5::BASE_PARAMETER_COUNT }>("ur5"),
    ];
    // Turning the fused form off takes effect only where it is chosen at run time, and there
    // (on a processor with FMA) the two forms must round differently somewhere.
    let chooses_at_run_time = !set_fused_multiply_adds(false);
    set_fused_multiply_adds(true);
    // Where the lanes can be 512 bits wide and that is chosen at run time, both widths ran.
    if chooses_at_run_time && avx512_lanes() {
        assert!(!set_avx512_lanes(false), "the 512-bit lanes do not turn off");
        set_avx512_lanes(true);
    }
    if chooses_at_run_time && fused_multiply_adds() {
        for (robot, d) in ["arm7", "arm7_friction", "panda", "panda_rounded", "ur5"]
            .iter()
            .zip(differing)
        {
            assert!(
                d > 100,
                "{robot}: only {d} outputs differ between the fused and unfused forms"
            );
        }
    } else {
        assert_eq!(differing, [0; 5], "one form only, yet results differ");
    }
}
