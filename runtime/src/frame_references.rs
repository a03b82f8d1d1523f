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

use crate::{Pose, ReferenceFrame};
use nalgebra::{Matrix3, SMatrix, SVector, Vector3, Vector6};

fn halves(x: &Vector6<f64>) -> (Vector3<f64>, Vector3<f64>) {
    (
        x.fixed_rows::<3>(0).into_owned(),
        x.fixed_rows::<3>(3).into_owned(),
    )
}

fn join(lin: Vector3<f64>, ang: Vector3<f64>) -> Vector6<f64> {
    Vector6::new(lin.x, lin.y, lin.z, ang.x, ang.y, ang.z)
}

/// `m` with each column `[v; w]` replaced by `column(v, w)`.
fn map_columns<const N: usize>(
    m: &SMatrix<f64, 6, N>,
    mut column: impl FnMut(usize, Vector3<f64>, Vector3<f64>) -> (Vector3<f64>, Vector3<f64>),
) -> SMatrix<f64, 6, N> {
    let mut out = SMatrix::<f64, 6, N>::zeros();
    for c in 0..N {
        let (v, w) = halves(&m.column(c).into_owned());
        out.set_column(c, &{
            let (lin, ang) = column(c, v, w);
            join(lin, ang)
        });
    }
    out
}

/// The frame's Jacobian in `reference`, from its pose and its Jacobian in base axes.
pub fn jacobian<const N: usize>(
    reference: ReferenceFrame,
    pose: &Pose,
    aligned: SMatrix<f64, 6, N>,
) -> SMatrix<f64, 6, N> {
    let (r, p) = (&pose.rotation, &pose.translation);
    match reference {
        ReferenceFrame::LocalWorldAligned => aligned,
        ReferenceFrame::World => map_columns(&aligned, |_, v, w| (v + p.cross(&w), w)),
        ReferenceFrame::Local => map_columns(&aligned, |_, v, w| (r.tr_mul(&v), r.tr_mul(&w))),
    }
}

/// `J̇` in `reference` (the time derivative of [`jacobian`] there), from the frame's pose,
/// `J` and `J̇` in base axes (`kinematics`, as `frame_kinematics` returns them) along `qd`.
pub fn jacobian_time_variation<const N: usize>(
    reference: ReferenceFrame,
    kinematics: (Pose, SMatrix<f64, 6, N>, SMatrix<f64, 6, N>),
    qd: &SVector<f64, N>,
) -> SMatrix<f64, 6, N> {
    let (pose, j, jd) = kinematics;
    let (r, p): (&Matrix3<f64>, &Vector3<f64>) = (&pose.rotation, &pose.translation);
    let (p_dot, omega) = halves(&(j * qd));
    let column = |c: usize| halves(&j.column(c).into_owned());
    match reference {
        ReferenceFrame::LocalWorldAligned => jd,
        ReferenceFrame::World => map_columns(&jd, |c, vd, wd| {
            let w = column(c).1;
            (vd + p_dot.cross(&w) + p.cross(&wd), wd)
        }),
        ReferenceFrame::Local => map_columns(&jd, |c, vd, wd| {
            let (v, w) = column(c);
            (
                r.tr_mul(&(vd - omega.cross(&v))),
                r.tr_mul(&(wd - omega.cross(&w))),
            )
        }),
    }
}

/// The frame's velocity `[linear; angular]` in `reference`, from its pose and its velocity in
/// base axes.
pub fn velocity(reference: ReferenceFrame, pose: &Pose, aligned: Vector6<f64>) -> Vector6<f64> {
    let (v, w) = halves(&aligned);
    let (r, p) = (&pose.rotation, &pose.translation);
    match reference {
        ReferenceFrame::LocalWorldAligned => aligned,
        ReferenceFrame::World => join(v + p.cross(&w), w),
        ReferenceFrame::Local => join(r.tr_mul(&v), r.tr_mul(&w)),
    }
}

/// The frame's classical acceleration in `reference`, from its pose, its velocity and its
/// classical acceleration (`p̈`, `ω̇`) in base axes.
pub fn classical_acceleration(
    reference: ReferenceFrame,
    pose: &Pose,
    velocity: Vector6<f64>,
    aligned: Vector6<f64>,
) -> Vector6<f64> {
    let (p_ddot, w_dot) = halves(&aligned);
    let (r, p) = (&pose.rotation, &pose.translation);
    match reference {
        ReferenceFrame::LocalWorldAligned => aligned,
        ReferenceFrame::World => {
            let w = halves(&velocity).1;
            join(p_ddot + p.cross(&w_dot) + w.cross(&p.cross(&w)), w_dot)
        }
        ReferenceFrame::Local => join(r.tr_mul(&p_ddot), r.tr_mul(&w_dot)),
    }
}
