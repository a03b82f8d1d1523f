//! The contact task: task-frame rotation `R`, contact stiffness rows `K` and their split into the
//! force-controlled directions `K⁺ = Kᵀ(KKᵀ)⁻¹` and the position-controlled ones `K⁻ = I − K⁺K`.

use super::error::ConfigError;
use nalgebra::{Cholesky, Matrix3, SMatrix, Vector3};

/// The environment as the controller models it (the note's eqs. 5–8), task dimension m = 3
/// (end-effector position).
///
/// - `rotation` `R`: task frame from base frame, `x_t = R x` (a rotation, so `R⁻¹ = Rᵀ`).
/// - `stiffness` `K` (S×3, full row rank): `F_t = K (x_t − x_e)` are the controlled force
///   components, positive when pressing for the plane (`K = [0, 0, −k]`).
/// - `force_selection` `Σ` (S×3): how the measured force on the environment `F̄` (base frame)
///   gives the same components, `F_t = Σ R F̄` (for the plane `Σ = [0, 0, −1]`).
/// - `contact_point` `x_e` (task frame): the undeformed surface point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactTask<const S: usize> {
    pub rotation: Matrix3<f64>,
    pub stiffness: SMatrix<f64, S, 3>,
    pub force_selection: SMatrix<f64, S, 3>,
    pub contact_point: Vector3<f64>,
}

impl ContactTask<1> {
    /// A plane through `point` with upward unit normal `normal` (base frame) and stiffness `k`:
    /// the task frame's z axis is the normal, `K = [0, 0, −k]`, `Σ = [0, 0, −1]`.
    pub fn plane(point: Vector3<f64>, normal: Vector3<f64>, k: f64) -> Result<Self, ConfigError> {
        let n = normal.try_normalize(1e-12).ok_or_else(|| ConfigError::Invalid {
            name: "plane normal",
            detail: "the normal is zero".into(),
        })?;
        // Rotation taking n to e_z (Rodrigues), so that x_t = R x has its z along n.
        let rotation = nalgebra::Rotation3::rotation_between(&n, &Vector3::z())
            .unwrap_or_else(|| nalgebra::Rotation3::from_axis_angle(&Vector3::x_axis(), std::f64::consts::PI))
            .into_inner();
        Ok(ContactTask {
            rotation,
            stiffness: SMatrix::<f64, 1, 3>::new(0.0, 0.0, -k),
            force_selection: SMatrix::<f64, 1, 3>::new(0.0, 0.0, -1.0),
            contact_point: rotation * point,
        })
    }
}

impl<const S: usize> ContactTask<S> {
    /// Checks `R` is a rotation and `K` has full row rank; returns the split.
    pub fn validate(&self) -> Result<Split<S>, ConfigError> {
        let r = &self.rotation;
        let ortho = (r.transpose() * r - Matrix3::identity()).amax();
        if !ortho.is_finite() || ortho > 1e-9 || r.determinant() < 0.0 {
            return Err(ConfigError::Invalid {
                name: "task rotation R",
                detail: format!("not a proper rotation (‖RᵀR − I‖ = {ortho:.1e})"),
            });
        }
        if S > 3 {
            return Err(ConfigError::StiffnessRankDeficient {
                rows: S,
                sigma_min: 0.0,
                threshold: Split::<S>::RANK_TOLERANCE,
            });
        }
        Split::new(&self.stiffness)
    }
}

/// `K`, `K⁺ = Kᵀ(KKᵀ)⁻¹`, `K⁻ = I − K⁺K`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Split<const S: usize> {
    pub k: SMatrix<f64, S, 3>,
    pub k_plus: SMatrix<f64, 3, S>,
    pub k_minus: Matrix3<f64>,
}

impl<const S: usize> Split<S> {
    /// Smallest singular value of `K` relative to its largest below which it counts as rank deficient.
    pub const RANK_TOLERANCE: f64 = 1e-6;

    /// Fails if `K` is not of full row rank (Cholesky of `KKᵀ` with a relative pivot test; the
    /// pivots bound the singular values). Allocation-free.
    pub fn new(k: &SMatrix<f64, S, 3>) -> Result<Self, ConfigError> {
        let kkt = k * k.transpose();
        let scale = kkt.diagonal().amax();
        let rank_error = |sigma_min: f64| ConfigError::StiffnessRankDeficient {
            rows: S,
            sigma_min,
            threshold: Self::RANK_TOLERANCE,
        };
        if !(scale.is_finite() && scale > 0.0) {
            return Err(rank_error(0.0));
        }
        let chol = Cholesky::new(kkt).ok_or_else(|| rank_error(0.0))?;
        let l = chol.l();
        let min_pivot = l.diagonal().iter().fold(f64::INFINITY, |a, &b| a.min(b.abs()));
        if min_pivot * min_pivot < Self::RANK_TOLERANCE * Self::RANK_TOLERANCE * scale {
            return Err(rank_error(min_pivot));
        }
        let kkt_inv = chol.inverse();
        let k_plus = k.transpose() * kkt_inv;
        Ok(Split {
            k: *k,
            k_plus,
            k_minus: Matrix3::identity() - k_plus * k,
        })
    }
}
