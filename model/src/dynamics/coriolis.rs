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
    let mut c = DMatrix::from_element(n, n, S::zero());
    tree_coriolis_into(model, x, inertias, qd, None, &mut c, 0);
    c
}

/// The three forces of a column `psi` (rate `psi_dot`) of a body whose subtree has composite
/// inertia `ic`, its derivative `icdot` and momentum `hc` (module docs): `f1` gives `C_ad`,
/// `f2` and `f3` give `C_da`.
pub fn column_forces<S: Scalar>(
    ic: &RigidInertia<S>,
    icdot: &RigidInertia<S>,
    hc: &Force<S>,
    psi: &Motion<S>,
    psi_dot: &Motion<S>,
) -> (Force<S>, Force<S>, Force<S>) {
    let half = S::from_f64(0.5);
    let g1 = icdot.mul_motion(psi).scale(half);
    let g2 = psi.cross_force(hc).scale(half);
    (ic.mul_motion(psi_dot) + g1 + g2, ic.mul_motion(psi), g1 - g2)
}

/// What a moving root (a floating base) needs of the tree's part of `C`: the whole robot's
/// composites but for the root body's own, and each joint's three forces carried to the root.
pub struct RootTerms<S> {
    pub ic: RigidInertia<S>,
    pub icdot: RigidInertia<S>,
    pub hc: Force<S>,
    /// Per joint `d`, its `(f1, f2, f3)` in the root's frame.
    pub forces: Vec<(Force<S>, Force<S>, Force<S>)>,
}

/// The tree's entries of `C` into `c` at rows and columns `offset + joint`, the roots hanging
/// from a base fixed in the world (`root: None`) or moving with `root` (in its frame; the
/// root's terms are returned). `qd` one rate per moving joint.
pub fn tree_coriolis_into<S: Scalar>(
    model: &Model,
    x: &[Transform<S>],
    inertias: &[RigidInertia<S>],
    qd: &[S],
    root: Option<&Motion<S>>,
    c: &mut DMatrix<S>,
    offset: usize,
) -> Option<RootTerms<S>> {
    let n = model.joints().len();
    let mut vel: Vec<Motion<S>> = Vec::with_capacity(n);
    for (i, joint) in model.joints().iter().enumerate() {
        let from_parent = match (joint.parent, root) {
            (Some(p), _) => x[i].motion_to_child(&vel[p]),
            (None, Some(nu)) => x[i].motion_to_child(nu),
            (None, None) => Motion::zero(),
        };
        vel.push(from_parent + joint_motion(joint, qd[i]));
    }
    let mut ic = inertias.to_vec();
    let mut icdot: Vec<RigidInertia<S>> = inertias.iter().zip(&vel).map(|(i, v)| i.derivative(v)).collect();
    let mut hc: Vec<Force<S>> = inertias.iter().zip(&vel).map(|(i, v)| i.mul_motion(v)).collect();
    let mut root_terms = root.map(|_| RootTerms {
        ic: RigidInertia::zero(),
        icdot: RigidInertia::zero(),
        hc: Force::zero(),
        forces: Vec::with_capacity(n),
    });
    for i in (0..n).rev() {
        match (model.joints()[i].parent, root_terms.as_mut()) {
            (Some(p), _) => {
                ic[p] = ic[p] + ic[i].to_parent(&x[i]);
                icdot[p] = icdot[p] + icdot[i].to_parent(&x[i]);
                hc[p] = hc[p] + x[i].force_to_parent(&hc[i]);
            }
            (None, Some(r)) => {
                r.ic = r.ic + ic[i].to_parent(&x[i]);
                r.icdot = r.icdot + icdot[i].to_parent(&x[i]);
                r.hc = r.hc + x[i].force_to_parent(&hc[i]);
            }
            (None, None) => {}
        }
    }
    for d in 0..n {
        let psi = joint_motion(&model.joints()[d], S::one());
        let psi_dot = vel[d].cross_motion(&psi);
        let (mut f1, mut f2, mut f3) = column_forces(&ic[d], &icdot[d], &hc[d], &psi, &psi_dot);
        c[(offset + d, offset + d)] = joint_force(&model.joints()[d], &f1);
        let mut a = d;
        while let Some(p) = model.joints()[a].parent {
            f1 = x[a].force_to_parent(&f1);
            f2 = x[a].force_to_parent(&f2);
            f3 = x[a].force_to_parent(&f3);
            a = p;
            let joint = &model.joints()[a];
            let psi_a_dot = vel[a].cross_motion(&joint_motion(joint, S::one()));
            c[(offset + a, offset + d)] = joint_force(joint, &f1);
            c[(offset + d, offset + a)] = f2.power(&psi_a_dot) + joint_force(joint, &f3);
        }
        if let Some(r) = root_terms.as_mut() {
            let up = |f: &Force<S>| x[a].force_to_parent(f);
            r.forces.push((up(&f1), up(&f2), up(&f3)));
        }
    }
    root_terms
}
