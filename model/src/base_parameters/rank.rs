//! Numerics of the base-parameter computation: the regressor stacked at random states, the
//! forward greedy column selection, least squares for the folding coefficients, and the SVD
//! rank that cross-checks the selection. Each works on the stack or on its triangular factor
//! alike (`triangular.rs`).

use super::triangular::{axpy, dot, triangular_factor};
use crate::dynamics::{FloatingDynamics, NumericDynamics};
use crate::model::{JointKind, Model};
use dyngen_runtime::SplitMix64;
use nalgebra::DMatrix;

/// The regressor `Y(q, q̇, v, a)` of `model` at `states` random states stacked vertically
/// (`states·n × P`, joint-level columns included), the same for the same `seed`.
///
/// Revolute joints take any angle in `[−π, π)` (the dependencies between columns hold for every
/// state, so joint limits do not matter and a full turn avoids accidental symmetries); prismatic
/// joints move within their limits, or ±0.5 m. `q̇` and `v` are independent (`v ≠ q̇`, so the
/// Coriolis terms of `C v` are seen separately from those of `C q̇`), in ±2; `a` in ±5. Gravity
/// is part of every row, as in `Y`.
///
/// On a floating base the rows are the `nv = n + 6` of the floating regressor (the base wrench's
/// six first) and the columns the base body's ten, then ten per body; the base moves too: a
/// uniformly random orientation, a position in ±1 m, a twist and an acceleration like the
/// joints'.
pub fn stacked_regressor(model: &Model, states: usize, seed: u64) -> DMatrix<f64> {
    let mut rng = SplitMix64::new(seed);
    match FloatingDynamics::new(model) {
        Some(dynamics) => stacked_floating(&dynamics, &mut rng, states),
        None => stacked_fixed(model, &mut rng, states),
    }
}

fn stacked_fixed(model: &Model, rng: &mut SplitMix64, states: usize) -> DMatrix<f64> {
    let n = model.dof();
    let p = model.parameter_count();
    let dynamics = NumericDynamics::new(model);
    let mut stacked = DMatrix::zeros(states * n, p);
    for k in 0..states {
        let q = joint_positions(model, rng);
        let (qd, v, a) = (vector(rng, n, 2.0), vector(rng, n, 2.0), vector(rng, n, 5.0));
        let y = dynamics.regressor(&q, &qd, &v, &a);
        stacked.view_mut((k * n, 0), (n, p)).copy_from(&y);
    }
    stacked
}

fn stacked_floating(dynamics: &FloatingDynamics, rng: &mut SplitMix64, states: usize) -> DMatrix<f64> {
    let model = dynamics.model;
    let nv = model.nv();
    let p = dynamics.parameters().len();
    let mut stacked = DMatrix::zeros(states * nv, p);
    for k in 0..states {
        // A uniformly random unit quaternion (Shoemake's method), normalised once more so that
        // rounding stays far inside the unit-norm tolerance.
        let [u1, u2, u3] = [0.0; 3].map(|_| rng.uniform((0.0, 1.0)));
        let tau = std::f64::consts::TAU;
        let (a, b) = ((1.0 - u1).sqrt(), u1.sqrt());
        let quaternion = [
            a * (tau * u2).sin(),
            a * (tau * u2).cos(),
            b * (tau * u3).sin(),
            b * (tau * u3).cos(),
        ];
        let norm = quaternion.iter().map(|x| x * x).sum::<f64>().sqrt();
        let mut q = vector(rng, 3, 1.0);
        q.extend(quaternion.map(|x| x / norm));
        q.extend(joint_positions(model, rng));
        let state = dynamics.state(&q).expect("a unit quaternion");
        let (qd, v, a) = (vector(rng, nv, 2.0), vector(rng, nv, 2.0), vector(rng, nv, 5.0));
        let y = dynamics.regressor(&state, &qd, &v, &a);
        stacked.view_mut((k * nv, 0), (nv, p)).copy_from(&y);
    }
    stacked
}

/// One position per coordinate (mimic joints follow their master).
fn joint_positions(model: &Model, rng: &mut SplitMix64) -> Vec<f64> {
    (model.coordinate_joints().iter())
        .map(|&k| &model.joints()[k])
        .map(|j| match (j.kind, j.limits) {
            (JointKind::Revolute, _) => rng.uniform((-std::f64::consts::PI, std::f64::consts::PI)),
            (JointKind::Prismatic, Some(l)) if l.lower < l.upper => rng.uniform((l.lower, l.upper)),
            (JointKind::Prismatic, _) => rng.uniform((-0.5, 0.5)),
        })
        .collect()
}

fn vector(rng: &mut SplitMix64, n: usize, r: f64) -> Vec<f64> {
    (0..n).map(|_| rng.uniform((-r, r))).collect()
}

/// Euclidean norms of the columns.
pub fn column_norms(m: &DMatrix<f64>) -> Vec<f64> {
    let rows = m.nrows();
    (0..m.ncols())
        .map(|j| &m.as_slice()[j * rows..(j + 1) * rows])
        .map(|c| dot(c, c).sqrt())
        .collect()
}

/// A column whose norm is at most this fraction of the largest column norm is zero: it holds
/// only rounding errors of terms that cancel exactly (e.g. the mass of a body on a vertical
/// axis through its own joint origin). Rounding errors are ~1e-16 relative; a real column of a
/// robot-sized machine is within a few orders of magnitude of the largest.
pub const ZERO_COLUMN_TOL: f64 = 1e-11;

/// What the greedy selection found.
pub struct Selection {
    /// Kept (independent) columns, ascending.
    pub kept: Vec<usize>,
    /// Dropped columns that are not zero, ascending.
    pub dependent: Vec<usize>,
    /// Relative residual of the least independent kept column (the smallest).
    pub smallest_kept_residual: f64,
    /// Relative residual of the most independent dropped column (the largest).
    pub largest_dropped_residual: f64,
}

/// Forward greedy selection in parameter order: column `j` is kept iff, scaled to unit norm, the
/// part of it orthogonal to the columns already kept is longer than `tol`. Gram–Schmidt with one
/// reorthogonalisation ("twice is enough", Giraud et al. 2005), so the basis stays orthonormal
/// to rounding error however many columns are kept.
pub fn greedy_selection(y: &DMatrix<f64>, tol: f64) -> Selection {
    let norms = column_norms(y);
    let largest = norms.iter().cloned().fold(0.0, f64::max);
    let mut basis: Vec<Vec<f64>> = Vec::new();
    let mut selection = Selection {
        kept: Vec::new(),
        dependent: Vec::new(),
        smallest_kept_residual: f64::INFINITY,
        largest_dropped_residual: 0.0,
    };
    for (j, &norm) in norms.iter().enumerate() {
        if norm <= ZERO_COLUMN_TOL * largest || norm == 0.0 {
            continue;
        }
        let mut r: Vec<f64> = y.column(j).iter().map(|x| x / norm).collect();
        for _ in 0..2 {
            for b in &basis {
                let c = dot(b, &r);
                axpy(-c, b, &mut r);
            }
        }
        let residual = dot(&r, &r).sqrt();
        if residual > tol {
            selection.kept.push(j);
            selection.smallest_kept_residual = selection.smallest_kept_residual.min(residual);
            basis.push(r.iter().map(|x| x / residual).collect());
        } else {
            selection.dependent.push(j);
            selection.largest_dropped_residual = selection.largest_dropped_residual.max(residual);
        }
    }
    selection
}

/// Singular values of `y` with every non-zero column scaled to unit norm (and zero columns
/// zeroed), largest first.
pub fn scaled_singular_values(y: &DMatrix<f64>) -> Vec<f64> {
    let norms = column_norms(y);
    let largest = norms.iter().cloned().fold(0.0, f64::max);
    let mut scaled = y.clone();
    for (j, &norm) in norms.iter().enumerate() {
        let mut c = scaled.column_mut(j);
        if norm <= ZERO_COLUMN_TOL * largest || norm == 0.0 {
            c.fill(0.0);
        } else {
            c /= norm;
        }
    }
    let mut s: Vec<f64> = scaled.singular_values().iter().cloned().collect();
    s.sort_by(|a, b| b.total_cmp(a));
    s
}

/// Numerical rank: singular values (of the column-scaled matrix) above `tol · σ_max`.
pub fn numerical_rank(y: &DMatrix<f64>, tol: f64) -> usize {
    let s = scaled_singular_values(y);
    let max = s.first().cloned().unwrap_or(0.0);
    s.iter().filter(|&&x| x > tol * max).count()
}

/// Least squares `Y_kept β ≈ Y_dep` (one column of β per dependent column), on unit-norm
/// columns, with one step of iterative refinement; returned in the units of the parameters
/// (`y_dep = Σ_k β_k y_kept,k`).
pub fn folding_coefficients(y: &DMatrix<f64>, kept: &[usize], dependent: &[usize]) -> DMatrix<f64> {
    let norms = column_norms(y);
    let pick =
        |cols: &[usize]| DMatrix::from_fn(y.nrows(), cols.len(), |i, k| y[(i, cols[k])] / norms[cols[k]]);
    let (a, b) = (pick(kept), pick(dependent));
    if kept.is_empty() || dependent.is_empty() {
        return DMatrix::zeros(kept.len(), dependent.len());
    }
    // Householder QR, not an SVD: on a random 10-joint tree whose kept columns are well apart
    // (smallest greedy residual 0.25), nalgebra's SVD solution was off by 4e-8 relative after a
    // rounding-level change of the samples; QR was exact to 2e-15 on both.
    let mut beta = least_squares(&a, &b);
    let mut residual = b.clone();
    for d in 0..b.ncols() {
        let r = &mut residual.as_mut_slice()[d * a.nrows()..(d + 1) * a.nrows()];
        for k in 0..a.ncols() {
            axpy(
                -beta[(k, d)],
                &a.as_slice()[k * a.nrows()..(k + 1) * a.nrows()],
                r,
            );
        }
    }
    beta += least_squares(&a, &residual);
    DMatrix::from_fn(kept.len(), dependent.len(), |k, d| {
        beta[(k, d)] * norms[dependent[d]] / norms[kept[k]]
    })
}

/// `argmin ‖A X − B‖` for `A` of full column rank, column by column: the triangular factor of
/// `[A B]` is `[R₁₁ R₁₂; 0 R₂₂]` and `R₁₁ X = R₁₂` (zero if `R₁₁` is singular).
fn least_squares(a: &DMatrix<f64>, b: &DMatrix<f64>) -> DMatrix<f64> {
    let (k, d) = (a.ncols(), b.ncols());
    let mut joined = DMatrix::zeros(a.nrows(), k + d);
    joined.columns_mut(0, k).copy_from(a);
    joined.columns_mut(k, d).copy_from(b);
    let r = triangular_factor(&joined);
    if r.nrows() < k || (0..k).any(|i| r[(i, i)] == 0.0) {
        return DMatrix::zeros(k, d);
    }
    let mut x = DMatrix::zeros(k, d);
    for c in 0..d {
        for i in (0..k).rev() {
            let mut s = r[(i, k + c)];
            for j in i + 1..k {
                s -= r[(i, j)] * x[(j, c)];
            }
            x[(i, c)] = s / r[(i, i)];
        }
    }
    x
}

/// How well `y_j ≈ Σ_k coefficients_k y_k` holds on `y`: `‖y_j − Σ c_k y_k‖` relative to
/// `‖y_j‖ + Σ |c_k| ‖y_k‖` (the size of the terms that cancel), 0 when all are zero.
pub fn relative_residual(y: &DMatrix<f64>, j: usize, terms: &[(usize, f64)]) -> f64 {
    let column = |k: usize| &y.as_slice()[k * y.nrows()..(k + 1) * y.nrows()];
    let mut r = column(j).to_vec();
    let mut scale = dot(&r, &r).sqrt();
    for &(k, c) in terms {
        let y_k = column(k);
        axpy(-c, y_k, &mut r);
        scale += c.abs() * dot(y_k, y_k).sqrt();
    }
    if scale == 0.0 {
        0.0
    } else {
        dot(&r, &r).sqrt() / scale
    }
}
