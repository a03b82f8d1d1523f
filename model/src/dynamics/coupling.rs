//! Mimic joints in the algorithms: the tree moves with `q_tree = G q + o`, so every quantity is
//! the tree's quantity carried through the constant matrix `G` (`model::Mimic`,
//! `docs/dynamics.md`): velocities and accelerations in, `q̇_tree = G q̇`; torques out, `Gᵀ τ`;
//! Jacobians `J G`; inertia and Coriolis matrices `Gᵀ M G`; regressor rows `Gᵀ Y`.
//!
//! Each public algorithm of this module's siblings takes and returns coordinates (`q` of
//! length [`Model::dof`]) and runs on the tree inside. Without mimic joints `G` is the identity
//! and every function here returns its input untouched: no operation is added, so the traced
//! graph (and the generated code) of such a robot is what it always was.

use crate::model::Model;
use crate::scalar::Scalar;
use nalgebra::DMatrix;

/// `G v`: the velocity (or acceleration) of every tree joint from the coordinates' ones.
pub fn expand<S: Scalar>(model: &Model, v: &[S]) -> Vec<S> {
    if !model.has_mimics() {
        return v.to_vec();
    }
    model
        .coordinate_maps()
        .iter()
        .zip(model.mimics())
        .map(|(c, m)| match m {
            None => v[c.coordinate],
            Some(_) => S::from_f64(c.multiplier) * v[c.coordinate],
        })
        .collect()
}

/// `Σ_j G_jc x_j` for every coordinate `c`, from `x_j` per tree joint (an entry or a row):
/// `scale(m, x)` is `m·x` and `add` the sum; the first term of a coordinate is not added to a
/// zero, so no `0 + x` is recorded.
fn gather<T: Clone>(
    model: &Model,
    tree: Vec<T>,
    scale: impl Fn(f64, T) -> T,
    add: impl Fn(T, T) -> T,
) -> Vec<T> {
    let mut out: Vec<Option<T>> = vec![None; model.dof()];
    for (c, x) in model.coordinate_maps().iter().zip(tree) {
        let term = scale(c.multiplier, x);
        out[c.coordinate] = Some(match out[c.coordinate].take() {
            None => term,
            Some(acc) => add(acc, term),
        });
    }
    // Every coordinate is its own joint's position, so each has at least one term.
    out.into_iter().flatten().collect()
}

fn scaled<S: Scalar>(m: f64, x: S) -> S {
    if m == 1.0 {
        x
    } else {
        S::from_f64(m) * x
    }
}

/// `Gᵀ τ`: the generalised forces on the coordinates from the tree joints' torques (virtual
/// work: a mimic joint's torque acts on its master's coordinate, times the multiplier).
pub fn project<S: Scalar>(model: &Model, tau: Vec<S>) -> Vec<S> {
    if !model.has_mimics() {
        return tau;
    }
    gather(model, tau, scaled, |a, b| a + b)
}

/// `Gᵀ M`: every column of `m` (rows per tree joint) projected as [`project`] does.
pub fn project_rows<S: Scalar>(model: &Model, m: DMatrix<S>) -> DMatrix<S> {
    project_rows_after(model, m, 0)
}

/// [`project_rows`] of the rows after the first `lead`, which are kept (a floating base's six:
/// the base wrench is not a tree joint's).
pub fn project_rows_after<S: Scalar>(model: &Model, m: DMatrix<S>, lead: usize) -> DMatrix<S> {
    if !model.has_mimics() {
        return m;
    }
    let cols = m.ncols();
    let rows: Vec<Vec<S>> = m.row_iter().map(|r| r.iter().copied().collect()).collect();
    let (kept, tree) = (&rows[..lead], rows[lead..].to_vec());
    let projected = gather(
        model,
        tree,
        |k, row: Vec<S>| row.into_iter().map(|x| scaled(k, x)).collect(),
        |a: Vec<S>, b: Vec<S>| a.into_iter().zip(b).map(|(x, y)| x + y).collect(),
    );
    let all: Vec<&Vec<S>> = kept.iter().chain(&projected).collect();
    DMatrix::from_fn(lead + model.dof(), cols, |r, c| all[r][c])
}

/// `M G`: columns per tree joint gathered onto the coordinates (a Jacobian's columns).
pub fn project_columns<S: Scalar>(model: &Model, m: DMatrix<S>) -> DMatrix<S> {
    project_columns_after(model, m, 0)
}

/// [`project_columns`] of the columns after the first `lead`, which are kept.
pub fn project_columns_after<S: Scalar>(model: &Model, m: DMatrix<S>, lead: usize) -> DMatrix<S> {
    if !model.has_mimics() {
        return m;
    }
    project_rows_after(model, m.transpose(), lead).transpose()
}

/// `Gᵀ M G`: a tree-joint matrix (inertia, Coriolis) on the coordinates.
pub fn project_both<S: Scalar>(model: &Model, m: DMatrix<S>) -> DMatrix<S> {
    project_both_after(model, m, 0)
}

/// [`project_both`] of the rows and columns after the first `lead`: a floating base's `D` and
/// `C`, whose base block and the base rows and columns of whose joint blocks are kept.
pub fn project_both_after<S: Scalar>(model: &Model, m: DMatrix<S>, lead: usize) -> DMatrix<S> {
    project_columns_after(model, project_rows_after(model, m, lead), lead)
}
