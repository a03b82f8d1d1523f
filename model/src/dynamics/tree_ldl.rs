//! `D = Lᵀ Δ L` along the kinematic tree on this crate's matrices: the runtime's `tree_factor`
//! (Featherstone's LTDL; why it fills in nothing is in its docs), which the algorithms trace,
//! with the solves, congruences and inverses they build on it.
//!
//! With mimic joints `D = Gᵀ D_tree G` couples the branches a mimic joint and its master sit
//! on, so it has no tree pattern: it is factored as a chain (every coordinate the "parent" of
//! the next), which is the dense `LDLᵀ` (`n³/6`; mimic robots have few coordinates).
//!
//! The pivots `Δ_k` are the inertia joint `k` feels with every joint below it free; a zero pivot
//! is a joint that moves nothing (see [`singular_joints`](super::singular_joints)). Each pivot is inverted once, so
//! flattened code has exactly `n` divisions.

use crate::model::Model;
use crate::scalar::Scalar;
use dyngen_runtime::__private::tree_factor;
use nalgebra::DMatrix;

/// Each coordinate's parent in the factor of the joints' `D`: the joint's, or with mimic joints
/// the coordinate before (a chain).
fn joint_parents(model: &Model) -> Vec<Option<usize>> {
    match model.has_mimics() {
        false => model.joints().iter().map(|j| j.parent).collect(),
        true => (0..model.dof()).map(|k| k.checked_sub(1)).collect(),
    }
}

/// Each velocity coordinate's parent in the factor of the robot's `D`: on a fixed base the
/// joints' ([`TreeLdl::factor`]); on a floating base the base's six a chain, the roots below its
/// last; with mimic joints, whose `D` couples the branches a mimic joint and its master sit on,
/// the coordinate before (the dense `LDLᵀ`).
pub fn velocity_parents(model: &Model) -> Vec<Option<usize>> {
    if model.has_mimics() {
        return (0..model.nv()).map(|k| k.checked_sub(1)).collect();
    }
    if model.floating_base().is_none() {
        return joint_parents(model);
    }
    let mut parents: Vec<Option<usize>> = (0..6).map(|k: usize| k.checked_sub(1)).collect();
    parents.extend(model.joints().iter().map(|j| Some(j.parent.map_or(5, |p| 6 + p))));
    parents
}

/// The factors of `D`: `L` below the diagonal (only ancestor entries are meaningful) and `Δ⁻¹`.
#[derive(Clone, Debug)]
pub struct TreeLdl<S> {
    /// `L_ki` at `(k, i)` for `i` an ancestor of `k`; nothing else is read.
    l: DMatrix<S>,
    inv_pivot: Vec<S>,
    /// Pivots `Δ_k`, in joint order.
    pub pivots: Vec<S>,
    ancestry: Chains,
}

/// Each coordinate's ancestors, nearest first: the tree the runtime's factorisation walks.
#[derive(Clone, Debug)]
struct Chains(Vec<Vec<usize>>);

impl Chains {
    fn of(parent: &[Option<usize>]) -> Chains {
        let chain = |k: usize| std::iter::successors(parent[k], |&i| parent[i]).collect();
        Chains((0..parent.len()).map(chain).collect())
    }
}

impl tree_factor::Ancestry for Chains {
    fn coordinates(&self) -> usize {
        self.0.len()
    }

    fn ancestors(&self, k: usize) -> &[usize] {
        &self.0[k]
    }
}

impl<S: Scalar> TreeLdl<S> {
    /// Factors `d` (the joint-space mass matrix of `model`'s tree), reading only its lower
    /// triangle.
    pub fn factor(model: &Model, d: &DMatrix<S>) -> Self {
        Self::factor_tree(joint_parents(model), d)
    }

    /// Factors `d`, whose sparsity follows `parent` (`d_ki = 0` unless one of `k`, `i` is an
    /// ancestor of the other; `parent[k] < k`), reading only its lower triangle.
    pub fn factor_tree(parent: Vec<Option<usize>>, d: &DMatrix<S>) -> Self {
        let n = parent.len();
        let ancestry = Chains::of(&parent);
        let mut h = d.clone();
        let mut inv_pivot = vec![S::zero(); n];
        let mut pivots = vec![S::zero(); n];
        tree_factor::factor_in_place(&ancestry, &mut h, &mut pivots, &mut inv_pivot, |x| S::one() / x);
        TreeLdl {
            l: h,
            inv_pivot,
            pivots,
            ancestry,
        }
    }

    /// The same factors in another scalar type (e.g. as constants of a dual number, to solve for
    /// tangents).
    pub fn map<U: Scalar>(&self, f: impl Fn(S) -> U) -> TreeLdl<U> {
        TreeLdl {
            l: self.l.map(&f),
            inv_pivot: self.inv_pivot.iter().map(|&x| f(x)).collect(),
            pivots: self.pivots.iter().map(|&x| f(x)).collect(),
            ancestry: self.ancestry.clone(),
        }
    }

    /// `x` with `D x = b`: `Lᵀ y = b` from the leaves up, `Δ⁻¹`, then `L x = z` from the root down.
    pub fn solve(&self, b: &[S]) -> Vec<S> {
        self.finish_solve(&self.solve_transposed_factor(b))
    }

    /// `Δ_k⁻¹`, in joint order.
    pub fn inv_pivot(&self) -> &[S] {
        &self.inv_pivot
    }

    /// `L⁻¹ Δ⁻¹ y`: the rest of [`TreeLdl::solve`] after its first half, so `D⁻¹ b` for `y =
    /// L⁻ᵀ b`. Solves of sums (`D⁻¹ (b + Bᵀ λ)`) can add their halves first.
    pub fn finish_solve(&self, y: &[S]) -> Vec<S> {
        let mut x = y.to_vec();
        tree_factor::finish_solve(&self.ancestry, &self.l, &self.inv_pivot, &mut x);
        x
    }

    /// `y` with `Lᵀ y = b`, from the leaves up: the first half of [`TreeLdl::solve`].
    pub fn solve_transposed_factor(&self, b: &[S]) -> Vec<S> {
        let mut x = b.to_vec();
        tree_factor::solve_transposed_factor(&self.ancestry, &self.l, &mut x);
        x
    }

    /// `(B D⁻¹ Bᵀ, D⁻¹ Bᵀ)` for rows `B` (`m × n`): with `Y = L⁻ᵀ Bᵀ` (the leaves-up half of
    /// each solve), `B D⁻¹ Bᵀ = Yᵀ Δ⁻¹ Y`, whose entry `(i, j)` sums over the coordinates both
    /// `Y` columns reach. A row that sees one branch of the tree and its ancestors keeps that
    /// pattern in `Y`, so the product of two feet' rows sums over the base alone (zeros fold
    /// away symbolically), far fewer operations than `B` times `D⁻¹ Bᵀ`. Symmetric: the upper
    /// triangle is mirrored from the lower one. `D⁻¹ Bᵀ` is finished from the same `Δ⁻¹ Y`
    /// with the same operations as [`TreeLdl::solve_matrix`].
    pub fn congruence(&self, b: &DMatrix<S>) -> (DMatrix<S>, DMatrix<S>) {
        let (m, n) = b.shape();
        let y: Vec<Vec<S>> = (0..m)
            .map(|r| self.solve_transposed_factor(&b.row(r).iter().copied().collect::<Vec<S>>()))
            .collect();
        let scaled: Vec<Vec<S>> = (y.iter())
            .map(|column| {
                column
                    .iter()
                    .zip(&self.inv_pivot)
                    .map(|(&x, &inv)| x * inv)
                    .collect()
            })
            .collect();
        let mut product = DMatrix::from_element(m, m, S::zero());
        for j in 0..m {
            for i in j..m {
                let entry = (0..n).fold(S::zero(), |sum, k| sum + y[i][k] * scaled[j][k]);
                product[(i, j)] = entry;
                product[(j, i)] = entry;
            }
        }
        let mut solved = DMatrix::from_element(n, m, S::zero());
        for (c, mut x) in scaled.into_iter().enumerate() {
            tree_factor::solve_factor(&self.ancestry, &self.l, &mut x);
            for (r, v) in x.into_iter().enumerate() {
                solved[(r, c)] = v;
            }
        }
        (product, solved)
    }

    /// `D⁻¹ B`, column by column.
    pub fn solve_matrix(&self, b: &DMatrix<S>) -> DMatrix<S> {
        let mut out = b.clone();
        for c in 0..b.ncols() {
            let col: Vec<S> = b.column(c).iter().copied().collect();
            for (r, v) in self.solve(&col).into_iter().enumerate() {
                out[(r, c)] = v;
            }
        }
        out
    }

    /// `D⁻¹ = M Δ⁻¹ Mᵀ` with `M = L⁻¹`, which keeps `L`'s ancestor pattern: entry `(a, b)` is a
    /// sum over the common ancestors of `a` and `b` (themselves included), `M` a sum over the
    /// path between each pair. Where the coordinates share a long chain (a floating base's six
    /// above every joint) this costs fewer operations than one solve per column
    /// ([`TreeLdl::inverse`]); generation keeps the cheaper.
    pub fn inverse_by_ancestors(&self) -> DMatrix<S> {
        let n = self.inv_pivot.len();
        let ancestors = &self.ancestry.0;
        // m[k][p] = M_{k, ancestors[k][p]} (M_kk = 1), rows in order so that every ancestor's
        // row is ready: L M = 1 gives M_ki = −Σ_j L_kj M_ji over j from i up to k's parent.
        let mut m: Vec<Vec<S>> = Vec::with_capacity(n);
        for (k, chain) in ancestors.iter().enumerate() {
            let mut row = Vec::with_capacity(chain.len());
            for (p, &i) in chain.iter().enumerate() {
                let mut sum = self.l[(k, i)];
                for (q, &j) in chain[..p].iter().enumerate() {
                    // i is ancestor number p − q − 1 of j (j's chain is k's after j).
                    sum = sum + self.l[(k, j)] * m[j][p - q - 1];
                }
                row.push(-sum);
            }
            m.push(row);
        }
        // Each coordinate's chain, root first, with M along it.
        let chains: Vec<Vec<(usize, S)>> = (0..n)
            .map(|k| {
                let mut chain: Vec<(usize, S)> =
                    ancestors[k].iter().copied().zip(m[k].iter().copied()).collect();
                chain.reverse();
                chain.push((k, S::one()));
                chain
            })
            .collect();
        let mut out = DMatrix::from_element(n, n, S::zero());
        for a in 0..n {
            for b in 0..=a {
                let mut sum: Option<S> = None;
                for (&(ca, ma), &(cb, mb)) in chains[a].iter().zip(&chains[b]) {
                    if ca != cb {
                        break;
                    }
                    // M_ac Δ⁻¹_c M_bc, with the unit diagonal of M written as no factor.
                    let mut term = self.inv_pivot[ca];
                    if ca != a {
                        term = ma * term;
                    }
                    if cb != b {
                        term = term * mb;
                    }
                    sum = Some(match sum {
                        None => term,
                        Some(s) => s + term,
                    });
                }
                let value = sum.unwrap_or_else(S::zero);
                out[(a, b)] = value;
                out[(b, a)] = value;
            }
        }
        out
    }

    /// `D⁻¹ = L⁻¹ Δ⁻¹ L⁻ᵀ`, symmetric. Column `c` of `L⁻ᵀ` is non-zero only on `c` and its
    /// ancestors, so the solves start sparse (zeros fold away symbolically); the upper triangle
    /// is mirrored from the lower one, which the tracer then never computes twice.
    pub fn inverse(&self) -> DMatrix<S> {
        let n = self.inv_pivot.len();
        let mut out = DMatrix::from_element(n, n, S::zero());
        for c in 0..n {
            let mut e = vec![S::zero(); n];
            e[c] = S::one();
            let col = self.solve(&e);
            for r in c..n {
                out[(r, c)] = col[r];
                out[(c, r)] = col[r];
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A symmetric positive definite matrix with the sparsity of `parent` (entries only between
    /// a coordinate and its ancestors), from `Lᵀ Δ L` with random factors.
    fn tree_matrix(parent: &[Option<usize>], seed: u64) -> DMatrix<f64> {
        let n = parent.len();
        let mut rng = dyngen_runtime::SplitMix64::new(seed);
        let mut l = DMatrix::<f64>::identity(n, n);
        for k in 0..n {
            let mut i = parent[k];
            while let Some(ii) = i {
                l[(k, ii)] = rng.uniform((-1.0, 1.0));
                i = parent[ii];
            }
        }
        let pivots = DMatrix::from_diagonal(&nalgebra::DVector::from_fn(n, |_, _| rng.uniform((0.5, 3.0))));
        l.transpose() * pivots * l
    }

    #[test]
    fn the_inverse_by_common_ancestors_is_the_inverse() {
        // A floating base's six coordinates in a chain, two legs of three and a branch of one.
        let parents: Vec<Option<usize>> = vec![
            None,
            Some(0),
            Some(1),
            Some(2),
            Some(3),
            Some(4),
            Some(5),
            Some(6),
            Some(7),
            Some(5),
            Some(9),
            Some(10),
            Some(9),
        ];
        for seed in 0..20 {
            let d = tree_matrix(&parents, seed);
            let factor = TreeLdl::factor_tree(parents.clone(), &d);
            let by_solves = factor.inverse();
            let by_ancestors = factor.inverse_by_ancestors();
            assert!(
                (&by_ancestors - &by_solves).amax() < 1e-12 * by_solves.amax(),
                "seed {seed}"
            );
            assert!(
                (by_ancestors * &d - DMatrix::identity(13, 13)).amax() < 1e-10,
                "seed {seed}"
            );
        }
    }

    #[test]
    fn the_congruence_is_rows_times_the_solves() {
        // Two legs of three on a six-coordinate chain, a chain alone and a single coordinate;
        // rows that see one leg and the base, both legs, and rows that are dense or repeated.
        let legs: Vec<Option<usize>> = (0..12)
            .map(|k: usize| match k {
                0 => None,
                9 => Some(5),
                _ => Some(k - 1),
            })
            .collect();
        let chain: Vec<Option<usize>> = (0..7).map(|k: usize| k.checked_sub(1)).collect();
        for (parents, seed) in [(legs, 3), (chain, 5), (vec![None], 7)] {
            let n = parents.len();
            let d = tree_matrix(&parents, seed);
            let factor = TreeLdl::factor_tree(parents, &d);
            let mut rng = dyngen_runtime::SplitMix64::new(seed + 1);
            let mut rows = DMatrix::from_fn(5, n, |_, _| rng.uniform((-1.0, 1.0)));
            // One row on the first leg alone, one repeated (K singular, still symmetric).
            for k in 9.min(n)..n {
                rows[(0, k)] = 0.0;
            }
            let repeated = rows.row(1).into_owned();
            rows.set_row(4, &repeated);
            let (product, solved) = factor.congruence(&rows);
            let inverse = d.clone().try_inverse().expect("positive definite");
            let expected_solved = &inverse * rows.transpose();
            let expected = &rows * &expected_solved;
            assert!((&solved - &expected_solved).amax() <= 1e-10 * expected_solved.amax());
            assert!((&product - &expected).amax() <= 1e-10 * expected.amax());
            assert_eq!(product, product.transpose(), "symmetric");
            // The same operations as the solves: equal to the last bit.
            assert_eq!(solved, factor.solve_matrix(&rows.transpose()));
        }
    }
}
