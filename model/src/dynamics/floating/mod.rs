//! Floating-base dynamics: the tree's recursions with its roots hanging from a free-flying base
//! body instead of the world.
//!
//! Pinocchio's conventions (`JointModelFreeFlyer`): the velocity is `ν = [v; ω]`, the base
//! body's twist in its own frame, then `q̇`; inverse dynamics returns the base wrench `[f; n]`
//! (in the base frame, about its origin), then the joint torques. In the base frame the base
//! is a body whose motion subspace is the identity and whose parent is the world, so every
//! recursion is the fixed-base one started from the base body's motion instead of from rest:
//! velocity `ν`, reference velocity `ν_r`, reference acceleration `a_r + ν × ν_r` with gravity
//! `Rᵀ g` folded in as an upward acceleration. That `ν × ν_r` is the term `Ṡ v` of any joint
//! (for the base, `Ṡ = ν × 1`): it makes `C` satisfy `Ḋ = C + Cᵀ` (`D`'s base block is
//! constant in base coordinates). Only gravity sees the base orientation; nothing but the
//! kinematics sees its position.
//!
//! Mimic joints and joint-level terms act on the joint rows as on a fixed base, through the same
//! code (`coupling`, `joint_terms`): velocities are `[ν_base; q̇]` with `q̇` the coordinates', the
//! tree runs at `G q̇`, its rows come back as `Gᵀ τ`; the armature sits on the joints' diagonal of
//! `D`, friction and offset in `τ`, their regressor columns after the bodies'. The base's six
//! rows are never touched.

mod centroidal;
mod coriolis;
mod derivatives;
mod inverse;
mod kinematics;
mod mass;

pub use mass::factor;

#[doc(hidden)]
pub use centroidal::{centroidal_bias, centroidal_momentum_matrix};
#[doc(hidden)]
pub use coriolis::floating_coriolis_matrix;
#[doc(hidden)]
pub use derivatives::{floating_forward_dynamics_derivatives, floating_inverse_dynamics_derivatives};
#[doc(hidden)]
pub use inverse::{
    floating_gravity, floating_inverse_dynamics, floating_inverse_dynamics_in_field,
    floating_motions_at_rest, floating_regressor, floating_slotine_li,
};
#[doc(hidden)]
pub use kinematics::{floating_body_poses, floating_frame_jacobian, floating_frame_jacobian_dot};
#[doc(hidden)]
pub use mass::{
    floating_bias, floating_forward_dynamics, floating_mass_matrix, floating_mass_matrix_inverse,
    floating_mass_matrix_inverse_by_ancestors,
};

use crate::scalar::Scalar;
use crate::spatial::{Force, Motion, RigidInertia, Transform, Vec3};

/// A floating base at one configuration: its pose in the world, and its body's inertia in its
/// own frame.
#[derive(Clone, Copy, Debug)]
pub struct FloatingBase<S> {
    pub pose: Transform<S>,
    pub inertia: RigidInertia<S>,
}

/// The base twist, the first six entries `[v; ω]` of a velocity vector, as a spatial motion.
pub fn base_motion<S: Scalar>(v: &[S]) -> Motion<S> {
    Motion {
        ang: Vec3([v[3], v[4], v[5]]),
        lin: Vec3([v[0], v[1], v[2]]),
    }
}

/// The entries `[f; n]` of a force on the base (what the base rows of `τ` hold).
pub fn base_entries<S: Scalar>(f: &Force<S>) -> [S; 6] {
    let (n, l) = (f.ang.0, f.lin.0);
    [l[0], l[1], l[2], n[0], n[1], n[2]]
}

/// The base motion of velocity coordinate `k < 6` at unit rate.
pub fn unit_base_motion<S: Scalar>(k: usize) -> Motion<S> {
    let mut v = [S::zero(); 6];
    v[k] = S::one();
    base_motion(&v)
}
