//! The operational space of a generated robot's end-effector (`dyngen_runtime::operational_space`
//! over the generated `J` and `D⁻¹`) against `(J M⁻¹ Jᵀ)⁻¹` computed here from Pinocchio's own
//! `J` and `M` (`codegen/tests/fixtures/`), for all six rows and for the position rows alone;
//! and the robust forms at a stretched-out arm, where the exact one is refused.

use dyngen_testkit as common;

use common::{assert_close, fixture};
use dyngen_generated::{Panda, Ur5};
use dyngen_runtime::nalgebra::{DMatrix, SMatrix, SVector};
use dyngen_runtime::{
    operational_space, ForwardDynamics, Inversion, JointTrig, Kinematics, OperationalSpaceError,
};

/// Λ is `K⁻¹`: the conditioning of `K` (up to 1e4 on these states) costs digits.
const TOL: f64 = 1e-8;

fn dm<const R: usize, const C: usize>(m: &SMatrix<f64, R, C>) -> DMatrix<f64> {
    DMatrix::from_column_slice(R, C, m.as_slice())
}

fn against_pinocchio<R: ForwardDynamics<N, P>, const N: usize, const P: usize>(robot: &str) {
    let fx = fixture::load(robot);
    for (k, s) in fx.states.iter().enumerate() {
        let at = |what: &str| format!("{robot} state {k}: {what}");
        let t = JointTrig::new(&SVector::<f64, N>::from_column_slice(&s.q));
        let (j, m_inv) = (R::jacobian(&t), R::mass_matrix_inverse(&t));
        let theirs_m_inv = s.d.clone().try_inverse().expect("M invertible");
        for rows in [6, 3] {
            let theirs_j = s.j.rows(0, rows).into_owned();
            let expected = (&theirs_j * &theirs_m_inv * theirs_j.transpose())
                .try_inverse()
                .unwrap();
            let ours = match rows {
                6 => dm(&operational_space(&j, &m_inv, Inversion::Exact).unwrap().inertia),
                _ => {
                    let position = j.fixed_rows::<3>(0).into_owned();
                    let os = operational_space(&position, &m_inv, Inversion::Exact).unwrap();
                    // `J J̄ = I` with Pinocchio's `J`.
                    let identity = &theirs_j * dm(&os.consistent_inverse);
                    assert_close(&at("J J̄"), &identity, &DMatrix::identity(3, 3), TOL);
                    dm(&os.inertia)
                }
            };
            assert_close(&at(&format!("Λ of {rows} rows")), &ours, &expected, TOL);
        }
    }
}

#[test]
fn panda_operational_space_matches_pinocchio() {
    against_pinocchio::<Panda, 7, 70>("panda");
}

#[test]
fn ur5_operational_space_matches_pinocchio() {
    against_pinocchio::<Ur5, 6, 60>("ur5");
}

/// The UR5 with its elbow straight: `J` loses a rank, the exact `Λ` is refused, the condition
/// limit bounds `Λ`'s condition number and damping keeps it finite.
#[test]
fn at_a_singularity_the_robust_forms_stay_bounded() {
    let q = SVector::<f64, 6>::from([0.3, -0.8, 0.0, -0.4, 1.1, 0.2]);
    let t = JointTrig::new(&q);
    let (j, m_inv) = (Ur5::jacobian(&t), Ur5::mass_matrix_inverse(&t));
    assert_eq!(
        operational_space(&j, &m_inv, Inversion::Exact).unwrap_err(),
        OperationalSpaceError::Singular
    );
    let kappa = 1e5;
    let limited = operational_space(&j, &m_inv, Inversion::ConditionLimited(kappa)).unwrap();
    let eigen = limited.inertia.symmetric_eigenvalues();
    assert!(eigen.amax() / eigen.amin() <= kappa * (1.0 + 1e-9), "{eigen}");
    let damped = operational_space(&j, &m_inv, Inversion::Damped(1e-4)).unwrap();
    assert!(damped.inertia.iter().all(|x| x.is_finite()));
}
