//! The lane forms (`*_lanes`, several states per call) equal the scalar functions lane by lane,
//! for 4- and 8-lane types, including a final batch shorter than the lane count: `τ` bit for
//! bit (the same statements), the base regressor to rounding (the scalar function computes its
//! columns four rows at a time, the lane form by the scalar recursion).

use dyngen_generated::{arm7, panda, panda_rounded, ur5, Arm7, Panda, PandaRounded, Ur5};
use dyngen_runtime::nalgebra::SVector;
use dyngen_runtime::{
    f64x4, f64x8, pack, unpack, BaseParameters, JointTrig, JointTrigLanes, LaneDynamics, Lanes, SplitMix64,
};

/// 19 states: four full batches of four and a short one; two of eight and a short one.
const STATES: usize = 19;

fn states<const N: usize>(seed: u64) -> Vec<[SVector<f64, N>; 3]> {
    let mut rng = SplitMix64::new(seed);
    (0..STATES)
        .map(|_| [(-3.0, 3.0), (-2.0, 2.0), (-5.0, 5.0)].map(|r| SVector::from_fn(|_, _| rng.uniform(r))))
        .collect()
}

fn check<R, L, const N: usize, const P: usize, const B: usize>(robot: &str)
where
    R: BaseParameters<N, P, B> + LaneDynamics<N, B>,
    L: Lanes,
{
    let all = states::<N>(7);
    for (b, batch) in all.chunks(L::WIDTH).enumerate() {
        let [q, qd, qdd] = [0, 1, 2].map(|i| pack::<L, N>(&batch.iter().map(|s| s[i]).collect::<Vec<_>>()));
        let t = JointTrigLanes::new(&q);
        let tau = R::inverse_dynamics_lanes(&t, &qd, &qdd);
        let y_b = R::base_torque_regressor_lanes(&t, &qd, &qdd);
        for (k, [q, qd, qdd]) in batch.iter().enumerate() {
            let at = format!("{robot}, {} lanes, batch {b}, lane {k}", L::WIDTH);
            let scalar_t = JointTrig::new(q);
            assert_eq!(unpack(&t.sin, k).as_slice(), &scalar_t.sin, "{at}: sin");
            assert_eq!(unpack(&t.cos, k).as_slice(), &scalar_t.cos, "{at}: cos");
            assert_eq!(
                unpack(&tau, k),
                R::inverse_dynamics(&scalar_t, qd, qdd),
                "{at}: τ"
            );
            let scalar_y = R::base_torque_regressor(&scalar_t, qd, qdd);
            let scale = scalar_y.amax().max(1.0);
            for (c, column) in y_b.iter().enumerate() {
                let gap = (unpack(column, k) - scalar_y.column(c)).amax();
                assert!(gap <= 1e-13 * scale, "{at}: Y_b column {c}: {gap:e} off");
            }
        }
    }
}

#[test]
fn lanes_equal_scalar_functions() {
    // The lane functions run under the same choice of multiply-adds as the scalar ones (fused
    // where the processor has FMA, also in a build that does not target it), so they agree bit
    // for bit under either choice (the only test of this binary that changes it; a debug build
    // has the unfused form only).
    for fused in [true, false] {
        dyngen_runtime::__private::set_fused_multiply_adds(fused);
        check::<Arm7, f64x4, 7, { arm7::PARAMETER_COUNT }, { arm7::BASE_PARAMETER_COUNT }>("arm7");
        check::<Panda, f64x4, 7, { panda::PARAMETER_COUNT }, { panda::BASE_PARAMETER_COUNT }>("panda");
        check::<Panda, f64x8, 7, { panda::PARAMETER_COUNT }, { panda::BASE_PARAMETER_COUNT }>("panda");
        check::<
            PandaRounded,
            f64x4,
            7,
            { panda_rounded::PARAMETER_COUNT },
            { panda_rounded::BASE_PARAMETER_COUNT },
        >("panda_rounded");
        check::<
            PandaRounded,
            f64x8,
            7,
            { panda_rounded::PARAMETER_COUNT },
            { panda_rounded::BASE_PARAMETER_COUNT },
        >("panda_rounded");
        check::<Ur5, f64x4, 6, { ur5::PARAMETER_COUNT }, { ur5::BASE_PARAMETER_COUNT }>("ur5");
        check::<Ur5, f64x8, 6, { ur5::PARAMETER_COUNT }, { ur5::BASE_PARAMETER_COUNT }>("ur5");
    }
    dyngen_runtime::__private::set_fused_multiply_adds(true);
}

#[test]
fn padding_repeats_the_last_state() {
    let v = [SVector::<f64, 2>::from([1.0, 2.0]), SVector::from([3.0, 4.0])];
    let x: [f64x4; 2] = pack(&v);
    assert_eq!(x[0].as_array(), &[1.0, 3.0, 3.0, 3.0]);
    assert_eq!(x[1].as_array(), &[2.0, 4.0, 4.0, 4.0]);
    let empty: [f64x4; 2] = pack(&[]);
    assert_eq!(empty[1].as_array(), &[0.0; 4]);
}
