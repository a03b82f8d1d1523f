//! Base (minimal, identifiable) inertial parameters.
//!
//! Of the ten standard parameters per body, some never affect the joint torques and others act
//! only in fixed combinations. The base parameters are a maximal set of independent columns of
//! the regressor `Y` (independent over all states), and `θ_b = θ₁ + β θ₂` folds every other
//! parameter into them, where `Y₂ = Y₁ β` are the dependent columns in terms of the kept ones.
//! Then `Y_b θ_b = Y₁ θ₁ + Y₁ β θ₂ = Y θ` with `Y_b = Y₁`, for every state and every θ.
//!
//! How (all deterministic: fixed seeds, a fixed order, no hash maps):
//! 1. `Y` of the generic `f64` dynamics, stacked at [`STATES`] random states (seed
//!    [`SELECTION_SEED`]; `v ≠ q̇`, gravity on): `10·STATES` rows per joint, four times as many
//!    rows as parameters; the steps below work on its triangular factor `R` (`Y = Q R`, `Q`
//!    orthonormal), whose columns have the same norms, residuals, least-squares coefficients
//!    and singular values in a quarter of the length (`triangular.rs`).
//! 2. Columns scaled to unit norm (masses, first moments and inertias differ in units); zero
//!    columns ([`rank::ZERO_COLUMN_TOL`]) dropped.
//! 3. Forward greedy selection in parameter order, body after body, within a body
//!    `[m, mcx, mcy, mcz, Ixx, Ixy, Iyy, Ixz, Iyz, Izz]`: a column is kept iff its relative
//!    residual after projection on the kept ones exceeds [`INDEPENDENCE_TOL`]. Parents come
//!    first, so parents absorb their children's parameters: the classical grouping of Gautier
//!    and Khalil (e.g. the mass of a body folds into its parent's inertia and first moments).
//! 4. `β` by least squares (SVD, one step of iterative refinement), then cleaned: entries that
//!    are zero to rounding error become 0, entries within rounding error of an integer or of a
//!    short decimal (products of the description's decimal lengths, e.g. `0.0625 = 0.25²`) become
//!    that exact value. A cleaned column of `β` is accepted only if `Y₂ = Y₁ β` still holds to
//!    [`VERIFICATION_TOL`] on a second, independent stack of states ([`VERIFICATION_SEED`]), as
//!    well as the computed one does; failing that (a near-exact description, whose real
//!    coefficients can be 10⁻¹¹), only the entries below [`NEGLIGIBLE_COEFFICIENT_TOL`] are
//!    zeroed (and the rest snapped where that still verifies); otherwise that column stays as
//!    computed.
//! 5. Cross-check: the number kept equals the SVD numerical rank of the scaled stack
//!    ([`SVD_RANK_TOL`]); [`Diagnostics`] records both and the gap between kept and dropped.

mod names;
#[doc(hidden)]
pub mod rank;
mod triangular;

use names::base_parameter_name;
pub use rank::ZERO_COLUMN_TOL;
use rank::{column_norms, numerical_rank, relative_residual, stacked_regressor};
use triangular::triangular_factor;

use crate::dynamics::FloatingDynamics;
use crate::model::Model;
use nalgebra::DMatrix;

/// Random states stacked per model: `STATES·n` rows for `10·n` columns.
pub const STATES: usize = 40;
/// Seed of the states the columns are selected on.
pub const SELECTION_SEED: u64 = 0xBA5E_0000_0000_0001;
/// Seed of the independent states the cleaned coefficients are verified on.
pub const VERIFICATION_SEED: u64 = 0xBA5E_0000_0000_0002;

/// A unit-norm column is independent of the kept ones iff the part orthogonal to them is longer
/// than this. A dependent column's residual is rounding error, a modest multiple of `ε ≈ 2e-16`
/// (measured: at most 1.3e-14 on arm7, Panda and UR5, 1.3e-12 on 256 random trees of up to 10
/// joints); an independent column's is a sizeable fraction of one (at least 0.55 on the
/// reference arms, 2.7e-4 on the random trees). `√ε ≈ 1.5e-8` lies roughly in the middle of
/// that gap on a logarithmic scale, so the decision does not hinge on rounding or on how the
/// random states fall. `tests/base_parameters.rs` prints these figures.
pub const INDEPENDENCE_TOL: f64 = 1e-8;

/// SVD cross-check: singular values of the column-scaled stack above `SVD_RANK_TOL·σ_max`
/// count. The same √ε gap argument as [`INDEPENDENCE_TOL`] (rounding gives ~1e-15·σ_max).
pub const SVD_RANK_TOL: f64 = 1e-8;

/// A folding coefficient whose contribution relative to the dependent column is below this
/// (in unit-norm column scale) is rounding error and becomes exactly 0 (subject to verification).
pub const ZERO_COEFFICIENT_TOL: f64 = 1e-10;

/// A folding coefficient whose contribution relative to the dependent column is below this is
/// rounding noise of the least squares even where the other coefficients cannot be cleaned (a
/// near-exact description, `1.5708`, has real coefficients of 10⁻¹¹ beside noise of 10⁻¹⁷): it
/// becomes exactly 0 when the column still verifies as well as with it. Left in, a noise term
/// makes the folded column a sum over base columns it has nothing to do with.
pub const NEGLIGIBLE_COEFFICIENT_TOL: f64 = 1e-14;

/// Cleaned coefficients must reproduce each dependent column on fresh states to this relative
/// residual (relative to the size of the terms that cancel).
pub const VERIFICATION_TOL: f64 = 1e-12;

/// How much larger than the computed coefficients' residual a cleaned candidate's may be: rounding
/// of the verification itself, not a different robot.
const CLEANING_SLACK: f64 = 16.0;

/// Most decimals a coefficient is snapped to (products of two lengths given to six decimals).
const MAX_SNAP_DECIMALS: i32 = 12;

/// Numbers that show how clear-cut the selection was.
#[derive(Clone, Debug, PartialEq)]
pub struct Diagnostics {
    /// SVD numerical rank of the scaled stacked regressor (must equal the base count).
    pub svd_rank: usize,
    /// Smallest relative residual of a kept column (large: clearly independent).
    pub smallest_kept_residual: f64,
    /// Largest relative residual of a dropped non-zero column (tiny: clearly dependent).
    pub largest_dropped_residual: f64,
    /// Worst relative residual of `Y₂ − Y₁ β` on the verification states, after cleaning.
    pub verification_residual: f64,
    /// Coefficients set to exactly 0 (rounding-level values of least squares).
    pub zeroed: usize,
    /// Non-zero coefficients that are exact: integers or short decimals (geometry).
    pub exact: usize,
    /// Non-zero coefficients left as computed (no exact value reproduced the columns).
    pub inexact: usize,
    /// Dependent columns whose cleaned coefficients failed verification (kept as computed).
    pub uncleaned_columns: usize,
}

/// The base parameters of one model.
#[derive(Clone, Debug, PartialEq)]
pub struct BaseParameterSet {
    /// Number of standard parameters (`10·n`, plus the joint-level ones).
    pub standard_count: usize,
    /// The standard parameters (regressor columns) kept, ascending: `Y_b` is these columns of `Y`.
    pub columns: Vec<usize>,
    /// `θ_b[k] = Σ c·θ[i]` over `terms[k]`, pairs `(i, c)`: first `(columns[k], 1)`, then the
    /// folded parameters in ascending order.
    pub terms: Vec<Vec<(usize, f64)>>,
    /// Readable names, e.g. `"Izz[link2] + Iyy[link3] + 0.0625·m[link3] + …"`.
    pub names: Vec<String>,
    pub diagnostics: Diagnostics,
}

/// Names of the standard parameters, the regressor's columns: on a floating base, the base
/// body's ten first.
fn standard_names(model: &Model) -> Vec<String> {
    match model.floating_base() {
        Some(_) => FloatingDynamics::parameter_names(model),
        None => model.parameter_names(),
    }
}

/// Nearest "exact" value to `x` (an integer, or a decimal with at most [`MAX_SNAP_DECIMALS`]
/// decimals) when `x` is within rounding error of it, with few decimals preferred.
fn snap(x: f64) -> Option<f64> {
    for d in 0..=MAX_SNAP_DECIMALS {
        let scale = 10f64.powi(d);
        let candidate = (x * scale).round() / scale;
        // Within rounding error of x, and far closer than the grid spacing (so not by chance).
        let close = (x - candidate).abs() <= 1e-11 * x.abs().max(1e-300);
        let on_grid = (x - candidate).abs() <= 1e-4 / scale;
        if close && on_grid {
            return Some(candidate);
        }
    }
    None
}

impl BaseParameterSet {
    /// Computes the base parameters of `model` (see the module documentation).
    pub fn compute(model: &Model) -> BaseParameterSet {
        let p = standard_names(model).len();
        // The selection, the rank and the verification on the stacks' triangular factors: the
        // same norms and residuals on vectors of `P` entries (`triangular.rs`). The folding
        // coefficients from the stack itself: the factor's own rounding (a few `ε` per column)
        // would reach the coefficients of a near-exact description (`1.5708`), whose real
        // values can be 1e-11.
        let stack = stacked_regressor(model, STATES, SELECTION_SEED);
        let y = triangular_factor(&stack);
        let selection = rank::greedy_selection(&y, INDEPENDENCE_TOL);
        let (kept, dependent) = (&selection.kept, &selection.dependent);
        let beta = rank::folding_coefficients(&stack, kept, dependent);
        let fresh = triangular_factor(&stacked_regressor(model, STATES, VERIFICATION_SEED));
        let norms = column_norms(&y);
        let mut diagnostics = Diagnostics {
            svd_rank: numerical_rank(&y, SVD_RANK_TOL),
            smallest_kept_residual: selection.smallest_kept_residual,
            largest_dropped_residual: selection.largest_dropped_residual,
            verification_residual: 0.0,
            zeroed: 0,
            exact: 0,
            inexact: 0,
            uncleaned_columns: 0,
        };
        // Folding coefficients of each dependent column: (kept column, coefficient).
        let mut folded: Vec<Vec<(usize, f64)>> = Vec::with_capacity(dependent.len());
        for (d, &j) in dependent.iter().enumerate() {
            let raw: Vec<(usize, f64)> = kept.iter().enumerate().map(|(k, &c)| (c, beta[(k, d)])).collect();
            let is_zero = |c: usize, x: f64| (x * norms[c] / norms[j]).abs() <= ZERO_COEFFICIENT_TOL;
            let zeroed: Vec<(usize, f64)> = raw.iter().filter(|&&(c, x)| !is_zero(c, x)).cloned().collect();
            let snapped = |t: &[(usize, f64)]| -> Vec<(usize, f64)> {
                t.iter().map(|&(c, x)| (c, snap(x).unwrap_or(x))).collect()
            };
            let exact = snapped(&zeroed);
            let is_negligible =
                |c: usize, x: f64| (x * norms[c] / norms[j]).abs() <= NEGLIGIBLE_COEFFICIENT_TOL;
            let trimmed: Vec<(usize, f64)> = raw
                .iter()
                .filter(|&&(c, x)| !is_negligible(c, x))
                .cloned()
                .collect();
            let trimmed_exact = snapped(&trimmed);
            // A cleaned candidate must reproduce the column as well as the computed coefficients
            // do, up to rounding: on a description whose angles are near-exact (`1.5708`), a
            // coefficient can be within 1e-11 of a short decimal without being it, and snapping
            // it would make `θ'` a slightly different robot.
            let raw_residual = relative_residual(&fresh, j, &raw);
            let acceptable =
                |r: f64| r <= VERIFICATION_TOL && r <= CLEANING_SLACK * raw_residual.max(f64::EPSILON);
            let candidates = [exact, zeroed, trimmed_exact, trimmed, raw];
            let chosen = candidates
                .iter()
                .map(|t| (t, relative_residual(&fresh, j, t)))
                .find(|(_, r)| acceptable(*r));
            let (terms, residual) = match chosen {
                Some((t, r)) => (t.clone(), r),
                None => {
                    diagnostics.uncleaned_columns += 1;
                    let raw = &candidates[4];
                    (raw.clone(), relative_residual(&fresh, j, raw))
                }
            };
            diagnostics.verification_residual = diagnostics.verification_residual.max(residual);
            diagnostics.zeroed += kept.len() - terms.len();
            for &(_, x) in &terms {
                match snap(x) == Some(x) {
                    true => diagnostics.exact += 1,
                    false => diagnostics.inexact += 1,
                }
            }
            folded.push(terms);
        }
        let terms: Vec<Vec<(usize, f64)>> = kept
            .iter()
            .map(|&c| {
                let mut t = vec![(c, 1.0)];
                for (d, &j) in dependent.iter().enumerate() {
                    if let Some(&(_, x)) = folded[d].iter().find(|&&(k, x)| k == c && x != 0.0) {
                        t.push((j, x));
                    }
                }
                t
            })
            .collect();
        let standard_names = standard_names(model);
        let names = terms
            .iter()
            .map(|t| base_parameter_name(t, &standard_names))
            .collect();
        BaseParameterSet {
            standard_count: p,
            columns: kept.clone(),
            terms,
            names,
            diagnostics,
        }
    }

    /// Every standard parameter its own base parameter, nothing folded.
    pub fn unreduced(names: Vec<String>) -> BaseParameterSet {
        let count = names.len();
        BaseParameterSet {
            standard_count: count,
            columns: (0..count).collect(),
            terms: (0..count).map(|i| vec![(i, 1.0)]).collect(),
            names,
            diagnostics: Diagnostics {
                svd_rank: count,
                smallest_kept_residual: 1.0,
                largest_dropped_residual: 0.0,
                verification_residual: 0.0,
                zeroed: 0,
                exact: 0,
                inexact: 0,
                uncleaned_columns: 0,
            },
        }
    }

    /// Number of base parameters `p_b`.
    pub fn count(&self) -> usize {
        self.columns.len()
    }

    /// `θ_b` from the standard parameters θ (ten per body).
    pub fn base_parameters(&self, theta: &[f64]) -> Vec<f64> {
        assert_eq!(theta.len(), self.standard_count, "θ has the wrong length");
        self.terms
            .iter()
            .map(|t| t.iter().map(|&(i, c)| c * theta[i]).sum())
            .collect()
    }

    /// The standard parameter vector that holds `θ_b` on the kept columns and 0 on every folded
    /// one. It has the same dynamics as θ (`Y θ' = Y_b θ_b = Y θ` at every state), so every
    /// quantity computed from it equals the one from θ; with the folded parameters at exactly 0,
    /// whole terms of the algorithms vanish (the customised models of Khalil and Kleinfinger).
    /// Its "bodies" need not be physical (a body may have zero mass and a first moment).
    pub fn representative(&self, theta: &[f64]) -> Vec<f64> {
        let mut out = vec![0.0; self.standard_count];
        for (&c, value) in self.columns.iter().zip(self.base_parameters(theta)) {
            out[c] = value;
        }
        out
    }

    /// `Y_b` from `Y` (its kept columns), for the numeric path.
    pub fn base_regressor(&self, y: &DMatrix<f64>) -> DMatrix<f64> {
        y.select_columns(self.columns.iter())
    }
}
