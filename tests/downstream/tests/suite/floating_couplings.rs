//! Floating bases with mimic joints (`codegen/tests/data/mimic/floating_gripper.yaml`: a finger
//! mimics the other with multiplier −1, a tail the elbow) and with joint-level terms
//! (`codegen/tests/data/floating/hopper_friction.yaml`: armature, viscous and smoothed Coulomb
//! friction, offsets), generated and compiled by this crate's build script, against the generic
//! floating-base dynamics with the parameters the code was generated with (the base parameters'
//! representative ones), every function to 1e-12 at random states; and the composed forms of
//! forward dynamics, `D⁻¹` and their derivatives over each robot's own functions.

use dyngen_codegen::base_parameters::BaseParameterSet;
use dyngen_codegen::description::load;
use dyngen_codegen::dynamics::{FloatingDynamics, FloatingState};
use dyngen_codegen::internals::dynamics::velocity_parents;
use dyngen_codegen::model::Model;
use dyngen_downstream_example::{floating_gripper, hopper_friction};
use dyngen_runtime::__private::{composed, tree_factor::Tree};
use dyngen_runtime::nalgebra::{DMatrix, SVector};
use dyngen_runtime::prelude::*;
use dyngen_runtime::{FloatingTrig, RobotFrame, SplitMix64};
use std::path::Path;

fn assert_close(what: &str, generated: &[f64], generic: &[f64]) {
    super::mimic_joints::assert_within(what, generated, generic, 1e-12);
}

fn model(description: &str) -> Model {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../codegen/tests/data")
        .join(description);
    load(&path).unwrap_or_else(|e| panic!("{e}")).model
}

/// A random state: configuration (unit quaternion), velocity, acceleration, reference ones.
fn state<const NQ: usize, const NV: usize>(rng: &mut SplitMix64) -> (Vec<f64>, [SVector<f64, NV>; 4]) {
    let mut q: Vec<f64> = (0..NQ).map(|_| rng.uniform((-1.0, 1.0))).collect();
    let norm = q[3..7].iter().map(|x| x * x).sum::<f64>().sqrt();
    q[3..7].iter_mut().for_each(|x| *x /= norm);
    let mut draw = |r: f64| SVector::<f64, NV>::from_fn(|_, _| rng.uniform((-r, r)));
    let rates = [draw(2.0), draw(5.0), draw(2.0), draw(5.0)];
    (q, rates)
}

/// The composed forms of forward dynamics, `D⁻¹` and `∂ν̇/∂x` (`code_shape: composed`) run over
/// `R`'s own `D`, `τ` and `∂τ/∂x` (mimic coordinates, joint-level terms), against its
/// straight-line functions at one state.
fn compare_composed<R, const N: usize, const NV: usize, const P: usize>(
    model: &Model,
    t: &FloatingTrig<N>,
    v: &SVector<f64, NV>,
    tau: &SVector<f64, NV>,
) where
    R: FloatingForwardDynamics<N, NV, P> + FloatingDynamicsDerivatives<N, NV, P>,
{
    let parents: [Option<usize>; NV] = velocity_parents(model).try_into().expect("NV coordinates");
    let tree = Tree::new(parents);
    let free_force = tau - R::inverse_dynamics(t, v, &SVector::zeros());
    let d = R::mass_matrix(t);
    assert_close(
        "composed ν̇",
        composed::forward_dynamics(&tree, d, free_force).as_slice(),
        R::forward_dynamics(t, v, tau).as_slice(),
    );
    assert_close(
        "composed D⁻¹",
        composed::mass_matrix_inverse(&tree, d).as_slice(),
        R::mass_matrix_inverse(t).as_slice(),
    );
    let (dq, dv) = composed::forward_dynamics_derivatives(&tree, d, free_force, |a| {
        R::inverse_dynamics_derivatives(t, v, a)
    });
    let (flat_q, flat_v) = R::forward_dynamics_derivatives(t, v, tau);
    assert_close("composed ∂ν̇/∂q", dq.as_slice(), flat_q.as_slice());
    assert_close("composed ∂ν̇/∂ν", dv.as_slice(), flat_v.as_slice());
}

/// What a generated floating robot computes, compared with the generic dynamics at one state.
fn compare<R, const N: usize, const NV: usize, const P: usize, const B: usize>(
    generic: &FloatingDynamics,
    s: &FloatingState,
    t: &FloatingTrig<N>,
    [v, a, vr, ar]: &[SVector<f64, NV>; 4],
) where
    R: FloatingRegressors<N, NV, P>
        + FloatingForwardDynamics<N, NV, P>
        + FloatingBaseParameters<N, NV, P, B>
        + FloatingDynamicsDerivatives<N, NV, P>
        + FloatingFrameKinematics<N, NV>,
{
    let (vs, as_, vrs, ars) = (v.as_slice(), a.as_slice(), vr.as_slice(), ar.as_slice());
    let tau = generic.inverse_dynamics(s, vs, as_);
    let tau_v = SVector::<f64, NV>::from_column_slice(tau.as_slice());
    assert_close(
        "D",
        R::mass_matrix(t).as_slice(),
        generic.mass_matrix(s).as_slice(),
    );
    assert_close(
        "C",
        R::coriolis_matrix(t, v).as_slice(),
        generic.coriolis_matrix(s, vs).as_slice(),
    );
    assert_close("g", R::gravity(t).as_slice(), generic.gravity(s).as_slice());
    assert_close("τ", R::inverse_dynamics(t, v, a).as_slice(), tau.as_slice());
    assert_close(
        "Slotine–Li",
        R::slotine_li(t, v, vr, ar).as_slice(),
        generic.slotine_li(s, vs, vrs, ars).as_slice(),
    );
    let y: DMatrix<f64> = generic.regressor(s, vs, vrs, ars);
    assert_close("Y", R::regressor(t, v, vr, ar).as_slice(), y.as_slice());
    let theta = SVector::<f64, P>::from_column_slice(&generic.parameters());
    assert_close(
        "Y_b θ_b",
        (R::base_regressor(t, v, vr, ar) * R::base_parameters(&theta)).as_slice(),
        (y * DMatrix::from_column_slice(P, 1, theta.as_slice())).as_slice(),
    );
    assert_close(
        "FD",
        R::forward_dynamics(t, v, &tau_v).as_slice(),
        generic.forward_dynamics(s, vs, tau.as_slice()).as_slice(),
    );
    assert_close(
        "D⁻¹",
        R::mass_matrix_inverse(t).as_slice(),
        generic.mass_matrix_inverse(s).as_slice(),
    );
    let (dq, dv) = R::inverse_dynamics_derivatives(t, v, a);
    let (gdq, gdv) = generic.inverse_dynamics_derivatives(s, vs, as_);
    assert_close("∂τ/∂q", dq.as_slice(), gdq.as_slice());
    assert_close("∂τ/∂ν", dv.as_slice(), gdv.as_slice());
    let (dq, dv) = R::forward_dynamics_derivatives(t, v, &tau_v);
    let (gdq, gdv) = generic.forward_dynamics_derivatives(s, vs, tau.as_slice());
    assert_close("∂ν̇/∂q", dq.as_slice(), gdq.as_slice());
    assert_close("∂ν̇/∂ν", dv.as_slice(), gdv.as_slice());
    assert_close(
        "A_g",
        R::centroidal_momentum_matrix(t).as_slice(),
        generic.centroidal_momentum_matrix(s).2.as_slice(),
    );
    let lwa = ReferenceFrame::LocalWorldAligned;
    for (k, &frame) in R::Frame::ALL.iter().enumerate() {
        assert_close(
            "J",
            R::frame_jacobian(frame, lwa, t).as_slice(),
            generic.frame_jacobian(s, k, lwa).as_slice(),
        );
        assert_close(
            "J̇",
            R::frame_jacobian_time_variation(frame, lwa, t, v).as_slice(),
            generic.frame_jacobian_time_variation(s, vs, k, lwa).as_slice(),
        );
    }
}

/// The generic dynamics of the parameters the code was generated with.
fn generated_with(model: &Model) -> FloatingDynamics<'_> {
    let description = FloatingDynamics::new(model)
        .expect("a floating base")
        .parameters();
    let representative = BaseParameterSet::compute(model).representative(&description);
    FloatingDynamics::with_parameters(model, &representative).expect("a floating base")
}

#[test]
fn a_floating_gripper_with_mimic_joints_matches_the_generic_dynamics() {
    use floating_gripper::{FloatingGripper, BASE_PARAMETER_COUNT as B, DOF, NQ, NV, PARAMETER_COUNT as P};
    let model = model("mimic/floating_gripper.yaml");
    assert_eq!(
        (DOF, NQ, NV),
        (4, 11, 10),
        "the coordinates, not the tree's six joints"
    );
    assert_eq!(
        P, 70,
        "ten for the base body, ten per body, mimic joints' bodies included"
    );
    assert_eq!(floating_gripper::JOINT_NAMES.len(), DOF);
    let generic = generated_with(&model);
    let mut rng = SplitMix64::new(17);
    for _ in 0..20 {
        let (q, rates) = state::<NQ, NV>(&mut rng);
        let t = floating_gripper::trig(&floating_gripper::Configuration::from_column_slice(&q)).unwrap();
        compare::<FloatingGripper, DOF, NV, P, B>(&generic, &generic.state(&q).unwrap(), &t, &rates);
        compare_composed::<FloatingGripper, DOF, NV, P>(&model, &t, &rates[0], &rates[1]);
    }
}

#[test]
fn a_floating_hopper_with_joint_friction_matches_the_generic_dynamics() {
    use hopper_friction::{HopperFriction, BASE_PARAMETER_COUNT as B, DOF, NQ, NV, PARAMETER_COUNT as P};
    let model = model("floating/hopper_friction.yaml");
    assert_eq!(
        P,
        10 + 20 + 8,
        "the base body's ten, ten per body, four per joint"
    );
    assert_eq!(
        &hopper_friction::PARAMETER_NAMES[30..32],
        &["Ia[hip]", "fv[hip]"],
        "the joint-level parameters after the inertial ones, named as on a fixed base"
    );
    assert_eq!(
        HopperFriction::parameters().as_slice(),
        FloatingDynamics::new(&model).unwrap().parameters().as_slice()
    );
    let generic = generated_with(&model);
    let mut rng = SplitMix64::new(19);
    for _ in 0..20 {
        let (q, rates) = state::<NQ, NV>(&mut rng);
        let t = hopper_friction::trig(&hopper_friction::Configuration::from_column_slice(&q)).unwrap();
        compare::<HopperFriction, DOF, NV, P, B>(&generic, &generic.state(&q).unwrap(), &t, &rates);
        compare_composed::<HopperFriction, DOF, NV, P>(&model, &t, &rates[0], &rates[1]);
    }
}
