//! The compiled forward dynamics of every committed robot as accurate as the conditioning of `D`
//! allows: within `ACCURACY` units of what a backward-stable computation may lose
//! (`dyngen_testkit::reference_solve`) of the same problem solved in double-double precision,
//! fused and unfused multiply-adds alike.

use dyngen_codegen::description::load;
use dyngen_runtime::__private::set_fused_multiply_adds;
use dyngen_runtime::nalgebra::SVector;
use dyngen_runtime::{ForwardDynamics, JointTrig, SplitMix64};
use dyngen_testkit::reference_solve::error_in_stable_units;
use dyngen_testkit::workspace_root;

const ACCURACY: f64 = 10.0;

fn check<R: ForwardDynamics<N, P>, const N: usize, const P: usize>(robot: &str) {
    let model = load(&workspace_root().join(format!("robots/{robot}.yaml")))
        .unwrap_or_else(|e| panic!("{e}"))
        .model;
    let theta = model.parameters();
    let mut rng = SplitMix64::new(17);
    let mut worst: f64 = 0.0;
    for _ in 0..50 {
        let mut vector = |r: f64| -> SVector<f64, N> { SVector::from_fn(|_, _| rng.uniform((-r, r))) };
        let (q, qd, tau) = (vector(2.5), vector(1.5), vector(20.0));
        for fused in [true, false] {
            set_fused_multiply_adds(fused);
            let got = R::forward_dynamics(&JointTrig::new(&q), &qd, &tau);
            set_fused_multiply_adds(true);
            let ratio = error_in_stable_units(
                got.as_slice(),
                &model,
                &theta,
                q.as_slice(),
                qd.as_slice(),
                tau.as_slice(),
            );
            assert!(
                ratio <= ACCURACY,
                "{robot} (fused {fused}): {ratio:.1} units at q = {q:?}"
            );
            worst = worst.max(ratio);
        }
    }
    println!("{robot}: worst {worst:.3} units");
}

#[test]
fn committed_robots() {
    check::<dyngen_generated::Arm7, 7, 70>("arm7");
    check::<dyngen_generated::arm7_friction::Arm7Friction, 7, 98>("arm7_friction");
    check::<dyngen_generated::Panda, 7, 70>("panda");
    check::<dyngen_generated::PandaRounded, 7, 70>("panda_rounded");
    check::<dyngen_generated::Ur5, 6, 60>("ur5");
}
