//! The centre of mass and the centroidal momentum: `h_G = A_g(q) ν`, the robot's linear
//! momentum and its angular momentum about the centre of mass, in world axes (Pinocchio's
//! `ccrba`), and `Ȧ_g ν` (`dccrba`), the rate of change of `h_G` at zero acceleration.
//!
//! The base rows of `D` are the momentum each velocity coordinate gives the whole robot, in the
//! base frame about its origin, so `A_g` is those rows moved to the centre of mass and turned
//! to world axes. The rate of change of the momentum about the centre of mass is the net
//! external wrench about it (the centre of mass's own velocity drops out), and at zero
//! acceleration without gravity that wrench is inverse dynamics' base wrench: `Ȧ_g ν` is it,
//! moved the same way.

use super::{inverse::floating_slotine_li, mass::floating_mass_matrix, FloatingBase};
use crate::model::Model;
use crate::scalar::Scalar;
use crate::spatial::{Force, RigidInertia, Transform, Vec3};
use nalgebra::DMatrix;

/// The robot's mass, centre of mass and centroidal momentum matrix at one configuration.
pub struct CentroidalMomentum<S> {
    pub mass: S,
    /// The centre of mass in world coordinates.
    pub com: Vec3<S>,
    /// `A_g` (6 × nv, rows `[linear; angular]`).
    pub matrix: DMatrix<S>,
}

/// The centre of mass in the base frame, and the total mass.
fn com_in_base<S: Scalar>(d: &DMatrix<S>) -> (S, Vec3<S>) {
    // The base block of `D` is the whole robot's inertia: mass on its linear diagonal, and the
    // first moment `m c` in its off-diagonal block (`D[ω_k, v_j] = (m c × e_j)_k`).
    let mass = d[(0, 0)];
    let h = Vec3([d[(5, 1)], d[(3, 2)], d[(4, 0)]]);
    (mass, h.scale(S::one() / mass))
}

/// A force on the base (entries `[f; n]` about the base origin, base axes) about the centre of
/// mass `c` (base frame), in world axes, as entries `[f; n]`.
fn about_com<S: Scalar>(base: &Transform<S>, c: &Vec3<S>, entries: [S; 6]) -> [S; 6] {
    let f = Force {
        lin: Vec3([entries[0], entries[1], entries[2]]),
        ang: Vec3([entries[3], entries[4], entries[5]]),
    };
    let n = f.ang - c.cross(&f.lin);
    let (fw, nw) = (base.rot.mul_vec(&f.lin), base.rot.mul_vec(&n));
    [fw.0[0], fw.0[1], fw.0[2], nw.0[0], nw.0[1], nw.0[2]]
}

/// Mass, centre of mass and `A_g`.
pub fn centroidal_momentum_matrix<S: Scalar>(
    model: &Model,
    base: &FloatingBase<S>,
    x: &[Transform<S>],
    inertias: &[RigidInertia<S>],
) -> CentroidalMomentum<S> {
    let d = floating_mass_matrix(model, &base.inertia, x, inertias);
    let (mass, c) = com_in_base(&d);
    let nv = d.ncols();
    let mut matrix = DMatrix::from_element(6, nv, S::zero());
    for col in 0..nv {
        let entries = std::array::from_fn(|r| d[(r, col)]);
        for (r, value) in about_com(&base.pose, &c, entries).into_iter().enumerate() {
            matrix[(r, col)] = value;
        }
    }
    CentroidalMomentum {
        mass,
        com: base.pose.transform_point(&c),
        matrix,
    }
}

/// `Ȧ_g(q, ν) ν`, entries `[linear; angular]`.
pub fn centroidal_bias<S: Scalar>(
    model: &Model,
    base: &FloatingBase<S>,
    x: &[Transform<S>],
    inertias: &[RigidInertia<S>],
    v: &[S],
) -> [S; 6] {
    let d = floating_mass_matrix(model, &base.inertia, x, inertias);
    let (_, c) = com_in_base(&d);
    let zero = vec![S::zero(); v.len()];
    let wrench = floating_slotine_li(model, base, x, inertias, v, v, &zero, None);
    about_com(&base.pose, &c, std::array::from_fn(|r| wrench[r]))
}
