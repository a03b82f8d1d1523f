//! A frame's quantities in the `local` and `world` reference frames, converted at run time from
//! those at its origin in base axes (`local_world_aligned`): what a robot generated with
//! `frame_references: aligned` runs instead of a straight-line function per reference frame.
//!
//! With `J = [J_v; J_ω]` at the frame origin `p` in base axes, `R` the frame's rotation,
//! `ṗ = J_v q̇` and `ω = J_ω q̇`:
//! - world (a spatial velocity, at the base origin): `[J_v + p × J_ω; J_ω]`, whose derivative
//!   is `[J̇_v + ṗ × J_ω + p × J̇_ω; J̇_ω]`;
//! - local (in the frame's axes): `Rᵀ` on each half, whose derivative is `Rᵀ (J̇ − ω × J)`.
//!
//! The classical acceleration in base axes is `(p̈, ω̇)`; in the frame's axes it is `Rᵀ` of
//! both, at the base origin `(p̈ + p × ω̇ + ω × (p × ω), ω̇)`. The generator traces the same
//! conversions symbolically where it writes each reference frame as its own function
//! (`dyngen_model`'s `FrameMotion`); the generated tests hold both to Pinocchio.
//!
//! Each works in place on the columns' six numbers: a call converts a Jacobian in a few
//! operations per column, with no temporary matrix. Every function is `#[inline]`: generated
//! code in another crate calls them, and a call per column costs more than its arithmetic.

use crate::{Pose, ReferenceFrame};
use nalgebra::{Matrix3, SMatrix, SVector, Vector3, Vector6};

type Three = [f64; 3];

#[inline]
fn cross(a: Three, b: Three) -> Three {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

#[inline]
fn add(a: Three, b: Three) -> Three {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

#[inline]
fn sub(a: Three, b: Three) -> Three {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// `Rᵀ x`.
#[inline]
fn turned_back(r: &Matrix3<f64>, x: Three) -> Three {
    core::array::from_fn(|i| r[(0, i)] * x[0] + r[(1, i)] * x[1] + r[(2, i)] * x[2])
}

#[inline]
fn three(v: &Vector3<f64>) -> Three {
    [v.x, v.y, v.z]
}

/// The halves `[v; w]` of a column (or a six-vector) and their replacement.
#[inline]
fn halves(column: &[f64]) -> (Three, Three) {
    (
        [column[0], column[1], column[2]],
        [column[3], column[4], column[5]],
    )
}

#[inline]
fn set(column: &mut [f64], lin: Three, ang: Three) {
    column[..3].copy_from_slice(&lin);
    column[3..6].copy_from_slice(&ang);
}

/// The linear and angular halves of `x`.
#[inline]
fn split(x: &SMatrix<f64, 6, 1>) -> (Three, Three) {
    halves(x.as_slice())
}

#[inline]
fn joined(lin: Three, ang: Three) -> Vector6<f64> {
    Vector6::new(lin[0], lin[1], lin[2], ang[0], ang[1], ang[2])
}

/// The frame's Jacobian in `reference`, from its pose and its Jacobian in base axes; `columns`
/// are those the frame's joints fill (the others are zero in every reference frame).
#[inline]
pub fn jacobian<const N: usize>(
    reference: ReferenceFrame,
    pose: &Pose,
    mut aligned: SMatrix<f64, 6, N>,
    columns: &[usize],
) -> SMatrix<f64, 6, N> {
    if reference == ReferenceFrame::LocalWorldAligned {
        return aligned;
    }
    let (r, p) = (&pose.rotation, three(&pose.translation));
    for &c in columns {
        let Some(column) = aligned.as_mut_slice().get_mut(6 * c..6 * c + 6) else {
            continue;
        };
        let (v, w) = halves(column);
        match reference {
            ReferenceFrame::World => set(column, add(v, cross(p, w)), w),
            _ => set(column, turned_back(r, v), turned_back(r, w)),
        }
    }
    aligned
}

/// `J̇` in `reference` (the time derivative of [`jacobian`] there), from the frame's pose,
/// `J` and `J̇` in base axes along `qd`; `columns` as for [`jacobian`].
#[inline]
pub fn jacobian_time_variation<const N: usize>(
    reference: ReferenceFrame,
    pose: &Pose,
    j: &SMatrix<f64, 6, N>,
    mut jd: SMatrix<f64, 6, N>,
    qd: &SVector<f64, N>,
    columns: &[usize],
) -> SMatrix<f64, 6, N> {
    if reference == ReferenceFrame::LocalWorldAligned {
        return jd;
    }
    let (r, p) = (&pose.rotation, three(&pose.translation));
    let mut velocity = [0.0; 6];
    for &c in columns {
        if let (Some(column), Some(&rate)) = (j.as_slice().get(6 * c..6 * c + 6), qd.get(c)) {
            velocity.iter_mut().zip(column).for_each(|(v, &x)| *v += x * rate);
        }
    }
    let (p_dot, omega) = halves(&velocity);
    for &c in columns {
        let (Some(column), Some(of_j)) = (
            jd.as_mut_slice().get_mut(6 * c..6 * c + 6),
            j.as_slice().get(6 * c..6 * c + 6),
        ) else {
            continue;
        };
        let ((vd, wd), (v, w)) = (halves(column), halves(of_j));
        match reference {
            ReferenceFrame::World => set(column, add(add(vd, cross(p_dot, w)), cross(p, wd)), wd),
            _ => set(
                column,
                turned_back(r, sub(vd, cross(omega, v))),
                turned_back(r, sub(wd, cross(omega, w))),
            ),
        }
    }
    jd
}

/// The frame's velocity `[linear; angular]` in `reference`, from its pose and its velocity in
/// base axes.
#[inline]
pub fn velocity(reference: ReferenceFrame, pose: &Pose, aligned: Vector6<f64>) -> Vector6<f64> {
    let (v, w) = split(&aligned);
    let (r, p) = (&pose.rotation, three(&pose.translation));
    match reference {
        ReferenceFrame::LocalWorldAligned => aligned,
        ReferenceFrame::World => joined(add(v, cross(p, w)), w),
        ReferenceFrame::Local => joined(turned_back(r, v), turned_back(r, w)),
    }
}

/// The frame's classical acceleration in `reference`, from its pose, its velocity and its
/// classical acceleration (`p̈`, `ω̇`) in base axes.
#[inline]
pub fn classical_acceleration(
    reference: ReferenceFrame,
    pose: &Pose,
    velocity: Vector6<f64>,
    aligned: Vector6<f64>,
) -> Vector6<f64> {
    let (p_ddot, w_dot) = split(&aligned);
    let (r, p) = (&pose.rotation, three(&pose.translation));
    match reference {
        ReferenceFrame::LocalWorldAligned => aligned,
        ReferenceFrame::World => {
            let w = split(&velocity).1;
            joined(add(add(p_ddot, cross(p, w_dot)), cross(w, cross(p, w))), w_dot)
        }
        ReferenceFrame::Local => joined(turned_back(r, p_ddot), turned_back(r, w_dot)),
    }
}
