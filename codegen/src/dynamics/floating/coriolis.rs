//! The Coriolis matrix of a floating-base robot in O(nv·depth): the fixed-base algorithm
//! (`dynamics::coriolis`, after Echeandia & Wensing 2021) with the base as the root body, its
//! six columns `Ψ_k = e_k` turning as `Ψ̇_k = ν × e_k`.
//!
//! For a column `d` and a column `a` of `d`'s body or of a body above it, with `I^C`, `İ^C`
//! and `h^C` the composite inertia, its derivative and momentum of `d`'s subtree:
//! `C_ad = Ψ_aᵀ (I^C Ψ̇_d + ½ İ^C Ψ_d + ½ Ψ_d ×* h^C)`, and for `a` strictly above,
//! `C_da = Ψ̇_aᵀ I^C Ψ_d + Ψ_aᵀ ½ (İ^C Ψ_d − Ψ_d ×* h^C)`, the three forces carried up to `a`.

use super::{base_entries, base_motion, unit_base_motion, FloatingBase};
use crate::dynamics::joint::{joint_force, joint_motion};
use crate::model::Model;
use crate::scalar::Scalar;
use crate::spatial::{Force, Motion, RigidInertia, Transform};
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
    let mut vel: Vec<Motion<S>> = Vec::with_capacity(n);
    for (i, joint) in model.joints().iter().enumerate() {
        let parent = joint.parent.map_or(nu, |p| vel[p]);
        vel.push(x[i].motion_to_child(&parent) + joint_motion(joint, qd[6 + i]));
    }
    let mut ic = inertias.to_vec();
    let mut icdot: Vec<RigidInertia<S>> = inertias.iter().zip(&vel).map(|(i, v)| i.derivative(v)).collect();
    let mut hc: Vec<Force<S>> = inertias.iter().zip(&vel).map(|(i, v)| i.mul_motion(v)).collect();
    let (mut ic_base, mut icdot_base, mut hc_base) = (
        base.inertia,
        base.inertia.derivative(&nu),
        base.inertia.mul_motion(&nu),
    );
    for i in (0..n).rev() {
        match model.joints()[i].parent {
            Some(p) => {
                ic[p] = ic[p] + ic[i].to_parent(&x[i]);
                icdot[p] = icdot[p] + icdot[i].to_parent(&x[i]);
                hc[p] = hc[p] + x[i].force_to_parent(&hc[i]);
            }
            None => {
                ic_base = ic_base + ic[i].to_parent(&x[i]);
                icdot_base = icdot_base + icdot[i].to_parent(&x[i]);
                hc_base = hc_base + x[i].force_to_parent(&hc[i]);
            }
        }
    }
    let half = S::from_f64(0.5);
    let base_rates: [Motion<S>; 6] = std::array::from_fn(|k| nu.cross_motion(&unit_base_motion(k)));
    let mut c = DMatrix::from_element(6 + n, 6 + n, S::zero());
    // The forces of column `psi` (rate `psi_dot`) of a body with these composites.
    let forces = |ic: &RigidInertia<S>,
                  icdot: &RigidInertia<S>,
                  hc: &Force<S>,
                  psi: &Motion<S>,
                  psi_dot: &Motion<S>| {
        let g1 = icdot.mul_motion(psi).scale(half);
        let g2 = psi.cross_force(hc).scale(half);
        (ic.mul_motion(psi_dot) + g1 + g2, ic.mul_motion(psi), g1 - g2)
    };
    for d in 0..n {
        let psi = joint_motion(&model.joints()[d], S::one());
        let psi_dot = vel[d].cross_motion(&psi);
        let (mut f1, mut f2, mut f3) = forces(&ic[d], &icdot[d], &hc[d], &psi, &psi_dot);
        c[(6 + d, 6 + d)] = joint_force(&model.joints()[d], &f1);
        let mut a = d;
        while let Some(p) = model.joints()[a].parent {
            f1 = x[a].force_to_parent(&f1);
            f2 = x[a].force_to_parent(&f2);
            f3 = x[a].force_to_parent(&f3);
            a = p;
            let joint = &model.joints()[a];
            let psi_a_dot = vel[a].cross_motion(&joint_motion(joint, S::one()));
            c[(6 + a, 6 + d)] = joint_force(joint, &f1);
            c[(6 + d, 6 + a)] = f2.power(&psi_a_dot) + joint_force(joint, &f3);
        }
        let (f1, f2, f3) = (
            x[a].force_to_parent(&f1),
            x[a].force_to_parent(&f2),
            x[a].force_to_parent(&f3),
        );
        let (e1, e3) = (base_entries(&f1), base_entries(&f3));
        for k in 0..6 {
            c[(k, 6 + d)] = e1[k];
            c[(6 + d, k)] = f2.power(&base_rates[k]) + e3[k];
        }
    }
    for k in 0..6 {
        let (f1, _, _) = forces(
            &ic_base,
            &icdot_base,
            &hc_base,
            &unit_base_motion(k),
            &base_rates[k],
        );
        for (j, value) in base_entries(&f1).into_iter().enumerate() {
            c[(j, k)] = value;
        }
    }
    c
}
