//! Scale: long chains and branching trees generate, and the operation counts of `D`, `g`, `J`
//! and `τ` grow no worse than quadratically with the number of joints.
//!
//! Operation counts are deterministic (the same model gives the same graph), so the growth
//! exponent is a legitimate test, unlike a timing. `cargo xtask scale` prints the table of
//! TESTING.md: generation time, code size and operation counts per function.

use dyngen_codegen::model::Model;
use dyngen_testkit::scale::{chain, exponent, exponents, tree, NAMES};

#[test]
fn exponent_fit_is_right() {
    let quadratic: Vec<(f64, f64)> = (1..6).map(|n| (n as f64, 3.0 * (n * n) as f64)).collect();
    assert!((exponent(&quadratic) - 2.0).abs() < 1e-12);
}

#[test]
fn op_counts_of_d_g_j_tau_grow_at_most_quadratically() {
    for (what, build, dofs) in [
        (
            "chain",
            chain as fn(usize) -> Model,
            &[6usize, 12, 18, 24, 30][..],
        ),
        ("tree", tree as fn(usize) -> Model, &[8usize, 12, 16, 20][..]),
    ] {
        let (fit, counts) = exponents(build, dofs);
        for (k, name) in NAMES.iter().enumerate() {
            let per_dof: Vec<usize> = counts.iter().map(|c| c[k]).collect();
            assert!(
                fit[k] <= 2.0,
                "{what}: operations of {name} grow as n^{:.2}: {per_dof:?} at n = {dofs:?}",
                fit[k]
            );
        }
    }
}
