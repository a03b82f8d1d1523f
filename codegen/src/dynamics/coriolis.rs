//! The Christoffel-consistent Coriolis matrix `C(q, q̇)` in O(n·depth), after Echeandia &
//! Wensing (2021), with composites that need no 6×6 matrices.
//!
//! With `Ψ_j` joint `j`'s motion subspace and `Ψ̇_j = v_j × Ψ_j`, column `j` of `C` is the
//! Slotine–Li torque at `v = e_j`: bodies below `j` see reference velocity `Ψ_j` and reference
//! acceleration `Ψ̇_j`, and exert `I_k Ψ̇_j + B(I_k, v_k) Ψ_j`. The body operator is
//! `B(I, v) w = ½ [İ w + w ×* (I v)]`, so its sum over a subtree needs only the composite
//! inertia `I^C`, its derivative `İ^C` (rigid-inertia shaped) and the composite momentum
//! `h^C = Σ I_k v_k`. For `a` an ancestor of `d` (or `d` itself):
//!
//! - `C_ad = Ψ_aᵀ (I^C_d Ψ̇_d + B^C_d Ψ_d)`,
//! - `C_da = Ψ̇_aᵀ I^C_d Ψ_d + Ψ_aᵀ B^C_dᵀ Ψ_d`, with `B^Cᵀ Ψ = ½ [İ^C Ψ − Ψ ×* h^C]`,
//!
//! the three forces carried from `d` up to `a`.

use super::coupling::{expand, project_both};
use super::joint::{joint_force, joint_motion};
use crate::model::Model;
use crate::scalar::Scalar;
use crate::spatial::{Force, Motion, RigidInertia, Transform};
use nalgebra::DMatrix;

/// `C(q, q̇)` on the coordinates: `Gᵀ C_tree(q, G q̇) G` with mimic joints, which is the
/// Christoffel matrix of `Gᵀ D_tree G` because `G` is constant.
pub fn coriolis_matrix<S: Scalar>(
    model: &Model,
    x: &[Transform<S>],
    inertias: &[RigidInertia<S>],
    qd: &[S],
) -> DMatrix<S> {
    project_both(
        model,
        tree_coriolis_matrix(model, x, inertias, &expand(model, qd)),
    )
}

/// The Coriolis matrix of the tree, `qd` one rate per moving joint.
fn tree_coriolis_matrix<S: Scalar>(
    model: &Model,
    x: &[Transform<S>],
    inertias: &[RigidInertia<S>],
    qd: &[S],
) -> DMatrix<S> {
    let n = model.joints().len();
    let mut vel: Vec<Motion<S>> = Vec::with_capacity(n);
    for (i, joint) in model.joints().iter().enumerate() {
        let from_parent = joint
            .parent
            .map_or(Motion::zero(), |p| x[i].motion_to_child(&vel[p]));
        vel.push(from_parent + joint_motion(joint, qd[i]));
    }
    let mut ic = inertias.to_vec();
    let mut icdot: Vec<RigidInertia<S>> = inertias.iter().zip(&vel).map(|(i, v)| i.derivative(v)).collect();
    let mut hc: Vec<Force<S>> = inertias.iter().zip(&vel).map(|(i, v)| i.mul_motion(v)).collect();
    for i in (0..n).rev() {
        if let Some(p) = model.joints()[i].parent {
            ic[p] = ic[p] + ic[i].to_parent(&x[i]);
            icdot[p] = icdot[p] + icdot[i].to_parent(&x[i]);
            hc[p] = hc[p] + x[i].force_to_parent(&hc[i]);
        }
    }
    let half = S::from_f64(0.5);
    let mut c = DMatrix::from_element(n, n, S::zero());
    for d in 0..n {
        let psi = joint_motion(&model.joints()[d], S::one());
        let psi_dot = vel[d].cross_motion(&psi);
        let g1 = icdot[d].mul_motion(&psi).scale(half);
        let g2 = psi.cross_force(&hc[d]).scale(half);
        let mut f1 = ic[d].mul_motion(&psi_dot) + g1 + g2;
        let mut f2 = ic[d].mul_motion(&psi);
        let mut f3 = g1 - g2;
        c[(d, d)] = joint_force(&model.joints()[d], &f1);
        let mut a = d;
        while let Some(p) = model.joints()[a].parent {
            f1 = x[a].force_to_parent(&f1);
            f2 = x[a].force_to_parent(&f2);
            f3 = x[a].force_to_parent(&f3);
            a = p;
            let joint = &model.joints()[a];
            let psi_a_dot = vel[a].cross_motion(&joint_motion(joint, S::one()));
            c[(a, d)] = joint_force(joint, &f1);
            c[(d, a)] = f2.power(&psi_a_dot) + joint_force(joint, &f3);
        }
    }
    c
}
