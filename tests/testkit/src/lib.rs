//! What dyngen's tests and developer commands share: random valid trees and states
//! (`random_model`), Pinocchio's reference values (`fixture`), oracles that use no dynamics
//! algorithm (`oracles`), the loader fuzzer (`fuzz`), models written back as YAML/URDF
//! (`serialize`), the scale models (`scale`), scratch directories (`scratch`), and tolerant
//! comparisons. A library rather than
//! a `tests/common` module, so that `cargo xtask fuzz` and `cargo xtask scale` call it directly.

pub mod allocations;
pub mod double_double;
pub mod fixture;
pub mod floating_fixture;
pub mod frame_fixture;
pub mod fuzz;
pub mod joint_terms;
pub mod oracles;
pub mod random_model;
pub mod reference_solve;
pub mod scale;
pub mod scratch;
pub mod serialize;
pub mod traced;

use nalgebra::DMatrix;

/// Largest entry-wise difference, relative to the largest entry of `expected` (at least 1).
pub fn relative_error(actual: &DMatrix<f64>, expected: &DMatrix<f64>) -> f64 {
    assert_eq!(actual.shape(), expected.shape(), "shapes differ");
    let scale = expected.amax().max(1.0);
    (actual - expected).amax() / scale
}

/// Asserts `actual ≈ expected` to `tol` relative, naming the quantity on failure.
pub fn assert_close(what: &str, actual: &DMatrix<f64>, expected: &DMatrix<f64>, tol: f64) {
    let err = relative_error(actual, expected);
    assert!(
        err <= tol,
        "{what}: relative error {err:.3e} > {tol:.0e}\nactual:\n{actual:.12}\nexpected:\n{expected:.12}"
    );
}

pub fn column(v: &[f64]) -> DMatrix<f64> {
    DMatrix::from_column_slice(v.len(), 1, v)
}

/// Numerical rank of `m` after scaling its columns to unit norm (zero columns left out), with
/// the tolerance of the base-parameter selection (1e-8 of the largest singular value), computed
/// here independently of the code under test.
pub fn scaled_rank(m: &DMatrix<f64>) -> (usize, Vec<f64>) {
    let largest = m.column_iter().map(|c| c.norm()).fold(0.0, f64::max);
    let cols: Vec<_> = m
        .column_iter()
        .filter(|c| c.norm() > 1e-11 * largest)
        .map(|c| c / c.norm())
        .collect();
    let scaled = DMatrix::from_columns(&cols);
    let mut s: Vec<f64> = scaled.singular_values().iter().cloned().collect();
    s.sort_by(|a, b| b.total_cmp(a));
    let rank = s.iter().filter(|&&x| x > 1e-8 * s[0]).count();
    (rank, s)
}

/// The workspace root (this crate sits two levels below it, in `tests/testkit`).
pub fn workspace_root() -> &'static std::path::Path {
    std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
}
