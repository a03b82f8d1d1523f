//! Which inertial parameters a regressor multiplies: the standard ten per body, or the base
//! (identifiable) set. An adaptive controller is generic over this choice.

use crate::robot::{JointTrig, RobotDynamics};
use nalgebra::{SMatrix, SVector};
use std::marker::PhantomData;

/// A linear parameterisation `φ = Φ(θ)` of a robot's dynamics with `M` parameters, such that
/// `regressor(q, q̇, v, a) · Φ(θ) = D a + C v + g` for the standard parameters `θ` (`P` of them)
/// of any robot with the same kinematics.
pub trait Parameterization<const N: usize, const P: usize, const M: usize> {
    /// Names of the `M` parameters, e.g. `"m[link3]"`.
    const NAMES: [&'static str; M];
    /// `Φ(θ)`: the parameters this regressor multiplies, from the standard ones.
    fn from_standard(theta: &SVector<f64, P>) -> SVector<f64, M>;
    /// The regressor: `N × M`, linear in `v` and `a`.
    fn regressor(
        t: &JointTrig<N>,
        qd: &SVector<f64, N>,
        v: &SVector<f64, N>,
        a: &SVector<f64, N>,
    ) -> SMatrix<f64, N, M>;
}

/// The standard parameters: ten per body, `Φ = identity`.
pub struct Standard<R>(PhantomData<R>);

impl<R: RobotDynamics<N, P>, const N: usize, const P: usize> Parameterization<N, P, P> for Standard<R> {
    const NAMES: [&'static str; P] = R::PARAMETER_NAMES;
    fn from_standard(theta: &SVector<f64, P>) -> SVector<f64, P> {
        *theta
    }
    fn regressor(
        t: &JointTrig<N>,
        qd: &SVector<f64, N>,
        v: &SVector<f64, N>,
        a: &SVector<f64, N>,
    ) -> SMatrix<f64, N, P> {
        R::regressor(t, qd, v, a)
    }
}

/// A robot whose generator also emitted its base (minimal, identifiable) parameters: `B`
/// combinations of the standard ones that span every torque the robot can produce.
pub trait BaseParameters<const N: usize, const P: usize, const B: usize>: RobotDynamics<N, P> {
    /// Readable names that show what each base parameter combines, e.g. `"Izz[link1] + Iyy[link2] + …"`.
    const BASE_PARAMETER_NAMES: [&'static str; B];
    /// `θ_b = Φ θ`, a constant linear map fixed by the kinematics.
    fn base_parameters(theta: &SVector<f64, P>) -> SVector<f64, B>;
    /// `Y_b(q, q̇, v, a)` with `Y_b θ_b = Y θ = D a + C v + g`.
    fn base_regressor(
        t: &JointTrig<N>,
        qd: &SVector<f64, N>,
        v: &SVector<f64, N>,
        a: &SVector<f64, N>,
    ) -> SMatrix<f64, N, B>;
}

/// The base parameters of a robot that has them.
pub struct Base<R>(PhantomData<R>);

impl<R: BaseParameters<N, P, B>, const N: usize, const P: usize, const B: usize> Parameterization<N, P, B>
    for Base<R>
{
    const NAMES: [&'static str; B] = R::BASE_PARAMETER_NAMES;
    fn from_standard(theta: &SVector<f64, P>) -> SVector<f64, B> {
        R::base_parameters(theta)
    }
    fn regressor(
        t: &JointTrig<N>,
        qd: &SVector<f64, N>,
        v: &SVector<f64, N>,
        a: &SVector<f64, N>,
    ) -> SMatrix<f64, N, B> {
        R::base_regressor(t, qd, v, a)
    }
}

/// `D(q)` of the robot whose parameters (in `Z`'s coordinates) are `phi`, through the
/// regressor, exact by linearity: column `i` is `Y(q, 0, 0, eᵢ) φ − Y(q, 0, 0, 0) φ`. How the
/// simulator gets the true robot's inertia (payload included) and the controller its estimate,
/// neither of which the generated `mass_matrix` (the description's parameters) can give.
pub fn mass_matrix_through_regressor<Z, const N: usize, const P: usize, const M: usize>(
    t: &JointTrig<N>,
    phi: &SVector<f64, M>,
) -> SMatrix<f64, N, N>
where
    Z: Parameterization<N, P, M>,
{
    let z = SVector::<f64, N>::zeros();
    let gravity = Z::regressor(t, &z, &z, &z) * phi;
    let mut d = SMatrix::<f64, N, N>::zeros();
    for i in 0..N {
        let e = SVector::<f64, N>::from_fn(|k, _| f64::from(u8::from(k == i)));
        d.set_column(i, &(Z::regressor(t, &z, &z, &e) * phi - gravity));
    }
    d
}
