//! `D = Lᵀ Δ L` along a kinematic tree (Featherstone's LTDL, RBDA §6.5) and its solves, generic
//! over the scalar: the model runs them on numbers and on symbols (the flattened code of forward
//! dynamics and `D⁻¹` is their trace), and a robot whose functions are composed from smaller
//! generated ones runs them on numbers, over its [`Tree`], a constant it declares.
//!
//! `L` is unit lower triangular with `L_ki ≠ 0` only when coordinate `i` is an ancestor of `k`,
//! so the factorisation fills in nothing and costs `Σ_k depth(k)²/2` multiplications instead of
//! `n³/6` on branched trees (a chain is a dense `LDLᵀ`). Eliminating from the leaves up keeps it
//! inside that pattern. Parents come before their children (`parent[k] < k`).
//!
//! The loops walk each coordinate's list of ancestors ([`Ancestry`]) rather than follow parents
//! one by one: each step of such a walk waits for the load before it, which on numbers cost more
//! than the arithmetic. A solve of many right-hand sides at once, vectorised over them, is
//! `composed`'s, with the same sweeps.

use core::ops::{Index, IndexMut, Mul, Sub};

/// Each coordinate's ancestors in the tree of a factor, nearest first.
pub trait Ancestry {
    /// The number of coordinates.
    fn coordinates(&self) -> usize;
    /// The ancestors of coordinate `k`, nearest first.
    fn ancestors(&self, k: usize) -> &[usize];
}

/// A tree of at most `N` coordinates' lists, built at compile time from the parents:
/// `const TREE: Tree<35> = Tree::new([None, Some(0), …]);` in generated code.
#[derive(Clone, Debug)]
pub struct Tree<const N: usize> {
    /// `ancestors[k][..depths[k]]`: coordinate `k`'s ancestors, nearest first.
    ancestors: [[usize; N]; N],
    depths: [usize; N],
    /// `descendants[i][..counts[i]]`: the coordinates `i` is an ancestor of, last first (the
    /// order in which the sweep from the leaves meets them).
    descendants: [[usize; N]; N],
    counts: [usize; N],
}

impl<const N: usize> Tree<N> {
    /// The tree of `parent` (`parent[k] < k`).
    pub const fn new(parent: [Option<usize>; N]) -> Tree<N> {
        let mut tree = Tree {
            ancestors: [[0; N]; N],
            depths: [0; N],
            descendants: [[0; N]; N],
            counts: [0; N],
        };
        let mut k = N;
        while k > 0 {
            k -= 1;
            let mut i = parent[k];
            while let Some(ii) = i {
                tree.ancestors[k][tree.depths[k]] = ii;
                tree.depths[k] += 1;
                tree.descendants[ii][tree.counts[ii]] = k;
                tree.counts[ii] += 1;
                i = parent[ii];
            }
        }
        tree
    }

    /// The coordinates `i` is an ancestor of, the last first.
    #[inline]
    pub fn descendants(&self, i: usize) -> &[usize] {
        &self.descendants[i][..self.counts[i]]
    }
}

impl<const N: usize> Ancestry for Tree<N> {
    #[inline]
    fn coordinates(&self) -> usize {
        N
    }

    #[inline]
    fn ancestors(&self, k: usize) -> &[usize] {
        &self.ancestors[k][..self.depths[k]]
    }
}

/// Factors `h` in place, reading only its lower triangle, whose sparsity follows `tree`
/// (`h_ki = 0` unless one of `k`, `i` is an ancestor of the other): afterwards `h[(k, i)]` is
/// `L_ki` for each ancestor `i` of `k`, and `pivots`, `inverse_pivots` hold `Δ_k` and
/// `invert(Δ_k)`. A zero pivot is a coordinate that moves nothing; its inverse is the caller's.
pub fn factor_in_place<T, H>(
    tree: &(impl Ancestry + ?Sized),
    h: &mut H,
    pivots: &mut [T],
    inverse_pivots: &mut [T],
    invert: impl Fn(T) -> T,
) where
    T: Copy + Sub<Output = T> + Mul<Output = T>,
    H: IndexMut<(usize, usize), Output = T> + ?Sized,
{
    for k in (0..tree.coordinates()).rev() {
        // Row k already holds every update from k's descendants (larger indices).
        pivots[k] = h[(k, k)];
        let inverse = invert(h[(k, k)]);
        inverse_pivots[k] = inverse;
        let chain = tree.ancestors(k);
        for (p, &ii) in chain.iter().enumerate() {
            let a = h[(k, ii)] * inverse;
            for &jj in &chain[p..] {
                h[(ii, jj)] = h[(ii, jj)] - a * h[(k, jj)];
            }
            h[(k, ii)] = a;
        }
    }
}

/// `x ← y` with `Lᵀ y = x`, from the leaves up: the first half of [`solve`].
pub fn solve_transposed_factor<T, L>(tree: &(impl Ancestry + ?Sized), l: &L, x: &mut [T])
where
    T: Copy + Sub<Output = T> + Mul<Output = T>,
    L: Index<(usize, usize), Output = T> + ?Sized,
{
    for k in (0..tree.coordinates()).rev() {
        for &i in tree.ancestors(k) {
            x[i] = x[i] - l[(k, i)] * x[k];
        }
    }
}

/// `x ← L⁻¹ Δ⁻¹ x`: the rest of [`solve`] after [`solve_transposed_factor`], so `D⁻¹ b` for `x =
/// L⁻ᵀ b`. Solves of sums can add their halves first.
pub fn finish_solve<T, L>(tree: &(impl Ancestry + ?Sized), l: &L, inverse_pivots: &[T], x: &mut [T])
where
    T: Copy + Sub<Output = T> + Mul<Output = T>,
    L: Index<(usize, usize), Output = T> + ?Sized,
{
    for (x, &inverse) in x.iter_mut().zip(inverse_pivots) {
        *x = *x * inverse;
    }
    solve_factor(tree, l, x);
}

/// `x ← L⁻¹ x`, from the root down: the last step of [`solve`]. Each row's ancestors' terms
/// come root first: the parent's `x` is the last to be ready, so its term comes last and each
/// row adds one multiply-add to the chain of dependent operations instead of its depth (the
/// Panda's forward dynamics: 21 dependent multiply-adds in this sweep → 7).
pub fn solve_factor<T, L>(tree: &(impl Ancestry + ?Sized), l: &L, x: &mut [T])
where
    T: Copy + Sub<Output = T> + Mul<Output = T>,
    L: Index<(usize, usize), Output = T> + ?Sized,
{
    for k in 0..tree.coordinates() {
        for &i in tree.ancestors(k).iter().rev() {
            x[k] = x[k] - l[(k, i)] * x[i];
        }
    }
}

/// `x ← D⁻¹ x` with `D` factored by [`factor_in_place`]: `Lᵀ y = x` from the leaves up, `Δ⁻¹`,
/// then `L x = z` from the root down.
pub fn solve<T, L>(tree: &(impl Ancestry + ?Sized), l: &L, inverse_pivots: &[T], x: &mut [T])
where
    T: Copy + Sub<Output = T> + Mul<Output = T>,
    L: Index<(usize, usize), Output = T> + ?Sized,
{
    solve_transposed_factor(tree, l, x);
    finish_solve(tree, l, inverse_pivots, x);
}
