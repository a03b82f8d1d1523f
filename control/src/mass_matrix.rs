//! `D(q)` of a robot with other parameters than its description's, through the regressor.

use dyngen_runtime::{JointTrig, Parameterization};
use nalgebra::{SMatrix, SVector};

/// `D(q)` of the robot whose parameters (in `Z`'s coordinates) are `phi`, through the
/// regressor, exact by linearity: column `i` is `Y(q, 0, 0, eᵢ) φ − Y(q, 0, 0, 0) φ`. How the
/// simulator gets the true robot's mass matrix (payload included) and the controller its estimate,
/// neither of which the generated `mass_matrix` (the description's parameters) can give.
pub fn mass_matrix_through_regressor<Z, const N: usize, const M: usize>(
    t: &JointTrig<N>,
    phi: &SVector<f64, M>,
) -> SMatrix<f64, N, N>
where
    Z: Parameterization<N, M>,
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
