//! The solve shared by constrained forward dynamics, impulses and the operational-space
//! inertia: `J M⁻¹ Jᵀ + μ I` factored once, generic over the scalar.

use crate::dynamics::tree_ldl::TreeLdl;
use crate::scalar::Scalar;
use nalgebra::DMatrix;

/// `M⁻¹ Jᵀ` and the factored `J M⁻¹ Jᵀ + μ I` at one state.
pub struct Delassus<S> {
    jacobian: DMatrix<S>,
    /// `M⁻¹ Jᵀ` (nv × rows).
    minv_jt: DMatrix<S>,
    /// `J M⁻¹ Jᵀ + μ I`, factored as a chain (the dense `LDLᵀ`).
    factor: TreeLdl<S>,
    mu: S,
}

impl<S: Scalar> Delassus<S> {
    /// Factors `J M⁻¹ Jᵀ + μ I`, `mass` the factored mass matrix.
    pub fn new(mass: &TreeLdl<S>, jacobian: DMatrix<S>, mu: S) -> Self {
        let minv_jt = mass.solve_matrix(&jacobian.transpose());
        let mut delassus = product(&jacobian, &minv_jt);
        let rows = delassus.nrows();
        for k in 0..rows {
            delassus[(k, k)] = delassus[(k, k)] + mu;
        }
        let chain = (0..rows).map(|k| k.checked_sub(1)).collect();
        Delassus {
            factor: TreeLdl::factor_tree(chain, &delassus),
            jacobian,
            minv_jt,
            mu,
        }
    }

    /// The pivots of the factored Delassus matrix (a zero pivot is a redundant row when
    /// `μ = 0`).
    pub fn pivots(&self) -> &[S] {
        &self.factor.pivots
    }

    /// One proximal iteration: `λ = (J M⁻¹ Jᵀ + μ I)⁻¹ (rhs − J a_free + μ λ_prev)`.
    pub fn multipliers(&self, free: &[S], rhs: &[S], previous: &[S]) -> Vec<S> {
        let j_free = times(&self.jacobian, free);
        let b: Vec<S> = (0..rhs.len())
            .map(|k| rhs[k] - j_free[k] + self.mu * previous[k])
            .collect();
        self.factor.solve(&b)
    }

    /// `a_free + M⁻¹ Jᵀ λ`.
    pub fn motion(&self, free: &[S], lambda: &[S]) -> Vec<S> {
        let correction = times(&self.minv_jt, lambda);
        free.iter().zip(correction).map(|(&f, c)| f + c).collect()
    }

    /// `J x`.
    pub fn rows_times(&self, x: &[S]) -> Vec<S> {
        times(&self.jacobian, x)
    }

    /// `(J M⁻¹ Jᵀ + μ I)⁻¹`, the (regularised) operational-space inertia of the rows.
    pub fn inverse(&self) -> DMatrix<S> {
        self.factor.inverse()
    }
}

/// `a b`, written out: the symbolic scalar is not one of nalgebra's.
fn product<S: Scalar>(a: &DMatrix<S>, b: &DMatrix<S>) -> DMatrix<S> {
    DMatrix::from_fn(a.nrows(), b.ncols(), |i, j| {
        (0..a.ncols()).fold(S::zero(), |acc, k| acc + a[(i, k)] * b[(k, j)])
    })
}

fn times<S: Scalar>(m: &DMatrix<S>, x: &[S]) -> Vec<S> {
    (0..m.nrows())
        .map(|i| (0..m.ncols()).fold(S::zero(), |acc, j| acc + m[(i, j)] * x[j]))
        .collect()
}
