//! `D = Lᵀ Δ L` along a kinematic tree (Featherstone's LTDL, RBDA §6.5) and its solves, generic
//! over the scalar: the model runs them on numbers and on symbols (the flattened code of forward
//! dynamics and `D⁻¹` is their trace), and a robot whose functions are composed from smaller
//! generated ones runs them on numbers, over its constant table of coordinate parents.
//!
//! `L` is unit lower triangular with `L_ki ≠ 0` only when coordinate `i` is an ancestor of `k`,
//! so the factorisation fills in nothing and costs `Σ_k depth(k)²/2` multiplications instead of
//! `n³/6` on branched trees (a chain is a dense `LDLᵀ`). Eliminating from the leaves up keeps it
//! inside that pattern. Parents come before their children (`parent[k] < k`).
//!
//! The unknowns of a solve are [`Unknowns`]: one number per coordinate, or with [`Rows`] one row
//! of many right-hand sides per coordinate, so that each step of the solve is a contiguous
//! multiply-add over every right-hand side at once (the derivatives of forward dynamics solve
//! `2 nv` of them).

use core::ops::{Index, IndexMut, Mul, Sub};
use nalgebra::SMatrix;

/// The unknowns of a solve, one per coordinate.
pub trait Unknowns<T> {
    /// `x_to ← x_to − l x_from`.
    fn subtract(&mut self, to: usize, l: T, from: usize);
    /// `x_k ← x_k s`.
    fn scale(&mut self, k: usize, s: T);
}

impl<T: Copy + Sub<Output = T> + Mul<Output = T>> Unknowns<T> for [T] {
    #[inline]
    fn subtract(&mut self, to: usize, l: T, from: usize) {
        self[to] = self[to] - l * self[from];
    }

    #[inline]
    fn scale(&mut self, k: usize, s: T) {
        self[k] = self[k] * s;
    }
}

/// `M` right-hand sides solved at once: column `k` of the matrix holds coordinate `k`'s unknown
/// in each of them (the transpose of the right-hand sides), contiguous in memory.
pub struct Rows<'a, const M: usize, const N: usize>(pub &'a mut SMatrix<f64, M, N>);

impl<const M: usize, const N: usize> Unknowns<f64> for Rows<'_, M, N> {
    #[inline]
    fn subtract(&mut self, to: usize, l: f64, from: usize) {
        let data = self.0.as_mut_slice();
        // Parents come first, but a solve subtracts both ways: split at the larger index.
        let (low, high) = data.split_at_mut(to.max(from) * M);
        let (to, from) = match to < from {
            true => (&mut low[to * M..(to + 1) * M], &high[..M]),
            false => (&mut high[..M], &low[from * M..(from + 1) * M]),
        };
        for (t, &f) in to.iter_mut().zip(from) {
            *t -= l * f;
        }
    }

    #[inline]
    fn scale(&mut self, k: usize, s: f64) {
        for x in &mut self.0.as_mut_slice()[k * M..(k + 1) * M] {
            *x *= s;
        }
    }
}

/// Factors `h` in place, reading only its lower triangle, whose sparsity follows `parent`
/// (`h_ki = 0` unless one of `k`, `i` is an ancestor of the other): afterwards `h[(k, i)]` is
/// `L_ki` for each ancestor `i` of `k`, and `pivots`, `inverse_pivots` hold `Δ_k` and
/// `invert(Δ_k)`. A zero pivot is a coordinate that moves nothing; its inverse is the caller's.
pub fn factor_in_place<T, H>(
    parent: &[Option<usize>],
    h: &mut H,
    pivots: &mut [T],
    inverse_pivots: &mut [T],
    invert: impl Fn(T) -> T,
) where
    T: Copy + Sub<Output = T> + Mul<Output = T>,
    H: IndexMut<(usize, usize), Output = T> + ?Sized,
{
    for k in (0..parent.len()).rev() {
        // Row k already holds every update from k's descendants (larger indices).
        pivots[k] = h[(k, k)];
        let inverse = invert(h[(k, k)]);
        inverse_pivots[k] = inverse;
        let mut i = parent[k];
        while let Some(ii) = i {
            let a = h[(k, ii)] * inverse;
            let mut j = Some(ii);
            while let Some(jj) = j {
                h[(ii, jj)] = h[(ii, jj)] - a * h[(k, jj)];
                j = parent[jj];
            }
            h[(k, ii)] = a;
            i = parent[ii];
        }
    }
}

/// `x ← y` with `Lᵀ y = x`, from the leaves up: the first half of [`solve`].
pub fn solve_transposed_factor<T, L, X>(parent: &[Option<usize>], l: &L, x: &mut X)
where
    T: Copy,
    L: Index<(usize, usize), Output = T> + ?Sized,
    X: Unknowns<T> + ?Sized,
{
    for k in (0..parent.len()).rev() {
        let mut i = parent[k];
        while let Some(ii) = i {
            x.subtract(ii, l[(k, ii)], k);
            i = parent[ii];
        }
    }
}

/// `x ← L⁻¹ Δ⁻¹ x`: the rest of [`solve`] after [`solve_transposed_factor`], so `D⁻¹ b` for `x =
/// L⁻ᵀ b`. Solves of sums can add their halves first.
pub fn finish_solve<T, L, X>(parent: &[Option<usize>], l: &L, inverse_pivots: &[T], x: &mut X)
where
    T: Copy,
    L: Index<(usize, usize), Output = T> + ?Sized,
    X: Unknowns<T> + ?Sized,
{
    for (k, &inverse) in inverse_pivots.iter().enumerate() {
        x.scale(k, inverse);
    }
    solve_factor(parent, l, x);
}

/// `x ← L⁻¹ x`, from the root down: the last step of [`solve`].
pub fn solve_factor<T, L, X>(parent: &[Option<usize>], l: &L, x: &mut X)
where
    T: Copy,
    L: Index<(usize, usize), Output = T> + ?Sized,
    X: Unknowns<T> + ?Sized,
{
    for k in 0..parent.len() {
        subtract_ancestors(parent, l, x, k, parent[k]);
    }
}

/// `x_k ← x_k − Σ L_ki x_i` over the ancestors `i` of `k` from `ancestor` up, the root's term
/// first: the parent's `x` is the last to be ready, so its term comes last and each row adds one
/// multiply-add to the chain of dependent operations instead of its depth (the Panda's forward
/// dynamics: 21 dependent multiply-adds in this sweep → 7).
fn subtract_ancestors<T, L, X>(parent: &[Option<usize>], l: &L, x: &mut X, k: usize, ancestor: Option<usize>)
where
    T: Copy,
    L: Index<(usize, usize), Output = T> + ?Sized,
    X: Unknowns<T> + ?Sized,
{
    if let Some(i) = ancestor {
        subtract_ancestors(parent, l, x, k, parent[i]);
        x.subtract(k, l[(k, i)], i);
    }
}

/// `x ← D⁻¹ x` with `D` factored by [`factor_in_place`]: `Lᵀ y = x` from the leaves up, `Δ⁻¹`,
/// then `L x = z` from the root down.
pub fn solve<T, L, X>(parent: &[Option<usize>], l: &L, inverse_pivots: &[T], x: &mut X)
where
    T: Copy,
    L: Index<(usize, usize), Output = T> + ?Sized,
    X: Unknowns<T> + ?Sized,
{
    solve_transposed_factor(parent, l, x);
    finish_solve(parent, l, inverse_pivots, x);
}
