//! Functions a large robot computes from its smaller generated ones instead of flattening them
//! whole (the generator's `code_shape`): the generated method passes its own `D`, bias and
//! `∂τ/∂x`, and the robot's constant table of coordinate parents, and these finish the work
//! through the tree factor ([`crate::tree_factor`]) in loops.
//!
//! Where the flattened form would be megabytes of code, this costs about what the pieces cost
//! together and needs no code of its own per robot.

use crate::tree_factor::{factor_in_place, solve, Rows};
use nalgebra::{SMatrix, SVector};

/// `D` factored along the tree, in place, with its inverse pivots.
struct Factored<'a, const N: usize> {
    parent: &'a [Option<usize>; N],
    l: SMatrix<f64, N, N>,
    inverse_pivots: [f64; N],
}

impl<'a, const N: usize> Factored<'a, N> {
    fn new(parent: &'a [Option<usize>; N], mut d: SMatrix<f64, N, N>) -> Self {
        let (mut pivots, mut inverse_pivots) = ([0.0; N], [0.0; N]);
        factor_in_place(parent, &mut d, &mut pivots, &mut inverse_pivots, |x| 1.0 / x);
        Factored {
            parent,
            l: d,
            inverse_pivots,
        }
    }

    /// `D⁻¹ b`.
    fn solve(&self, mut b: SVector<f64, N>) -> SVector<f64, N> {
        solve(self.parent, &self.l, &self.inverse_pivots, b.as_mut_slice());
        b
    }

    /// `−D⁻¹ B`, every column at once.
    fn solve_negated(&self, b: &SMatrix<f64, N, N>) -> SMatrix<f64, N, N> {
        // Coordinate k's unknowns over every right-hand side are row k of `B`: contiguous in
        // its transpose.
        let mut rows = -b.transpose();
        solve(self.parent, &self.l, &self.inverse_pivots, &mut Rows(&mut rows));
        rows.transpose()
    }
}

/// The derivatives of forward dynamics `(∂ν̇/∂q, ∂ν̇/∂ν)` from the robot's own `D` (armature
/// included), `free_force = τ − ID(q, ν, 0)` and its `∂τ/∂x` (`inverse_dynamics_derivatives`,
/// called at the solution): with `ν̇ = D⁻¹ (τ − b)` held by `ID(q, ν, ν̇) = τ`,
/// `∂ν̇/∂x = −D⁻¹ ∂τ/∂x` at that `ν̇`, every column solved through the tree factor of `D`.
/// `parent` is each velocity coordinate's parent in the factor's tree.
#[inline]
pub fn forward_dynamics_derivatives<const N: usize>(
    parent: &[Option<usize>; N],
    mass_matrix: SMatrix<f64, N, N>,
    free_force: SVector<f64, N>,
    inverse_dynamics_derivatives: impl FnOnce(&SVector<f64, N>) -> (SMatrix<f64, N, N>, SMatrix<f64, N, N>),
) -> (SMatrix<f64, N, N>, SMatrix<f64, N, N>) {
    let factored = Factored::new(parent, mass_matrix);
    let acceleration = factored.solve(free_force);
    let (dq, dv) = inverse_dynamics_derivatives(&acceleration);
    (factored.solve_negated(&dq), factored.solve_negated(&dv))
}
