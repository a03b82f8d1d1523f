//! Orientation rows of the task: a rotation-error formulation on the geometric Jacobian.
//!
//! # Why not Euler angles
//! The note's Remark 1 writes orientation as Euler angles `φ`, with `w = T(φ) φ̇` and the
//! analytic Jacobian `J = T⁻¹ J̄`. `T(φ)` is singular on a whole set of orientations (pitch
//! ±90° for roll-pitch-yaw, `θ = 0` for ZYZ, which is exactly a tool pointing straight down),
//! so a task would have to be refused near them, and `T⁻¹` and its derivative enter `q̈_r`.
//! Here the orientation rows are the **angular-velocity rows of the geometric Jacobian** (no
//! `T`, no parameterisation singularity; the only singularities left are the robot's own), and
//! the orientation *error* is a smooth function of the rotation matrices:
//!
//! - full orientation (`T = 6`): `e = ½ vee(R R_dᵀ − R_d Rᵀ) = sin φ · u`, base axes, where
//!   `R R_dᵀ` is the rotation by `φ` about `u` that takes the desired orientation to the
//!   actual one;
//! - tool axis (`T = 5`): `e = a_d × a = sin φ · u` with `a = R a_b` the tool axis, `a_d = R_d a_b`
//!   its desired direction; rows `E Rᵀ ω`, the angular velocity about the two tool axes
//!   perpendicular to `a_b` (`E` = an orthonormal basis of `a_b⊥`, tool frame), so the rotation
//!   about the tool axis is in the null space.
//!
//! # What it changes in the note's equations
//! For the orientation rows, `x_t − x_d` and `ẋ_t − ẋ_d` are replaced by the error `e` and
//! `ω − ω_d` (the desired motion gives `R_d`, `ω_d`, `ω̇_d`):
//!
//! ```text
//! v_x,o = P (ω_d − λ e)                   P = I (T = 6),  P = E Rᵀ (T = 5)
//! v̇_x,o = Ṗ (ω_d − λ e) + P (ω̇_d − λ ė)  Ṗ = 0,          Ṗ = −E Rᵀ [ω]×
//! J_o   = P J_ω,  J̇_o = P J̇_ω + Ṗ J_ω
//! ```
//!
//! with `ω = J_ω q̇` measured and `ė` exact: for `A = R R_dᵀ`, `Ȧ = [ω]× A − A [ω_d]×` and
//! `ė = ½ vee(Ȧ − Ȧᵀ)`; for the axis, `ė = (ω_d × a_d) × a + a_d × (ω × a)`. So `q̈_r` stays the
//! exact derivative of `q̇_r` (a test compares it with central differences) and everything the
//! note proves about `r` (`D ṙ + C r + G r = Y θ̃`, `V̇ = −rᵀ G r`) is unchanged: it never
//! depends on what `v_x` is, only on `q̈_r = d/dt q̇_r`. What changes is the meaning of
//! `r → 0` in these rows: `P (ω − ω_d + λ e) → 0`, which gives `φ̇ = −λ sin φ` for the angle `φ`
//! between actual and desired orientation (or axis): `φ → 0` from any `φ < 180°`, like `x̃` at
//! rate `λ` near 0. At 180° the error vanishes (an unstable equilibrium, not a singularity of the
//! law); beyond 90° it shrinks as the angle grows, so a start more than 90° away is refused.
//! Contact forces act on position rows only (`K`'s orientation columns are zero), so `K⁻` is
//! the identity on the orientation rows and the task-frame rotation is `R_T = diag(R, I)`.

use super::task::Orientation;
use nalgebra::{Matrix3, SMatrix, Vector3};

/// `[v]×`, so that `[v]× w = v × w`.
#[inline]
pub(crate) fn skew(v: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(0.0, -v.z, v.y, v.z, 0.0, -v.x, -v.y, v.x, 0.0)
}

/// `½ vee(A − Aᵀ)`.
#[inline]
fn vee_skew(a: &Matrix3<f64>) -> Vector3<f64> {
    Vector3::new(
        a[(2, 1)] - a[(1, 2)],
        a[(0, 2)] - a[(2, 0)],
        a[(1, 0)] - a[(0, 1)],
    ) * 0.5
}

/// An orthonormal pair `E` (rows) perpendicular to the unit vector `a`: the first row is
/// `a × c` normalised, `c` the base vector least aligned with `a`; the second `a × E₀`.
#[inline]
pub(crate) fn perpendicular_basis(a: &Vector3<f64>) -> SMatrix<f64, 2, 3> {
    let c = if a.x.abs() <= a.y.abs() && a.x.abs() <= a.z.abs() {
        Vector3::x()
    } else if a.y.abs() <= a.z.abs() {
        Vector3::y()
    } else {
        Vector3::z()
    };
    let e0 = a.cross(&c).normalize();
    let e1 = a.cross(&e0);
    SMatrix::<f64, 2, 3>::from_rows(&[e0.transpose(), e1.transpose()])
}

/// The orientation rows of a `T`-row task at one state: `P` and `Ṗ` placed in rows `3..T` of
/// `T×3` matrices (rows `0..3` are zero), the error `e`, its rate `ė` (base axes), and the
/// angle `φ` between actual and desired orientation (or tool axis).
#[derive(Clone, Copy, Debug)]
pub(crate) struct OrientationRows<const T: usize> {
    pub p: SMatrix<f64, T, 3>,
    pub p_dot: SMatrix<f64, T, 3>,
    pub error: Vector3<f64>,
    pub error_rate: Vector3<f64>,
}

impl<const T: usize> OrientationRows<T> {
    /// From the actual rotation `rot` and angular velocity `omega` and the desired `rot_d`,
    /// `omega_d` (base frame). For [`Orientation::Free`] everything is zero.
    #[inline]
    pub fn new(
        orientation: &Orientation,
        rot: &Matrix3<f64>,
        omega: &Vector3<f64>,
        rot_d: &Matrix3<f64>,
        omega_d: &Vector3<f64>,
    ) -> Self {
        let mut p = SMatrix::<f64, T, 3>::zeros();
        let mut p_dot = SMatrix::<f64, T, 3>::zeros();
        let (error, error_rate) = match orientation {
            Orientation::Free => (Vector3::zeros(), Vector3::zeros()),
            Orientation::Full => {
                for i in 0..3.min(T.saturating_sub(3)) {
                    p[(3 + i, i)] = 1.0;
                }
                let a = rot * rot_d.transpose();
                let a_dot = skew(omega) * a - a * skew(omega_d);
                (vee_skew(&a), vee_skew(&a_dot))
            }
            Orientation::ToolAxis { axis } => {
                let e = perpendicular_basis(axis);
                let rows = e * rot.transpose();
                let rows_dot = -rows * skew(omega);
                for i in 0..2.min(T.saturating_sub(3)) {
                    p.set_row(3 + i, &rows.row(i));
                    p_dot.set_row(3 + i, &rows_dot.row(i));
                }
                let (a, a_d) = (rot * axis, rot_d * axis);
                (
                    a_d.cross(&a),
                    omega_d.cross(&a_d).cross(&a) + a_d.cross(&omega.cross(&a)),
                )
            }
        };
        OrientationRows {
            p,
            p_dot,
            error,
            error_rate,
        }
    }
}

/// The angle (rad) between the actual and the desired orientation (`Full`) or tool axis
/// (`ToolAxis`); `NaN` when the orientation is free (not controlled).
pub(crate) fn orientation_angle(orientation: &Orientation, rot: &Matrix3<f64>, rot_d: &Matrix3<f64>) -> f64 {
    match orientation {
        Orientation::Free => f64::NAN,
        Orientation::Full => {
            let a = rot * rot_d.transpose();
            vee_skew(&a).norm().atan2(0.5 * (a.trace() - 1.0))
        }
        Orientation::ToolAxis { axis } => {
            let (a, a_d) = (rot * axis, rot_d * axis);
            a_d.cross(&a).norm().atan2(a_d.dot(&a))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use dyngen_runtime::SplitMix64;
    use nalgebra::Rotation3;

    fn random_rotation(rng: &mut SplitMix64) -> Matrix3<f64> {
        let v = Vector3::new(
            rng.uniform((-2.0, 2.0)),
            rng.uniform((-2.0, 2.0)),
            rng.uniform((-2.0, 2.0)),
        );
        Rotation3::new(v).into_inner()
    }

    fn random_vector(rng: &mut SplitMix64) -> Vector3<f64> {
        Vector3::new(
            rng.uniform((-1.0, 1.0)),
            rng.uniform((-1.0, 1.0)),
            rng.uniform((-1.0, 1.0)),
        )
    }

    /// Rotates `r` by the angular velocity `w` (base axes) for time `h`.
    fn advance(r: &Matrix3<f64>, w: &Vector3<f64>, h: f64) -> Matrix3<f64> {
        Rotation3::new(w * h).into_inner() * r
    }

    /// `ė` is the derivative of `e` along any motion, and the error is `sin φ` long.
    #[test]
    fn error_rate_is_the_derivative_of_the_error() {
        let mut rng = SplitMix64::new(4);
        let axis = Vector3::new(0.2, -0.3, 0.9).normalize();
        for orientation in [Orientation::Full, Orientation::ToolAxis { axis }] {
            for _ in 0..50 {
                let (r, rd) = (random_rotation(&mut rng), random_rotation(&mut rng));
                let (w, wd) = (random_vector(&mut rng), random_vector(&mut rng));
                let at = |h: f64| {
                    OrientationRows::<6>::new(
                        &orientation,
                        &advance(&r, &w, h),
                        &w,
                        &advance(&rd, &wd, h),
                        &wd,
                    )
                };
                let h = 1e-6;
                let fd = (at(h).error - at(-h).error) / (2.0 * h);
                let o = at(0.0);
                assert!((fd - o.error_rate).amax() < 1e-8, "{orientation:?}");
                let fd_p = (at(h).p - at(-h).p) / (2.0 * h);
                assert!((fd_p - o.p_dot).amax() < 1e-8, "{orientation:?}");
                let phi = orientation_angle(&orientation, &r, &rd);
                assert!((o.error.norm() - phi.sin()).abs() < 1e-12);
            }
        }
    }

    /// With the orientation rows tracked (`P ω = P (ω_d − λ e)`, any rotation about the tool
    /// axis for `T = 5`), the angle to the desired orientation obeys `φ̇ = −λ sin φ`.
    #[test]
    fn tracked_rows_give_the_angle_rate_minus_lambda_sin_phi() {
        let mut rng = SplitMix64::new(8);
        let axis = Vector3::z();
        let lambda = 3.0;
        for orientation in [Orientation::Full, Orientation::ToolAxis { axis }] {
            for _ in 0..50 {
                let (r, rd) = (random_rotation(&mut rng), random_rotation(&mut rng));
                let wd = random_vector(&mut rng);
                let o = OrientationRows::<6>::new(&orientation, &r, &Vector3::zeros(), &rd, &wd);
                // A free spin about the tool axis changes nothing for T = 5.
                let spin = match orientation {
                    Orientation::ToolAxis { .. } => r * axis * rng.uniform((-2.0, 2.0)),
                    _ => Vector3::zeros(),
                };
                let w = wd - o.error * lambda + spin;
                let angle =
                    |h: f64| orientation_angle(&orientation, &advance(&r, &w, h), &advance(&rd, &wd, h));
                let h = 1e-6;
                let rate = (angle(h) - angle(-h)) / (2.0 * h);
                let phi = angle(0.0);
                assert!(
                    (rate + lambda * phi.sin()).abs() < 1e-6,
                    "{orientation:?}: φ = {phi}, φ̇ = {rate}"
                );
            }
        }
    }
}
