//! The contact task: task dimension `T` (what of the controlled frame's pose is controlled: the
//! end-effector's by default, see `HybridController::with_controlled_frame`), the
//! task-frame rotation `R`, the contact stiffness rows `K` and their split into the
//! force-controlled directions `K⁺ = Kᵀ(KKᵀ)⁻¹` and the position-controlled ones `K⁻ = I − K⁺K`.
//!
//! # Task dimension
//! The task vector has `T` rows, chosen by the task's [`Orientation`]:
//!
//! | `T` | rows | null space on a 7-DOF arm |
//! |---|---|---|
//! | 3 (default) | position (of the controlled frame's origin) | 4-D |
//! | 5 | position + the direction of a tool axis (free rotation about it) | 2-D |
//! | 6 | position + full orientation | 1-D |
//!
//! Position rows are in the task frame (`x_t = R x`); orientation rows are angular-velocity
//! rows of the geometric Jacobian (base axes for `T = 6`, the tool's own axes perpendicular to
//! the tool axis for `T = 5`), so the task-frame rotation of the note is
//! `R_T = diag(R, I)`: it turns positions only. See [`crate::controller::orientation`] for the
//! orientation error and why it is not Euler angles.

use super::error::ConfigError;
use nalgebra::{Cholesky, Matrix3, SMatrix, Vector3};

/// What of the controlled frame's orientation the task controls.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Orientation {
    /// Nothing: task dimension 3 (position only).
    Free,
    /// The direction of `axis` (a unit vector in the controlled frame's axes, e.g. `+z`, the
    /// tool axis); the rotation about it is left to the null space. Task dimension 5.
    ToolAxis { axis: Vector3<f64> },
    /// The whole orientation. Task dimension 6.
    Full,
}

impl std::fmt::Display for Orientation {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Orientation::Free => write!(f, "position only"),
            Orientation::ToolAxis { axis } => {
                write!(f, "tool axis [{}, {}, {}]", axis.x, axis.y, axis.z)
            }
            Orientation::Full => write!(f, "full orientation"),
        }
    }
}

impl Orientation {
    /// The task dimension this orientation task gives.
    pub const fn task_dimension(&self) -> usize {
        match self {
            Orientation::Free => 3,
            Orientation::ToolAxis { .. } => 5,
            Orientation::Full => 6,
        }
    }

    /// The orientation task of task dimension `t` (tool axis `axis` for `t = 5`), if any.
    pub fn for_dimension(t: usize, axis: Vector3<f64>) -> Option<Orientation> {
        match t {
            3 => Some(Orientation::Free),
            5 => Some(Orientation::ToolAxis { axis }),
            6 => Some(Orientation::Full),
            _ => None,
        }
    }
}

/// The environment and the task as the controller models them (the note's eqs. 5–8).
///
/// - `rotation` `R`: task frame from base frame for positions, `x_t = R x` (a rotation, so
///   `R⁻¹ = Rᵀ`).
/// - `stiffness` `K` (S×T, full row rank): `F_t = K (x_t − x_e)` are the controlled force
///   components, positive when pressing for the plane (`K = [0, 0, −k, 0, …]`). Contact acts
///   on positions only: the orientation columns of `K` must be zero (a point contact exerts
///   no moment, and orientation errors are not coordinates whose derivative is `ω`).
/// - `force_selection` `Σ` (S×3): how the measured force on the environment `F̄` (base frame)
///   gives the same components, `F_t = Σ R F̄` (for the plane `Σ = [0, 0, −1]`).
/// - `contact_point` `x_e` (task frame): the undeformed surface point.
/// - `orientation`: what of the orientation is controlled; must match `T`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactTask<const T: usize = 3, const S: usize = 1> {
    pub rotation: Matrix3<f64>,
    pub stiffness: SMatrix<f64, S, T>,
    pub force_selection: SMatrix<f64, S, 3>,
    pub contact_point: Vector3<f64>,
    pub orientation: Orientation,
}

impl ContactTask<3, 1> {
    /// A plane through `point` with upward unit normal `normal` (base frame) and stiffness `k`:
    /// the task frame's z axis is the normal, `K = [0, 0, −k]`, `Σ = [0, 0, −1]`. Position
    /// only; [`ContactTask::with_orientation`] and [`ContactTask::with_tool_axis`] add
    /// orientation rows.
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
            orientation: Orientation::Free,
        })
    }
}

impl<const S: usize> ContactTask<3, S> {
    /// The same contact with the task dimension `U` (3, 5 or 6) and the orientation task that
    /// goes with it (`axis`, in the controlled frame's axes, is the tool axis for `U = 5`): `K`
    /// gains zero orientation columns. A `U` that is none of these gives a task that
    /// [`ContactTask::validate`] refuses.
    pub fn with_task_dimension<const U: usize>(&self, axis: Vector3<f64>) -> ContactTask<U, S> {
        ContactTask {
            rotation: self.rotation,
            stiffness: SMatrix::from_fn(|i, j| if j < 3 { self.stiffness[(i, j)] } else { 0.0 }),
            force_selection: self.force_selection,
            contact_point: self.contact_point,
            orientation: Orientation::for_dimension(U, axis).unwrap_or(Orientation::Free),
        }
    }

    /// Position and the full orientation (`T = 6`).
    pub fn with_orientation(&self) -> ContactTask<6, S> {
        self.with_task_dimension::<6>(Vector3::z())
    }

    /// Position and the direction of the tool axis `axis` (controlled frame's axes), free rotation
    /// about it (`T = 5`).
    pub fn with_tool_axis(&self, axis: Vector3<f64>) -> ContactTask<5, S> {
        self.with_task_dimension::<5>(axis)
    }
}

impl<const T: usize, const S: usize> ContactTask<T, S> {
    /// `K` from rows given at run time (a configuration file, a command line), checked against
    /// the task's shape: `S` rows of `T` entries.
    pub fn stiffness_from_rows(rows: &[&[f64]]) -> Result<SMatrix<f64, S, T>, ConfigError> {
        if rows.len() != S {
            return Err(ConfigError::StiffnessShape(format!(
                "K has {} rows; the task has {S} force-controlled directions",
                rows.len()
            )));
        }
        if let Some((i, row)) = rows.iter().enumerate().find(|(_, r)| r.len() != T) {
            return Err(ConfigError::StiffnessShape(format!(
                "row {i} of K has {} entries; the task dimension is {T}",
                row.len()
            )));
        }
        Ok(SMatrix::from_fn(|i, j| rows[i][j]))
    }

    /// Checks `R` is a rotation, the orientation task matches `T`, `K` acts on positions only
    /// and has full row rank; returns the split.
    pub fn validate(&self) -> Result<Split<T, S>, ConfigError> {
        let r = &self.rotation;
        let ortho = (r.transpose() * r - Matrix3::identity()).amax();
        if !ortho.is_finite() || ortho > 1e-9 || r.determinant() < 0.0 {
            return Err(ConfigError::Invalid {
                name: "task rotation R",
                detail: format!("not a proper rotation (‖RᵀR − I‖ = {ortho:.1e})"),
            });
        }
        let expected = self.orientation.task_dimension();
        if T != expected {
            return Err(ConfigError::TaskKind {
                task: T,
                orientation: self.orientation,
                expected,
            });
        }
        if let Orientation::ToolAxis { axis } = self.orientation {
            if !(axis.iter().all(|a| a.is_finite()) && (axis.norm() - 1.0).abs() < 1e-9) {
                return Err(ConfigError::Invalid {
                    name: "tool axis",
                    detail: format!("must be a unit vector, got [{}, {}, {}]", axis.x, axis.y, axis.z),
                });
            }
        }
        Split::new(&self.stiffness)
    }
}

/// `K`, `K⁺ = Kᵀ(KKᵀ)⁻¹`, `K⁻ = I − K⁺K`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Split<const T: usize = 3, const S: usize = 1> {
    pub k: SMatrix<f64, S, T>,
    pub k_plus: SMatrix<f64, T, S>,
    pub k_minus: SMatrix<f64, T, T>,
}

impl<const T: usize, const S: usize> Split<T, S> {
    /// Smallest singular value of `K` relative to its largest below which it counts as rank deficient.
    pub const RANK_TOLERANCE: f64 = 1e-6;

    /// Fails if `K` is not consistent with the task (more rows than the 3 position directions,
    /// a nonzero orientation column) or not of full row rank (Cholesky of `KKᵀ` with a relative
    /// pivot test; the pivots bound the singular values). Allocation-free.
    pub fn new(k: &SMatrix<f64, S, T>) -> Result<Self, ConfigError> {
        if T < 3 {
            return Err(ConfigError::TaskKind {
                task: T,
                orientation: Orientation::Free,
                expected: 3,
            });
        }
        if S > 3 {
            return Err(ConfigError::StiffnessShape(format!(
                "K has {S} rows: a contact controls at most the 3 force directions of the position rows"
            )));
        }
        if let Some((i, j)) = (0..S)
            .flat_map(|i| (3..T).map(move |j| (i, j)))
            .find(|&(i, j)| k[(i, j)] != 0.0)
        {
            return Err(ConfigError::StiffnessShape(format!(
                "K[{i}, {j}] = {:e} acts on orientation row {j} of the {T}-dimensional task; contact \
                 forces act on the position rows 0–2 only (orientation columns must be zero)",
                k[(i, j)]
            )));
        }
        let kkt = k * k.transpose();
        let scale = kkt.diagonal().amax();
        let rank_error = |sigma_min: f64| ConfigError::StiffnessRankDeficient {
            rows: S,
            cols: T,
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
            k_minus: SMatrix::<f64, T, T>::identity() - k_plus * k,
        })
    }
}
