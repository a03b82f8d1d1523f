//! The `_into` forms, which write into a `ResultBuffer` kept between calls, against the
//! by-value functions: equal at every state whether the buffer last held the same function's
//! result (its structural zeros kept, the other entries stale), another function's, or another
//! robot's.

use dyngen_generated::solo12::{self, Solo12, NV};
use dyngen_generated::{Arm7, Arm7Friction, Panda, PandaRounded, Ur5, Xarm7, Xarm7Snapped};
use dyngen_runtime::nalgebra::{SMatrix, SVector};
use dyngen_runtime::{
    BaseParameters, BufferedResult, DynamicsDerivatives, FloatingBaseDynamics, FloatingBaseParameters,
    FloatingDynamicsDerivatives, FloatingForwardDynamics, FloatingRegressors, ForwardDynamics, JointTrig,
    Regressors, ResultBuffer, SplitMix64,
};
use std::fmt::Debug;

const STATES: usize = 25;

/// One buffer per function of a shape, each kept over every state (the buffer every function
/// of that shape writes in turn is passed to `check`).
struct Buffers<T: BufferedResult> {
    own: Vec<ResultBuffer<T>>,
}

impl<T: BufferedResult + PartialEq + Debug> Buffers<T> {
    fn new(functions: usize) -> Self {
        Buffers {
            own: (0..functions).map(|_| ResultBuffer::new()).collect(),
        }
    }

    /// Function `k` written into its own buffer and into `shared` equals its by-value result.
    fn check(
        &mut self,
        k: usize,
        shared: &mut ResultBuffer<T>,
        into: impl Fn(&mut ResultBuffer<T>),
        expected: T,
        what: &str,
    ) {
        into(&mut self.own[k]);
        assert_eq!(*self.own[k], expected, "{what}, its own buffer");
        into(shared);
        assert_eq!(**shared, expected, "{what}, a shared buffer");
    }
}

fn vector<const N: usize>(rng: &mut SplitMix64, bound: f64) -> SVector<f64, N> {
    SVector::from_fn(|_, _| rng.uniform((-bound, bound)))
}

/// Buffers shared by the fixed-base robots of the same shapes (7 joints, 70 parameters).
struct Shared<const N: usize, const P: usize, const B: usize> {
    joint: ResultBuffer<SMatrix<f64, N, N>>,
    regressor: ResultBuffer<SMatrix<f64, N, P>>,
    base: ResultBuffer<SMatrix<f64, N, B>>,
    pair: ResultBuffer<(SMatrix<f64, N, N>, SMatrix<f64, N, N>)>,
}

impl<const N: usize, const P: usize, const B: usize> Shared<N, P, B> {
    fn new() -> Self {
        Shared {
            joint: ResultBuffer::new(),
            regressor: ResultBuffer::new(),
            base: ResultBuffer::new(),
            pair: ResultBuffer::new(),
        }
    }
}

fn fixed<R, const N: usize, const P: usize, const B: usize>(robot: &str, shared: &mut Shared<N, P, B>)
where
    R: Regressors<N, P> + BaseParameters<N, P, B> + ForwardDynamics<N, P> + DynamicsDerivatives<N, P>,
{
    let mut rng = SplitMix64::new(N as u64 * 1000 + P as u64);
    let (mut joint, mut regressor, mut base, mut pair) =
        (Buffers::new(3), Buffers::new(2), Buffers::new(2), Buffers::new(2));
    for k in 0..STATES {
        let what = |f: &str| format!("{robot} state {k}: {f}");
        let t = JointTrig::new(&vector::<N>(&mut rng, 3.0));
        let [qd, v, a] = [2.0, 2.0, 5.0].map(|b| vector::<N>(&mut rng, b));
        joint.check(
            0,
            &mut shared.joint,
            |o| R::mass_matrix_into(&t, o),
            R::mass_matrix(&t),
            &what("D"),
        );
        joint.check(
            1,
            &mut shared.joint,
            |o| R::coriolis_matrix_into(&t, &qd, o),
            R::coriolis_matrix(&t, &qd),
            &what("C"),
        );
        joint.check(
            2,
            &mut shared.joint,
            |o| R::mass_matrix_inverse_into(&t, o),
            R::mass_matrix_inverse(&t),
            &what("D⁻¹"),
        );
        regressor.check(
            0,
            &mut shared.regressor,
            |o| R::regressor_into(&t, &qd, &v, &a, o),
            R::regressor(&t, &qd, &v, &a),
            &what("Y"),
        );
        regressor.check(
            1,
            &mut shared.regressor,
            |o| R::torque_regressor_into(&t, &qd, &a, o),
            R::torque_regressor(&t, &qd, &a),
            &what("torque-form Y"),
        );
        base.check(
            0,
            &mut shared.base,
            |o| R::base_regressor_into(&t, &qd, &v, &a, o),
            R::base_regressor(&t, &qd, &v, &a),
            &what("Y_b"),
        );
        base.check(
            1,
            &mut shared.base,
            |o| R::base_torque_regressor_into(&t, &qd, &a, o),
            R::base_torque_regressor(&t, &qd, &a),
            &what("torque-form Y_b"),
        );
        pair.check(
            0,
            &mut shared.pair,
            |o| R::inverse_dynamics_derivatives_into(&t, &qd, &a, o),
            R::inverse_dynamics_derivatives(&t, &qd, &a),
            &what("∂τ/∂x"),
        );
        pair.check(
            1,
            &mut shared.pair,
            |o| R::forward_dynamics_derivatives_into(&t, &qd, &v, o),
            R::forward_dynamics_derivatives(&t, &qd, &v),
            &what("∂q̈/∂x"),
        );
    }
}

/// The 7-joint arms write the same shared buffers in turn, so each finds another robot's
/// result there (another pattern of structural zeros, or the same one).
#[test]
fn fixed_base_into_forms_equal_the_by_value_functions() {
    let mut seven = Shared::<7, 70, 43>::new();
    fixed::<Arm7, 7, 70, 43>("arm7", &mut seven);
    fixed::<Panda, 7, 70, 43>("panda", &mut seven);
    fixed::<PandaRounded, 7, 70, 43>("panda_rounded", &mut seven);
    fixed::<Xarm7, 7, 70, 43>("xarm7", &mut seven);
    fixed::<Xarm7Snapped, 7, 70, 43>("xarm7_snapped", &mut seven);
    fixed::<Arm7, 7, 70, 43>("arm7 again", &mut seven);
    fixed::<Ur5, 6, 60, 36>("ur5", &mut Shared::new());
    fixed::<Arm7Friction, 7, 98, 69>("arm7_friction", &mut Shared::new());
}

#[test]
fn floating_base_into_forms_equal_the_by_value_functions() {
    let mut rng = SplitMix64::new(18);
    let (mut joint, mut regressor, mut base, mut pair) =
        (Buffers::new(3), Buffers::new(2), Buffers::new(2), Buffers::new(2));
    let mut shared_joint = ResultBuffer::new();
    let mut shared_regressor = ResultBuffer::new();
    let mut shared_base = ResultBuffer::new();
    let mut shared_pair = ResultBuffer::new();
    for k in 0..STATES {
        let what = |f: &str| format!("solo12 state {k}: {f}");
        let mut q: Vec<f64> = (0..19).map(|_| rng.uniform((-3.0, 3.0))).collect();
        let norm = q[3..7].iter().map(|x| x * x).sum::<f64>().sqrt();
        q[3..7].iter_mut().for_each(|x| *x /= norm);
        let t = solo12::trig(&solo12::Configuration::from_column_slice(&q)).unwrap();
        let [v, vr, a] = [2.0, 2.0, 5.0].map(|b| vector::<NV>(&mut rng, b));
        joint.check(
            0,
            &mut shared_joint,
            |o| Solo12::mass_matrix_into(&t, o),
            Solo12::mass_matrix(&t),
            &what("D"),
        );
        joint.check(
            1,
            &mut shared_joint,
            |o| Solo12::coriolis_matrix_into(&t, &v, o),
            Solo12::coriolis_matrix(&t, &v),
            &what("C"),
        );
        joint.check(
            2,
            &mut shared_joint,
            |o| Solo12::mass_matrix_inverse_into(&t, o),
            Solo12::mass_matrix_inverse(&t),
            &what("D⁻¹"),
        );
        regressor.check(
            0,
            &mut shared_regressor,
            |o| Solo12::regressor_into(&t, &v, &vr, &a, o),
            Solo12::regressor(&t, &v, &vr, &a),
            &what("Y"),
        );
        regressor.check(
            1,
            &mut shared_regressor,
            |o| Solo12::torque_regressor_into(&t, &v, &a, o),
            Solo12::torque_regressor(&t, &v, &a),
            &what("torque-form Y"),
        );
        base.check(
            0,
            &mut shared_base,
            |o| Solo12::base_regressor_into(&t, &v, &vr, &a, o),
            Solo12::base_regressor(&t, &v, &vr, &a),
            &what("Y_b"),
        );
        base.check(
            1,
            &mut shared_base,
            |o| Solo12::base_torque_regressor_into(&t, &v, &a, o),
            Solo12::base_torque_regressor(&t, &v, &a),
            &what("torque-form Y_b"),
        );
        pair.check(
            0,
            &mut shared_pair,
            |o| Solo12::inverse_dynamics_derivatives_into(&t, &v, &a, o),
            Solo12::inverse_dynamics_derivatives(&t, &v, &a),
            &what("∂τ/∂x"),
        );
        pair.check(
            1,
            &mut shared_pair,
            |o| Solo12::forward_dynamics_derivatives_into(&t, &v, &vr, o),
            Solo12::forward_dynamics_derivatives(&t, &v, &vr),
            &what("∂ν̇/∂x"),
        );
    }
}

/// The regressor of a tree leaves most entries zero in every state: what makes its `_into`
/// form worth having. A buffer written once at a state and then at another holds exactly the
/// second state's result although the function wrote only part of it.
#[test]
fn a_kept_buffer_holds_only_the_last_state() {
    let mut rng = SplitMix64::new(5);
    let mut y = ResultBuffer::new();
    let mut states = Vec::new();
    for _ in 0..2 {
        let mut q: Vec<f64> = (0..19).map(|_| rng.uniform((-3.0, 3.0))).collect();
        let norm = q[3..7].iter().map(|x| x * x).sum::<f64>().sqrt();
        q[3..7].iter_mut().for_each(|x| *x /= norm);
        let t = solo12::trig(&solo12::Configuration::from_column_slice(&q)).unwrap();
        states.push((t, vector::<NV>(&mut rng, 2.0), vector::<NV>(&mut rng, 5.0)));
    }
    for (t, v, a) in &states {
        Solo12::torque_regressor_into(t, v, a, &mut y);
    }
    let (t, v, a) = &states[1];
    let expected = Solo12::torque_regressor(t, v, a);
    assert_eq!(*y, expected);
    let zeros = expected.iter().filter(|x| **x == 0.0).count();
    assert!(
        zeros > expected.len() / 3,
        "{zeros} of {} entries zero",
        expected.len()
    );
}
