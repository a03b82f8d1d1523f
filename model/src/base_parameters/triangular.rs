//! The stacked regressor compressed to its triangular factor, and the few vector operations the
//! selection needs, on plain slices.
//!
//! `Y = Q R` with orthonormal `Q` keeps everything the base parameters are computed from: the
//! columns' norms, the residual of a column after projection on others, least-squares
//! coefficients between columns and the singular values are those of `R`'s columns, which have
//! `P` entries where `Y`'s have `STATES·n` (four to five times as many). Build scripts run the
//! generator unoptimised, where nalgebra's generic loops cost about fifty times their optimised
//! time and plain slice loops a few times: the factor is computed here, once per stack, and the
//! selection then works on vectors a quarter as long.

use nalgebra::DMatrix;

/// `R` of the Householder factorisation `Y = Q R` (`min(m, n) × n`, upper triangular; a row's
/// sign may differ from another factorisation's).
pub fn triangular_factor(y: &DMatrix<f64>) -> DMatrix<f64> {
    let (m, n) = y.shape();
    let rows = m.min(n);
    let mut a: Vec<f64> = y.as_slice().to_vec();
    let mut v = vec![0.0; m];
    for k in 0..rows {
        let column = &a[k * m + k..(k + 1) * m];
        let norm = dot(column, column).sqrt();
        if norm == 0.0 {
            continue;
        }
        // The reflector that takes the column below the diagonal to `alpha e₁`, `alpha` of
        // the sign opposite to its first entry so that `v` has no cancellation.
        let alpha = if column[0] > 0.0 { -norm } else { norm };
        let v = &mut v[..m - k];
        v.copy_from_slice(column);
        v[0] -= alpha;
        let v_norm2 = dot(v, v);
        for j in k..n {
            let target = &mut a[j * m + k..(j + 1) * m];
            let s = 2.0 * dot(v, target) / v_norm2;
            axpy(-s, v, target);
        }
        a[k * m + k] = alpha;
    }
    DMatrix::from_fn(rows, n, |i, j| if i <= j { a[j * m + i] } else { 0.0 })
}

/// `Σ xᵢ yᵢ`. A `while` loop: unoptimised, a range iterator is a call per step.
pub fn dot(x: &[f64], y: &[f64]) -> f64 {
    let (mut s, mut i) = (0.0, 0);
    let len = x.len().min(y.len());
    while i < len {
        s += x[i] * y[i];
        i += 1;
    }
    s
}

/// `y ← y + a x`.
pub fn axpy(a: f64, x: &[f64], y: &mut [f64]) {
    let (mut i, len) = (0, x.len().min(y.len()));
    while i < len {
        y[i] += a * x[i];
        i += 1;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_factor_reproduces_the_gram_matrix() {
        let mut rng = dyngen_runtime::SplitMix64::new(7);
        for (m, n) in [(12, 5), (5, 9), (40, 40), (30, 8)] {
            let mut y = DMatrix::from_fn(m, n, |_, _| rng.uniform((-1.0, 1.0)));
            // A dependent column and a zero one: what the stacks hold.
            if n > 3 {
                let c = y.column(0) * 2.0 - y.column(1);
                y.set_column(2, &c);
                y.column_mut(3).fill(0.0);
            }
            let r = triangular_factor(&y);
            assert_eq!(r.shape(), (m.min(n), n));
            for i in 0..r.nrows() {
                for j in 0..i {
                    assert_eq!(r[(i, j)], 0.0);
                }
            }
            let (gram, from_r) = (y.transpose() * &y, r.transpose() * &r);
            let scale = gram.amax();
            assert!((gram - from_r).amax() <= 1e-13 * scale, "{m}×{n}");
        }
    }
}
