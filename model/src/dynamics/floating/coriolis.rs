//! The Coriolis matrix of a floating-base robot in O(nv·depth): the fixed-base algorithm
//! (`dynamics::coriolis`, after Echeandia & Wensing 2021) with the base as the root body, its
//! six columns `Ψ_k = e_k` turning as `Ψ̇_k = ν × e_k`.
//!
//! For a column `d` and a column `a` of `d`'s body or of a body above it, with `I^C`, `İ^C`
//! and `h^C` the composite inertia, its derivative and momentum of `d`'s subtree:
//! `C_ad = Ψ_aᵀ (I^C Ψ̇_d + ½ İ^C Ψ_d + ½ Ψ_d ×* h^C)`, and for `a` strictly above,
//! `C_da = Ψ̇_aᵀ I^C Ψ_d + Ψ_aᵀ ½ (İ^C Ψ_d − Ψ_d ×* h^C)`, the three forces carried up to `a`.
//! With mimic joints, the tree's at `G q̇` carried through `G` on the joint rows and columns
//! (`coupling`), the Christoffel matrix of `D`'s as on a fixed base (`G` is constant).

use super::{base_entries, base_motion, unit_base_motion, FloatingBase};
use crate::dynamics::coriolis::{column_forces, tree_coriolis_into};
use crate::dynamics::coupling::{expand, project_both_after};
use crate::model::Model;
use crate::scalar::Scalar;
use crate::spatial::{Motion, RigidInertia, Transform};
use nalgebra::DMatrix;

/// `C(q, ν)` with `Ḋ = C + Cᵀ` and `C ν` the velocity terms of inverse dynamics.
pub fn floating_coriolis_matrix<S: Scalar>(
    model: &Model,
    base: &FloatingBase<S>,
    x: &[Transform<S>],
    inertias: &[RigidInertia<S>],
    qd: &[S],
) -> DMatrix<S> {
    let n = model.joints().len();
    let nu = base_motion(qd);
    let mut c = DMatrix::from_element(6 + n, 6 + n, S::zero());
    let joint_rates = expand(model, &qd[6..]);
    let tree = tree_coriolis_into(model, x, inertias, &joint_rates, Some(&nu), &mut c, 6)
        .expect("a moving root has its terms");
    let base_rates: [Motion<S>; 6] = std::array::from_fn(|k| nu.cross_motion(&unit_base_motion(k)));
    for (d, (f1, f2, f3)) in tree.forces.iter().enumerate() {
        let (e1, e3) = (base_entries(f1), base_entries(f3));
        for k in 0..6 {
            c[(k, 6 + d)] = e1[k];
            c[(6 + d, k)] = f2.power(&base_rates[k]) + e3[k];
        }
    }
    // The base block: the base body's own terms added to the whole tree's composites.
    let i = &base.inertia;
    let (ic, icdot, hc) = (
        tree.ic + *i,
        tree.icdot + i.derivative(&nu),
        tree.hc + i.mul_motion(&nu),
    );
    for k in 0..6 {
        let (f1, _, _) = column_forces(&ic, &icdot, &hc, &unit_base_motion(k), &base_rates[k]);
        for (j, value) in base_entries(&f1).into_iter().enumerate() {
            c[(j, k)] = value;
        }
    }
    project_both_after(model, c, 6)
}
