//! The dense algebra of the contact solve, written out for its sizes: the Delassus matrix
//! `K = J M⁻¹ Jᵀ`, its Cholesky factor, solves with the factor and `K⁻¹`. Contacts have a few
//! dozen rows at most; at a dozen, nalgebra's general routines (`*` through `gemm`, `Cholesky`,
//! and its `inverse`, which solves `K X = I`) took about 3× the time of these loops in a native
//! build, which the compiler specialises to a robot's fixed sizes (in the default build as long
//! for `K`, 1.4× for the factor, 3× for `K⁻¹`: here `L⁻ᵀ L⁻¹`, `L⁻¹` triangular and `K⁻¹`
//! symmetric). The factor is the lower triangle; the strict upper one is never read.

use nalgebra::allocator::Allocator;
use nalgebra::{DefaultAllocator, Dim, OMatrix, OVector};

/// `J R` (`R = M⁻¹ Jᵀ`): the Delassus matrix `K`.
pub(super) fn delassus<NV: Dim, NC: Dim>(
    jacobian: &OMatrix<f64, NC, NV>,
    response: &OMatrix<f64, NV, NC>,
) -> OMatrix<f64, NC, NC>
where
    DefaultAllocator: Allocator<NC, NC> + Allocator<NC, NV> + Allocator<NV, NC>,
{
    let (rows, inner) = jacobian.shape_generic();
    let n = rows.value();
    let mut k = OMatrix::<f64, NC, NC>::zeros_generic(rows, rows);
    for c in 0..n {
        for m in 0..inner.value() {
            let b = response[(m, c)];
            for i in 0..n {
                k[(i, c)] += jacobian[(i, m)] * b;
            }
        }
    }
    k
}

/// Factors `k = L Lᵀ` in place (`L` in the lower triangle). `Err(row)` at the first pivot
/// `L[row, row]²` that is not above `floor` (nor a number).
pub(super) fn factor_in_place<NC: Dim>(k: &mut OMatrix<f64, NC, NC>, floor: f64) -> Result<(), usize>
where
    DefaultAllocator: Allocator<NC, NC>,
{
    let n = k.nrows();
    for j in 0..n {
        let mut pivot = k[(j, j)];
        for m in 0..j {
            pivot -= k[(j, m)] * k[(j, m)];
        }
        if pivot.is_nan() || pivot <= floor {
            return Err(j);
        }
        let d = libm::sqrt(pivot);
        k[(j, j)] = d;
        for i in j + 1..n {
            let mut s = k[(i, j)];
            for m in 0..j {
                s -= k[(i, m)] * k[(j, m)];
            }
            k[(i, j)] = s / d;
        }
    }
    Ok(())
}

/// Solves `L Lᵀ x = b` in place, `L` the lower triangle of `factor`.
pub(super) fn solve_in_place<NC: Dim>(factor: &OMatrix<f64, NC, NC>, x: &mut OVector<f64, NC>)
where
    DefaultAllocator: Allocator<NC, NC> + Allocator<NC>,
{
    let n = factor.nrows();
    for j in 0..n {
        let v = x[j] / factor[(j, j)];
        x[j] = v;
        for i in j + 1..n {
            x[i] -= factor[(i, j)] * v;
        }
    }
    for j in (0..n).rev() {
        let mut s = x[j];
        for i in j + 1..n {
            s -= factor[(i, j)] * x[i];
        }
        x[j] = s / factor[(j, j)];
    }
}

/// Solves `L Lᵀ x = b` for every row of `xt` at once (each row a right-hand side `bᵀ`, replaced
/// by `xᵀ`), `L` the lower triangle of `factor`, with the arithmetic of [`solve_in_place`] on
/// each: the results are those of a solve per right-hand side to the bit. Each step updates
/// whole columns of `xt`, contiguous, so the work vectorises across the right-hand sides
/// where one solve at a time is a chain of dependent operations.
pub(super) fn solve_rows_in_place<R: Dim, NC: Dim>(
    factor: &OMatrix<f64, NC, NC>,
    xt: &mut OMatrix<f64, R, NC>,
) where
    DefaultAllocator: Allocator<NC, NC> + Allocator<R, NC>,
{
    let (rows, n) = (xt.nrows(), factor.nrows());
    let x = xt.as_mut_slice();
    for j in 0..n {
        let d = factor[(j, j)];
        let (before, after) = x.split_at_mut((j + 1) * rows);
        let column = &mut before[j * rows..];
        column.iter_mut().for_each(|v| *v /= d);
        for (i, target) in (j + 1..n).zip(after.chunks_exact_mut(rows)) {
            let l = factor[(i, j)];
            target
                .iter_mut()
                .zip(column.iter())
                .for_each(|(t, v)| *t -= l * v);
        }
    }
    for j in (0..n).rev() {
        let (before, after) = x.split_at_mut((j + 1) * rows);
        let column = &mut before[j * rows..];
        for (i, source) in (j + 1..n).zip(after.chunks_exact(rows)) {
            let l = factor[(i, j)];
            column.iter_mut().zip(source).for_each(|(t, v)| *t -= l * v);
        }
        let d = factor[(j, j)];
        column.iter_mut().for_each(|v| *v /= d);
    }
}

/// `(L Lᵀ)⁻¹ = L⁻ᵀ L⁻¹`, `L` the lower triangle of `factor`: `L⁻¹` by columns, then its
/// product with its transpose (symmetric, each entry computed once).
pub(super) fn inverse<NC: Dim>(factor: &OMatrix<f64, NC, NC>) -> OMatrix<f64, NC, NC>
where
    DefaultAllocator: Allocator<NC, NC>,
{
    let (rows, _) = factor.shape_generic();
    let n = rows.value();
    let mut l_inv = OMatrix::<f64, NC, NC>::zeros_generic(rows, rows);
    for c in 0..n {
        l_inv[(c, c)] = 1.0 / factor[(c, c)];
        for i in c + 1..n {
            let mut s = 0.0;
            for m in c..i {
                s -= factor[(i, m)] * l_inv[(m, c)];
            }
            l_inv[(i, c)] = s / factor[(i, i)];
        }
    }
    // (L⁻ᵀ L⁻¹)[i, j] = Σ_{m ≥ max(i, j)} L⁻¹[m, i] L⁻¹[m, j].
    let mut out = OMatrix::<f64, NC, NC>::zeros_generic(rows, rows);
    for j in 0..n {
        for i in j..n {
            let mut s = 0.0;
            for m in i..n {
                s += l_inv[(m, i)] * l_inv[(m, j)];
            }
            out[(i, j)] = s;
            out[(j, i)] = s;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::SplitMix64;
    use nalgebra::{DMatrix, DVector, SMatrix, SVector};

    /// Random rows `J` (`n × nv`) and the inverse of a random symmetric positive definite `M`.
    fn rows_and_mass_inverse(n: usize, nv: usize, seed: u64) -> (DMatrix<f64>, DMatrix<f64>) {
        let mut rng = SplitMix64::new(seed);
        let jacobian = DMatrix::from_fn(n, nv, |_, _| rng.uniform((-1.0, 1.0)));
        let a = DMatrix::from_fn(nv, nv, |_, _| rng.uniform((-1.0, 1.0)));
        let mass = &a * a.transpose() + DMatrix::identity(nv, nv) * 0.1;
        (jacobian, mass.try_inverse().unwrap())
    }

    fn factored(k: &DMatrix<f64>) -> DMatrix<f64> {
        let mut l = k.clone();
        factor_in_place(&mut l, 0.0).unwrap();
        l.lower_triangle()
    }

    #[test]
    fn the_factor_solve_and_inverse_satisfy_their_equations() {
        // One row to two dozen, square and wide.
        for (n, nv) in [(1, 1), (3, 7), (6, 6), (12, 18), (12, 35), (24, 30)] {
            let (jacobian, mass_inverse) = rows_and_mass_inverse(n, nv, 7 * n as u64 + nv as u64);
            let response = &mass_inverse * jacobian.transpose();
            let k = delassus(&jacobian, &response);
            let product = &jacobian * &response;
            assert!((&k - &product).amax() <= 1e-12 * product.amax(), "{n}×{nv}: K");
            let l = factored(&k);
            assert!(
                (&l * l.transpose() - &k).amax() <= 1e-12 * k.amax(),
                "{n}×{nv}: L Lᵀ = K"
            );
            let b = DVector::from_fn(n, |i, _| i as f64 - 2.5);
            let mut x = b.clone();
            solve_in_place(&l, &mut x);
            assert!(
                (&k * &x - &b).amax() <= 1e-9 * b.amax().max(1.0),
                "{n}×{nv}: K x = b"
            );
            let inverse = inverse(&l);
            let identity = DMatrix::<f64>::identity(n, n);
            assert!((&k * &inverse - &identity).amax() <= 1e-9, "{n}×{nv}: K K⁻¹ = I");
            assert_eq!(inverse, inverse.transpose(), "{n}×{nv}: K⁻¹ symmetric");
        }
    }

    #[test]
    fn the_rows_solve_is_a_solve_per_row_to_the_bit() {
        let (jacobian, mass_inverse) = rows_and_mass_inverse(12, 18, 5);
        let l = factored(&delassus(&jacobian, &(&mass_inverse * jacobian.transpose())));
        let rhs = DMatrix::from_fn(7, 12, |r, c| (r * 12 + c) as f64 * 0.37 - 9.0);
        let mut all = rhs.clone();
        solve_rows_in_place(&l, &mut all);
        for r in 0..7 {
            let mut one = rhs.row(r).transpose();
            solve_in_place(&l, &mut one);
            assert_eq!(all.row(r).transpose(), one, "row {r}");
        }
    }

    #[test]
    fn fixed_sizes_give_the_numbers_of_dynamic_ones() {
        let (jacobian, mass_inverse) = rows_and_mass_inverse(12, 18, 3);
        let response = &mass_inverse * jacobian.transpose();
        let dynamic = delassus(&jacobian, &response);
        let fixed_rows = SMatrix::<f64, 12, 18>::from_column_slice(jacobian.as_slice());
        let fixed_response = SMatrix::<f64, 18, 12>::from_column_slice(response.as_slice());
        let mut fixed = delassus(&fixed_rows, &fixed_response);
        factor_in_place(&mut fixed, 0.0).unwrap();
        assert_eq!(fixed.lower_triangle().as_slice(), factored(&dynamic).as_slice());
        let mut x = SVector::<f64, 12>::repeat(1.0);
        let mut y = DVector::<f64>::repeat(12, 1.0);
        solve_in_place(&fixed, &mut x);
        solve_in_place(&factored(&dynamic), &mut y);
        assert_eq!(x.as_slice(), y.as_slice());
    }

    #[test]
    fn a_row_the_others_fix_is_named() {
        // Row 2 is the sum of rows 0 and 1: its pivot is at rounding level.
        let (mut jacobian, mass_inverse) = rows_and_mass_inverse(5, 9, 11);
        let sum = jacobian.row(0) + jacobian.row(1);
        jacobian.set_row(2, &sum);
        let response = &mass_inverse * jacobian.transpose();
        let k = delassus(&jacobian, &response);
        let largest = k.diagonal().amax();
        assert_eq!(factor_in_place(&mut k.clone(), 1e-12 * largest), Err(2));
        // Damped, the same rows factor.
        let mut damped = &k + DMatrix::identity(5, 5) * 1e-6;
        assert_eq!(factor_in_place(&mut damped, 0.0), Ok(()));
        // Not a number is refused, never factored.
        let mut bad = k;
        bad[(0, 0)] = f64::NAN;
        assert_eq!(factor_in_place(&mut bad, 0.0), Err(0));
    }
}
