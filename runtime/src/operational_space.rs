//! The operational-space quantities of any rows `J` (a frame's Jacobian, its position rows, a
//! stack of task rows) from `M⁻¹`: the inertia `Λ = (J M⁻¹ Jᵀ)⁻¹` the task feels, `J M⁻¹`, and
//! the dynamically consistent generalised inverse `J̄ = M⁻¹ Jᵀ Λ`. A generated robot gives `J`
//! (`frame_jacobian`), `M⁻¹` (`mass_matrix_inverse`) and the rows' drift `J̇ q̇`
//! (`frame_classical_acceleration` at `q̈ = 0`); this assembles the rest without allocating.
//!
//! `K = J M⁻¹ Jᵀ` loses rank where `J` does (an arm stretched out, a wrist aligned), and `Λ`
//! then grows without bound along the lost directions. [`Inversion`] chooses how `K` is
//! inverted: exactly (refused near a singularity), damped (`(K + ε I)⁻¹`, which changes `Λ`
//! everywhere by a little) or with its condition number limited (`K`'s eigenvalues raised to at
//! least `λ_max / κ`, which leaves `Λ` as it is away from singularities and bounds it near them).

use nalgebra::allocator::Allocator;
use nalgebra::{Cholesky, DefaultAllocator, Dim, DimDiff, DimSub, OMatrix, SymmetricEigen, U1};

/// How `K = J M⁻¹ Jᵀ` is inverted into `Λ`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Inversion {
    /// `K⁻¹`, refused when `K` is singular to rounding (a pivot below `1e-12` of the largest
    /// diagonal entry).
    Exact,
    /// `(K + ε I)⁻¹`, `ε > 0` in `K`'s units (1/kg for position rows).
    Damped(f64),
    /// `K`'s eigenvalues below `λ_max / κ` raised to it before inverting, `κ ≥ 1`: `Λ`'s
    /// condition number is at most `κ`, and where `K` is better conditioned `Λ = K⁻¹` exactly.
    ConditionLimited(f64),
}

/// What [`operational_space`] returns for rows `J` (`R` rows, `NV` velocity coordinates).
#[derive(Clone, Debug, PartialEq)]
pub struct OperationalSpace<NV: Dim, R: Dim>
where
    DefaultAllocator: Allocator<R, R> + Allocator<R, NV> + Allocator<NV, R>,
{
    /// `Λ` (R × R), symmetric.
    pub inertia: OMatrix<f64, R, R>,
    /// `J M⁻¹` (R × NV): a task force's effect `J M⁻¹ Jᵀ F` is `K F`.
    pub jacobian_mass_inverse: OMatrix<f64, R, NV>,
    /// `J̄ = M⁻¹ Jᵀ Λ` (NV × R): the generalised inverse of `J` consistent with the dynamics,
    /// whose null-space projector `I − J̄ J` leaves the task's acceleration untouched.
    pub consistent_inverse: OMatrix<f64, NV, R>,
}

/// Why the operational-space quantities were not computed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum OperationalSpaceError {
    /// `J` or `M⁻¹` holds a value that is not finite.
    NotFinite,
    /// The inversion's parameter is not allowed (`ε ≤ 0`, `κ < 1`, or not finite).
    Parameter,
    /// `K` is singular to rounding and the inversion is [`Inversion::Exact`].
    Singular,
}

impl core::fmt::Display for OperationalSpaceError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            OperationalSpaceError::NotFinite => write!(f, "J or M⁻¹ holds a value that is not finite"),
            OperationalSpaceError::Parameter => {
                write!(f, "the damping must be positive and the condition limit at least 1")
            }
            OperationalSpaceError::Singular => write!(
                f,
                "J M⁻¹ Jᵀ is singular (a singular configuration, or redundant rows): invert it damped or with a condition limit"
            ),
        }
    }
}

/// `Λ`, `J M⁻¹` and `J̄` of the rows `jacobian` with `mass_inverse` `M⁻¹`, `K` inverted as
/// `inversion` says.
pub fn operational_space<NV: Dim, R: Dim + DimSub<U1>>(
    jacobian: &OMatrix<f64, R, NV>,
    mass_inverse: &OMatrix<f64, NV, NV>,
    inversion: Inversion,
) -> Result<OperationalSpace<NV, R>, OperationalSpaceError>
where
    DefaultAllocator: Allocator<R, R>
        + Allocator<R, NV>
        + Allocator<NV, R>
        + Allocator<NV, NV>
        + Allocator<R>
        + Allocator<DimDiff<R, U1>>,
{
    if !(jacobian.iter().all(|x| x.is_finite()) && mass_inverse.iter().all(|x| x.is_finite())) {
        return Err(OperationalSpaceError::NotFinite);
    }
    let jacobian_mass_inverse = jacobian * mass_inverse;
    let mut k = &jacobian_mass_inverse * jacobian.transpose();
    // `M⁻¹` is symmetric; rounding in the products is not, and the eigensolver wants symmetry.
    k = (&k + k.transpose()) * 0.5;
    let inertia = match inversion {
        Inversion::Exact => exact_inverse(k)?,
        Inversion::Damped(epsilon) => {
            if !(epsilon > 0.0 && epsilon.is_finite()) {
                return Err(OperationalSpaceError::Parameter);
            }
            for i in 0..k.nrows() {
                k[(i, i)] += epsilon;
            }
            exact_inverse(k)?
        }
        Inversion::ConditionLimited(kappa) => {
            if !(kappa >= 1.0 && kappa.is_finite()) {
                return Err(OperationalSpaceError::Parameter);
            }
            let eigen = SymmetricEigen::new(k);
            let largest = eigen.eigenvalues.amax();
            if largest <= 0.0 {
                return Err(OperationalSpaceError::Singular);
            }
            let floor = largest / kappa;
            let inverted = eigen.eigenvalues.map(|l| 1.0 / l.max(floor));
            let u = &eigen.eigenvectors;
            u * OMatrix::from_diagonal(&inverted) * u.transpose()
        }
    };
    let consistent_inverse = jacobian_mass_inverse.transpose() * &inertia;
    Ok(OperationalSpace {
        inertia,
        jacobian_mass_inverse,
        consistent_inverse,
    })
}

/// `k⁻¹` by Cholesky, refused when a pivot is at rounding level against the largest diagonal
/// entry.
fn exact_inverse<R: Dim>(k: OMatrix<f64, R, R>) -> Result<OMatrix<f64, R, R>, OperationalSpaceError>
where
    DefaultAllocator: Allocator<R, R>,
{
    let largest = (0..k.nrows()).fold(0.0_f64, |m, i| m.max(k[(i, i)].abs()));
    let cholesky = Cholesky::new(k).ok_or(OperationalSpaceError::Singular)?;
    let l = cholesky.l_dirty();
    if (0..l.nrows()).any(|i| l[(i, i)] * l[(i, i)] <= 1e-12 * largest) {
        return Err(OperationalSpaceError::Singular);
    }
    Ok(cholesky.inverse())
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Matrix3, SMatrix};

    /// A planar two-link arm's position rows and a diagonal `M⁻¹` standing in for its own:
    /// `J` loses rank as the elbow straightens.
    fn two_link(elbow: f64) -> (SMatrix<f64, 2, 2>, SMatrix<f64, 2, 2>) {
        let (l1, l2, shoulder) = (0.5, 0.4, 0.3_f64);
        let (s1, c1) = (shoulder.sin(), shoulder.cos());
        let (s12, c12) = ((shoulder + elbow).sin(), (shoulder + elbow).cos());
        let j = SMatrix::<f64, 2, 2>::new(-l1 * s1 - l2 * s12, -l2 * s12, l1 * c1 + l2 * c12, l2 * c12);
        let m = SMatrix::<f64, 2, 2>::new(2.0, 0.4, 0.4, 0.8);
        (j, m.try_inverse().unwrap())
    }

    #[test]
    fn exact_is_the_inverse_and_the_generalised_inverse_is_consistent() {
        let (j, m_inv) = two_link(1.2);
        let os = operational_space(&j, &m_inv, Inversion::Exact).unwrap();
        let k = j * m_inv * j.transpose();
        assert!((os.inertia * k - SMatrix::<f64, 2, 2>::identity()).amax() < 1e-12);
        // `J J̄ = I`, and `J̄` is `M`-weighted: `M J̄ = Jᵀ Λ`.
        assert!((j * os.consistent_inverse - SMatrix::<f64, 2, 2>::identity()).amax() < 1e-12);
        let m = m_inv.try_inverse().unwrap();
        assert!((m * os.consistent_inverse - j.transpose() * os.inertia).amax() < 1e-12);
    }

    #[test]
    fn near_a_singularity_exact_is_refused_and_the_robust_forms_stay_bounded() {
        let (j, m_inv) = two_link(1e-9);
        assert_eq!(
            operational_space(&j, &m_inv, Inversion::Exact).unwrap_err(),
            OperationalSpaceError::Singular
        );
        let kappa = 1e4;
        let limited = operational_space(&j, &m_inv, Inversion::ConditionLimited(kappa)).unwrap();
        let eigen = SymmetricEigen::new(limited.inertia).eigenvalues;
        let condition = eigen.amax() / eigen.amin();
        assert!(condition <= kappa * (1.0 + 1e-9), "condition {condition}");
        let damped = operational_space(&j, &m_inv, Inversion::Damped(1e-3)).unwrap();
        assert!(damped.inertia.iter().all(|x| x.is_finite()) && damped.inertia.amax() < 1e4);
    }

    #[test]
    fn away_from_singularities_the_condition_limit_changes_nothing_and_damping_vanishes() {
        let (j, m_inv) = two_link(1.2);
        let exact = operational_space(&j, &m_inv, Inversion::Exact).unwrap().inertia;
        let limited = operational_space(&j, &m_inv, Inversion::ConditionLimited(1e6))
            .unwrap()
            .inertia;
        assert!((limited - exact).amax() < 1e-10 * exact.amax());
        let damped = |e| {
            operational_space(&j, &m_inv, Inversion::Damped(e))
                .unwrap()
                .inertia
        };
        let (far, near) = ((damped(1e-3) - exact).amax(), (damped(1e-6) - exact).amax());
        assert!(near < far * 1e-2, "damping 1e-3: {far}, 1e-6: {near}");
    }

    #[test]
    fn bad_input_is_refused_with_a_reason() {
        let (j, m_inv) = two_link(1.2);
        let mut bad = j;
        bad[(0, 0)] = f64::NAN;
        let e = operational_space(&bad, &m_inv, Inversion::Exact).unwrap_err();
        assert_eq!(e, OperationalSpaceError::NotFinite);
        for inversion in [
            Inversion::Damped(0.0),
            Inversion::Damped(f64::INFINITY),
            Inversion::ConditionLimited(0.5),
        ] {
            let e = operational_space(&j, &m_inv, inversion).unwrap_err();
            assert_eq!(e, OperationalSpaceError::Parameter, "{inversion:?}");
        }
        // Three rows of a planar arm's two coordinates: redundant whatever the pose.
        let rows = Matrix3::<f64>::identity().fixed_view::<3, 2>(0, 0).into_owned();
        let e = operational_space(&rows, &m_inv, Inversion::Exact).unwrap_err();
        assert_eq!(e, OperationalSpaceError::Singular);
        assert!(e.to_string().contains("condition limit"));
    }
}
