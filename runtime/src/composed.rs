//! Functions a large robot computes from its smaller generated ones instead of flattening them
//! whole (the generator's `code_shape`): the generated method passes its own `D`, bias and
//! `∂τ/∂x`, and the robot's [`Tree`] (a constant built at compile time from its coordinates'
//! parents), and these finish the work through the tree factor ([`crate::tree_factor`]) in
//! loops.
//!
//! Where the flattened form would be megabytes of code, this costs about what the pieces cost
//! together and needs no code of its own per robot.

use crate::dispatch::{dispatch, Kernel, MulAdd};
use crate::tree_factor::{factor_in_place, solve, Ancestry, Tree};
use nalgebra::{SMatrix, SVector};

/// `D` factored along the tree, in place, with its inverse pivots.
struct Factored<'a, const N: usize> {
    tree: &'a Tree<N>,
    l: SMatrix<f64, N, N>,
    inverse_pivots: [f64; N],
}

impl<'a, const N: usize> Factored<'a, N> {
    fn new(tree: &'a Tree<N>, mut d: SMatrix<f64, N, N>) -> Self {
        let (mut pivots, mut inverse_pivots) = ([0.0; N], [0.0; N]);
        factor_in_place(tree, &mut d, &mut pivots, &mut inverse_pivots, |x| 1.0 / x);
        Factored {
            tree,
            l: d,
            inverse_pivots,
        }
    }

    /// `D⁻¹ b`.
    fn solve(&self, mut b: SVector<f64, N>) -> SVector<f64, N> {
        solve(self.tree, &self.l, &self.inverse_pivots, b.as_mut_slice());
        b
    }

    /// `−D⁻¹ B`, every column at once.
    fn solve_negated(&self, b: &SMatrix<f64, N, N>) -> SMatrix<f64, N, N> {
        let mut out = SMatrix::zeros();
        dispatch::<SolveNegated, _>((self, b, &mut out));
        out
    }
}

/// `−D⁻¹ B` for a square `B` (column-major, as the robot's functions return it), in rows: row
/// `k` holds coordinate `k`'s unknown in every right-hand side, so each step of the sweeps of
/// [`solve`] is a multiply-add over every right-hand side at once, which the processor's vector
/// unit runs (hence a kernel, compiled with its features, [`dispatch`]). Each row is updated in
/// a local array the compiler keeps in registers, and written back once.
struct SolveNegated;

impl<'a, const N: usize> Kernel<(&Factored<'a, N>, &SMatrix<f64, N, N>, &mut SMatrix<f64, N, N>)>
    for SolveNegated
{
    type Output = ();

    #[inline(always)]
    fn run<A: MulAdd>(
        arith: A,
        (factored, b, out): (&Factored<'a, N>, &SMatrix<f64, N, N>, &mut SMatrix<f64, N, N>),
    ) {
        let (tree, l) = (factored.tree, &factored.l);
        let columns = &b.data.0;
        let mut rows = [[0.0; N]; N];
        for (k, row) in rows.iter_mut().enumerate() {
            for (x, column) in row.iter_mut().zip(columns) {
                *x = -column[k];
            }
        }
        // `Lᵀ y = b` from the leaves up, each row once with the terms of its descendants (in
        // the order the one-column sweep subtracts them, from the last coordinate down).
        for i in (0..N).rev() {
            let descendants = tree.descendants(i);
            let Some((&first, rest)) = descendants.split_first() else {
                continue;
            };
            let (l_first, from) = (-l[(first, i)], &rows[first]);
            let mut row: [f64; N] = core::array::from_fn(|j| arith.mul_add(l_first, from[j], rows[i][j]));
            for &k in rest {
                let l_ki = -l[(k, i)];
                for (to, &from) in row.iter_mut().zip(&rows[k]) {
                    *to = arith.mul_add(l_ki, from, *to);
                }
            }
            for (to, from) in rows[i].iter_mut().zip(row) {
                *to = from;
            }
        }
        // `Δ⁻¹`, then `L x = z` from the root down, each row's ancestors' terms root first.
        for k in 0..N {
            let inverse = factored.inverse_pivots[k];
            let mut row: [f64; N] = core::array::from_fn(|j| rows[k][j] * inverse);
            for &i in tree.ancestors(k).iter().rev() {
                let l_ki = -l[(k, i)];
                for (to, &from) in row.iter_mut().zip(&rows[i]) {
                    *to = arith.mul_add(l_ki, from, *to);
                }
            }
            for (to, from) in rows[k].iter_mut().zip(row) {
                *to = from;
            }
        }
        for (j, column) in out.data.0.iter_mut().enumerate() {
            for (x, row) in column.iter_mut().zip(&rows) {
                *x = row[j];
            }
        }
    }
}

/// Forward dynamics `ν̇ = D⁻¹ (τ − b)` from the robot's own `D` (armature included) and
/// `free_force = τ − ID(q, ν, 0)`, solved through the tree factor of `D` (`tree`, the velocity
/// coordinates').
#[inline]
pub fn forward_dynamics<const N: usize>(
    tree: &Tree<N>,
    mass_matrix: SMatrix<f64, N, N>,
    free_force: SVector<f64, N>,
) -> SVector<f64, N> {
    Factored::new(tree, mass_matrix).solve(free_force)
}

/// `D⁻¹` from the robot's own `D` (armature included), through the tree factor of `D` (`tree`,
/// the velocity coordinates'), as `Yᵀ Δ⁻¹ Y` by rows (`InverseByAncestors`).
#[inline]
pub fn mass_matrix_inverse<const N: usize>(
    tree: &Tree<N>,
    mass_matrix: SMatrix<f64, N, N>,
) -> SMatrix<f64, N, N> {
    let factored = Factored::new(tree, mass_matrix);
    let mut out = SMatrix::zeros();
    dispatch::<InverseByAncestors, _>((&factored, &mut out));
    out
}

/// `D⁻¹ = Yᵀ Δ⁻¹ Y` with `Y = L⁻ᵀ`, whose column `a` is zero but at `a` and its ancestors: the
/// model's `inverse_by_ancestors` (there `M = L⁻¹ = Yᵀ`), by rows. `Y`'s entries come from
/// `L Yᵀ = I` over each coordinate's ancestors (`Σ depth²/2` multiply-adds); then row `a` of
/// `D⁻¹` is `Σ_c Y_ca Δ⁻¹_c Y_c` over `a` and its ancestors `c`, each term a multiply-add over
/// a whole row, which the vector unit runs. Solving the identity's columns instead (both sweeps
/// over every column) took twice as long on TIAGo Dual.
struct InverseByAncestors;

impl<'a, const N: usize> Kernel<(&Factored<'a, N>, &mut SMatrix<f64, N, N>)> for InverseByAncestors {
    type Output = ();

    #[inline(always)]
    fn run<A: MulAdd>(arith: A, (factored, out): (&Factored<'a, N>, &mut SMatrix<f64, N, N>)) {
        let (tree, l) = (factored.tree, &factored.l);
        // `y[i][a]`: row `i` of `Y`, entry `a` (`M_ai`).
        let mut y = [[0.0; N]; N];
        for a in 0..N {
            y[a][a] = 1.0;
            let chain = tree.ancestors(a);
            for (q, &i) in chain.iter().enumerate() {
                // `M_ai = −(L_ai + Σ_j L_aj M_ji)` over the coordinates `j` between `i` and `a`.
                let mut sum = l[(a, i)];
                for &j in &chain[..q] {
                    sum = arith.mul_add(l[(a, j)], y[i][j], sum);
                }
                y[i][a] = -sum;
            }
        }
        for (a, column) in out.data.0.iter_mut().enumerate() {
            // Symmetric: row `a` is column `a`.
            let scale = factored.inverse_pivots[a];
            let mut row: [f64; N] = core::array::from_fn(|b| y[a][b] * scale);
            for &c in tree.ancestors(a) {
                let scale = y[c][a] * factored.inverse_pivots[c];
                for (to, &from) in row.iter_mut().zip(&y[c]) {
                    *to = arith.mul_add(scale, from, *to);
                }
            }
            for (to, from) in column.iter_mut().zip(row) {
                *to = from;
            }
        }
    }
}

/// The derivatives of forward dynamics `(∂ν̇/∂q, ∂ν̇/∂ν)` from the robot's own `D` (armature
/// included), `free_force = τ − ID(q, ν, 0)` and its `∂τ/∂x` (`inverse_dynamics_derivatives`,
/// called at the solution): with `ν̇ = D⁻¹ (τ − b)` held by `ID(q, ν, ν̇) = τ`,
/// `∂ν̇/∂x = −D⁻¹ ∂τ/∂x` at that `ν̇`, every column solved through the tree factor of `D`.
/// `tree` is the velocity coordinates' in the factor.
#[inline]
pub fn forward_dynamics_derivatives<const N: usize>(
    tree: &Tree<N>,
    mass_matrix: SMatrix<f64, N, N>,
    free_force: SVector<f64, N>,
    inverse_dynamics_derivatives: impl FnOnce(&SVector<f64, N>) -> (SMatrix<f64, N, N>, SMatrix<f64, N, N>),
) -> (SMatrix<f64, N, N>, SMatrix<f64, N, N>) {
    let factored = Factored::new(tree, mass_matrix);
    let acceleration = factored.solve(free_force);
    let (dq, dv) = inverse_dynamics_derivatives(&acceleration);
    (factored.solve_negated(&dq), factored.solve_negated(&dv))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::SplitMix64;

    /// A trunk of three, two arms of four on it, two fingers at the end of the first.
    const TREE: Tree<13> = Tree::new(PARENTS);
    const PARENTS: [Option<usize>; 13] = [
        None,
        Some(0),
        Some(1),
        Some(2),
        Some(3),
        Some(4),
        Some(5),
        Some(6),
        Some(6),
        Some(2),
        Some(9),
        Some(10),
        Some(11),
    ];

    /// A symmetric positive definite matrix with the sparsity of `PARENTS`, `Lᵀ Δ L` of random
    /// factors.
    fn tree_matrix(rng: &mut SplitMix64) -> SMatrix<f64, 13, 13> {
        let mut l = SMatrix::<f64, 13, 13>::identity();
        for k in 0..13 {
            let mut i = PARENTS[k];
            while let Some(ii) = i {
                l[(k, ii)] = rng.uniform((-1.0, 1.0));
                i = PARENTS[ii];
            }
        }
        let pivots = SVector::<f64, 13>::from_fn(|_, _| rng.uniform((0.5, 3.0)));
        l.transpose() * SMatrix::from_diagonal(&pivots) * l
    }

    #[test]
    fn every_column_is_minus_the_solve() {
        let mut rng = SplitMix64::new(5);
        for _ in 0..20 {
            let d = tree_matrix(&mut rng);
            let b = SMatrix::<f64, 13, 13>::from_fn(|_, _| rng.uniform((-2.0, 2.0)));
            let factored = Factored::new(&TREE, d);
            let solved = factored.solve_negated(&b);
            // Against a dense solve, and against the one-column solve of the same sweeps.
            let dense = d.lu().solve(&b).expect("positive definite");
            assert!((solved + dense).amax() < 1e-11 * dense.amax());
            for c in 0..13 {
                let column = factored.solve(b.column(c).into_owned());
                assert!((solved.column(c) + column).amax() < 1e-13 * column.amax().max(1.0));
            }
        }
    }

    #[test]
    fn forward_dynamics_and_the_inverse_solve_with_d() {
        let mut rng = SplitMix64::new(13);
        let d = tree_matrix(&mut rng);
        let free_force = SVector::<f64, 13>::from_fn(|_, _| rng.uniform((-1.0, 1.0)));
        let acceleration = forward_dynamics(&TREE, d, free_force);
        assert!((d * acceleration - free_force).amax() < 1e-12);
        let inverse = mass_matrix_inverse(&TREE, d);
        assert!((inverse * d - SMatrix::<f64, 13, 13>::identity()).amax() < 1e-11);
        assert!((inverse - inverse.transpose()).amax() < 1e-12 * inverse.amax());
    }

    #[test]
    fn the_derivatives_solve_at_the_solution() {
        let mut rng = SplitMix64::new(9);
        let d = tree_matrix(&mut rng);
        let free_force = SVector::<f64, 13>::from_fn(|_, _| rng.uniform((-1.0, 1.0)));
        let derivative = SMatrix::<f64, 13, 13>::from_fn(|_, _| rng.uniform((-1.0, 1.0)));
        let mut seen = None;
        let (dq, dv) = forward_dynamics_derivatives(&TREE, d, free_force, |a| {
            seen = Some(*a);
            (derivative, 2.0 * derivative)
        });
        let acceleration = seen.expect("called once");
        assert!((d * acceleration - free_force).amax() < 1e-12);
        assert!((d * dq + derivative).amax() < 1e-11);
        assert!((d * dv + 2.0 * derivative).amax() < 1e-11);
    }
}
