//! The Slotine–Li regressor `Y(q, q̇, v, a)` with `Y θ = D a + C v + g`.

use super::coupling::{expand, project_rows};
use super::joint::{joint_force, joint_motion};
use super::joint_terms::{column_entry, fill_joint_term_columns};
use super::slotine_li::{unit_body_forces, UnitForces};
use crate::model::Model;
use crate::scalar::Scalar;
use crate::scalar_dual::{seeded, Dual, LaneScalar, Tangent};
use crate::spatial::{Motion, Transform};
use dyngen_runtime::PARAMETERS_PER_BODY;
use nalgebra::DMatrix;

/// `Y` (n × P): column block `i` (ten columns) belongs to body `i`'s standard parameters; then
/// the joint-level columns of the model's chosen kinds (none: `P = 10·n`), see
/// `fill_joint_term_columns`.
///
/// The body force is linear in the body's inertia, so column `k` of a body's block is the
/// body force with unit parameter `k`, carried up the tree and projected on each ancestor joint.
///
/// With mimic joints, `Gᵀ` of the tree's regressor at `G q̇, G v, G a`: θ keeps every body's
/// ten parameters, a mimic joint's body included.
pub fn regressor<S: Scalar>(model: &Model, x: &[Transform<S>], qd: &[S], v: &[S], a: &[S]) -> DMatrix<S> {
    let (qd, v, a) = (expand(model, qd), expand(model, v), expand(model, a));
    project_rows(model, tree_regressor(model, x, &qd, &v, &a))
}

/// The regressor of the tree, one row per moving joint.
fn tree_regressor<S: Scalar>(model: &Model, x: &[Transform<S>], qd: &[S], v: &[S], a: &[S]) -> DMatrix<S> {
    let n = model.joints().len();
    let forces = unit_body_forces(model, x, qd, v, a);
    let mut y = DMatrix::from_element(n, model.parameter_count(), S::zero());
    for (i, unit) in forces.iter().enumerate() {
        for (k, mut f) in unit.iter().copied().enumerate() {
            let col = PARAMETERS_PER_BODY * i + k;
            let mut j = i;
            y[(j, col)] = joint_force(&model.joints()[j], &f);
            while let Some(p) = model.joints()[j].parent {
                f = x[j].force_to_parent(&f);
                j = p;
                y[(j, col)] = joint_force(&model.joints()[j], &f);
            }
        }
    }
    fill_joint_term_columns(model, &mut y, qd, v, a);
    y
}

/// [`regressor`] by the bodies' Jacobians: the entry of ancestor joint `i` in the column of
/// body `j`'s parameter `k` is `(X_{j←i} S_i) · f_j^k`, the ancestor's axis carried down to
/// the body (once per pair of joints) dotted with the body force, instead of each of the ten
/// body forces carried up to every ancestor. Where the joint frames are dense (a description
/// whose quarter turns are `1.5708`), carrying one axis is cheaper than carrying ten forces;
/// where they fold to permutations it may not be, so generation keeps whichever costs less.
pub fn regressor_by_jacobians<S: Scalar>(
    model: &Model,
    x: &[Transform<S>],
    qd: &[S],
    v: &[S],
    a: &[S],
) -> DMatrix<S> {
    let (qd, v, a) = (expand(model, qd), expand(model, v), expand(model, a));
    let n = model.joints().len();
    let forces = unit_body_forces(model, x, &qd, &v, &a);
    // Every joint's axis seen from each body below it (body j's local Jacobian, column by
    // column), built parent first: a body carries its parent's list down and adds its own.
    let mut axes: Vec<Vec<(usize, Motion<S>)>> = Vec::with_capacity(n);
    let mut y = DMatrix::from_element(n, model.parameter_count(), S::zero());
    for (j, (joint, unit)) in model.joints().iter().zip(&forces).enumerate() {
        let ancestors: Vec<(usize, Motion<S>)> = match joint.parent {
            Some(p) => axes[p]
                .iter()
                .map(|(i, s)| (*i, x[j].motion_to_child(s)))
                .collect(),
            None => Vec::new(),
        };
        for (k, f) in unit.iter().enumerate() {
            let col = PARAMETERS_PER_BODY * j + k;
            y[(j, col)] = joint_force(joint, f);
            for (i, s) in &ancestors {
                y[(*i, col)] = f.power(s);
            }
        }
        let mut own = ancestors;
        own.push((j, joint_motion(joint, S::one())));
        axes.push(own);
    }
    fill_joint_term_columns(model, &mut y, &qd, &v, &a);
    project_rows(model, y)
}

/// Rows of a regressor column computed at once, one per lane of a vector: four, one AVX
/// register of `f64`s. Eight (two AVX registers) left half of each vector idle on the rows no
/// body below reaches and doubled the values the compiled kernel spills.
pub const ROW_LANES: usize = 4;

/// The columns of [`regressor`], [`ROW_LANES`] rows at a time: entry `r` of the result holds, for
/// every column, the lane vector of rows `r·ROW_LANES ..` (row `r·ROW_LANES + k` in lane `k`;
/// lanes past the last row are zero).
///
/// Column `c` (parameter `k` of body `j`) has in row `i` the power `f_j^k · (X_{j←i} S_i)` of the
/// body force with unit parameter `k` on joint `i`'s axis seen from the body — the derivative of
/// `f_j^k · w_j` along `r_i`, where `w_j` is the velocity the joint rates `r` give body `j`
/// (`dynamics::regressor_products`). With the rates seeded one per lane (dual numbers whose
/// tangents are lane vectors), the bodies' velocities carry the axes of a run's rows side by
/// side, and each column is the body force's entries times them: a handful of vector
/// multiply-adds per column instead of one dot product per entry, with the axes in a few vector
/// registers instead of dozens of scalars. With mimic joints the rates are `G r`, so the rows are
/// those of `Gᵀ Y_tree`.
pub fn regressor_row_lanes<S: LaneScalar>(
    model: &Model,
    x: &[Transform<S>],
    qd: &[S],
    v: &[S],
    a: &[S],
) -> Vec<Vec<S::Lanes>> {
    let (qd, v, a) = (expand(model, qd), expand(model, v), expand(model, a));
    let joints = model.joints();
    let forces = unit_body_forces(model, x, &qd, &v, &a);
    let n = model.dof();
    let inertial = model.inertial_parameter_count();
    // The state enters as constants: only the rates carry lanes.
    let x: Vec<Transform<Dual<S, S::Lanes>>> = x.iter().map(|t| t.map(Dual::constant)).collect();
    let forces: Vec<UnitForces<Dual<S, S::Lanes>>> = forces
        .iter()
        .map(|unit| unit.map(|f| f.map(Dual::constant)))
        .collect();
    (0..n)
        .step_by(ROW_LANES)
        .map(|first| {
            let rates = expand(model, &seeded(&vec![S::zero(); n], first, ROW_LANES));
            let mut columns = vec![S::Lanes::zero(); model.parameter_count()];
            let mut w: Vec<Motion<Dual<S, S::Lanes>>> = Vec::with_capacity(joints.len());
            for (j, joint) in joints.iter().enumerate() {
                let up = joint
                    .parent
                    .map_or(Motion::zero(), |p| x[j].motion_to_child(&w[p]));
                let wj = up + joint_motion(joint, rates[j]);
                for (k, f) in forces[j].iter().enumerate() {
                    columns[PARAMETERS_PER_BODY * j + k] = f.power(&wj).tangent;
                }
                w.push(wj);
            }
            // A joint-level column is non-zero in its joint's row only.
            for (c, column) in columns.iter_mut().enumerate().skip(inertial) {
                let (j, kind) = model.joint_term_of_column(c);
                *column = rates[j].tangent.scale(column_entry(model, kind, j, &qd, &v, &a));
            }
            columns
        })
        .collect()
}
