//! The solve shared by constrained forward dynamics, impacts and the operational-space
//! inertia, for any sizes: fixed (generated robots, no allocation) or dynamic (the generic
//! dynamics).
//!
//! With `J` the stacked rows, `a_free = M⁻¹ (τ − b)` and `M⁻¹ Jᵀ` given, the Delassus matrix
//! `K = J M⁻¹ Jᵀ` is regularised by `μ` and the multipliers refined by proximal iterations,
//! `λ_k = (K + μ I)⁻¹ (rhs − J a_free + μ λ_{k−1})`, `a = a_free + M⁻¹ Jᵀ λ`. They converge to
//! the exact solution of `J a = rhs` where the rows are independent, and, where they are
//! redundant, to the solution whose forces are smallest.

use super::dense;
use crate::Pose;
use core::fmt;
use nalgebra::allocator::Allocator;
use nalgebra::{DefaultAllocator, Dim, OMatrix, OVector};

/// The proximal solve: `mu` regularises the Delassus matrix (0 solves the rows exactly, which
/// needs independent rows), and the iterations refine the solution until the rows' residual
/// or the change of the forces is at most `accuracy`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProximalSettings {
    pub mu: f64,
    pub max_iterations: usize,
    pub accuracy: f64,
}

impl ProximalSettings {
    /// The proximal iterations a generated robot runs in its code for a regularised solve
    /// (`mu > 0`, at least this many allowed), untested between them; the solve goes on at run
    /// time if they do not meet the accuracy.
    pub const UNROLLED_ITERATIONS: usize = 4;
}

impl Default for ProximalSettings {
    /// Exact rows in one solve: independent rows, no regularisation.
    fn default() -> Self {
        ProximalSettings {
            mu: 0.0,
            max_iterations: 1,
            accuracy: 1e-12,
        }
    }
}

/// Baumgarte stabilisation: each contact's rows ask for `−K_p e − K_d J ν` (`e` its frame's
/// [`placement_error`](super::placement_error) from its anchor) instead of zero acceleration,
/// which pulls a contact that drifted (integration error, a touchdown off the anchor) back to
/// where it is held.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stabilisation<'a> {
    /// Where each contact with the world holds its frame, one per such contact in the
    /// contacts' order (a point contact uses only the translation); a loop closure is held
    /// where its other frame is and has none.
    pub anchors: &'a [Pose],
    pub kp: f64,
    pub kd: f64,
}

impl Stabilisation<'_> {
    /// Refuses anchors that are not one per contact with the world (`held` of them) and gains
    /// that are not finite.
    pub fn check(&self, held: usize) -> Result<(), ContactError> {
        if self.anchors.len() != held {
            return Err(ContactError::Anchors {
                contacts: held,
                anchors: self.anchors.len(),
            });
        }
        if !(self.kp.is_finite() && self.kd.is_finite()) {
            return Err(ContactError::Settings("the Baumgarte gains must be finite"));
        }
        Ok(())
    }
}

/// Constrained forward dynamics at one state.
#[derive(Clone, Debug, PartialEq)]
pub struct ContactSolution<NV: Dim, NC: Dim>
where
    DefaultAllocator: Allocator<NV> + Allocator<NC>,
{
    /// `a` (`q̈`, or `ν̇` on a floating base).
    pub acceleration: OVector<f64, NV>,
    /// `λ`: each contact's force (a point's three, a frame's six, linear first) in its
    /// reference axes, acting on the robot; an impulse for an impact.
    pub forces: OVector<f64, NC>,
    /// Proximal iterations run.
    pub iterations: usize,
    /// `‖J a − rhs‖∞` at the end: how well the rows hold.
    pub residual: f64,
}

/// Why a constrained solve gave no answer.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ContactError {
    /// Contact `k` is written in world axes (a spatial quantity at the world origin), which
    /// is no contact's: its rows are `Local` or `LocalWorldAligned`.
    WorldReference(usize),
    /// Baumgarte stabilisation needs one anchor per contact.
    Anchors { contacts: usize, anchors: usize },
    /// `mu` negative, no iteration, a non-finite setting or gain, or a stabilisation the
    /// derivatives do not cover.
    Settings(&'static str),
    /// The Delassus matrix is singular: row `row` depends on the rows before it (or the robot
    /// cannot move in its direction), and the solve needs `mu > 0`.
    Redundant { row: usize },
    /// A restitution coefficient outside `[0, 1]`.
    Restitution(f64),
}

impl fmt::Display for ContactError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ContactError::WorldReference(k) => write!(
                f,
                "contact {k} is written in world axes; a contact's rows are local or local_world_aligned"
            ),
            ContactError::Anchors { contacts, anchors } => {
                write!(f, "{contacts} contacts but {anchors} anchors")
            }
            ContactError::Settings(what) => write!(f, "contact solve: {what}"),
            ContactError::Redundant { row } => write!(
                f,
                "the contact rows are redundant (row {row} depends on the others): solve with mu > 0"
            ),
            ContactError::Restitution(r) => write!(f, "restitution {r} is outside [0, 1]"),
        }
    }
}

/// `K + μ I` factored in place (`L` in the lower triangle), `k` the Delassus matrix
/// `K = J M⁻¹ Jᵀ`; with `μ = 0`, refused when a pivot is at rounding level against the largest
/// diagonal entry (a row the others already fix).
pub(super) fn factor_delassus<NC: Dim>(
    mut k: OMatrix<f64, NC, NC>,
    mu: f64,
) -> Result<OMatrix<f64, NC, NC>, ContactError>
where
    DefaultAllocator: Allocator<NC, NC>,
{
    check_regularisation(mu)?;
    let n = k.nrows();
    let floor = pivot_floor((0..n).map(|i| k[(i, i)]), mu);
    for i in 0..n {
        k[(i, i)] += mu;
    }
    dense::factor_in_place(&mut k, floor).map_err(|row| ContactError::Redundant { row })?;
    Ok(k)
}

/// Refuses a regularisation (or damping) `mu` that is negative or not finite.
pub(super) fn check_regularisation(mu: f64) -> Result<(), ContactError> {
    match mu >= 0.0 && mu.is_finite() {
        true => Ok(()),
        false => Err(ContactError::Settings("mu must be finite and not negative")),
    }
}

/// The value a pivot of `K + μ I`'s factor must exceed, `diagonal` `K`'s: exactly rank
/// deficient rows give a pivot at rounding level against `K`'s largest diagonal entry, which
/// without regularisation (`μ = 0`) is refused; with `μ > 0` every pivot is at least `μ`.
fn pivot_floor(diagonal: impl Iterator<Item = f64>, mu: f64) -> f64 {
    match mu == 0.0 {
        true => 1e-12 * diagonal.fold(0.0_f64, |l, d| l.max(d.abs())),
        false => 0.0,
    }
}

/// Whether every pivot of a factor of `K + μ I` (in any elimination order) is above the floor
/// [`factor_delassus`] holds its own pivots to, `diagonal` `K`'s.
pub(super) fn pivots_hold(pivots: &[f64], diagonal: impl Iterator<Item = f64>, mu: f64) -> bool {
    let floor = pivot_floor(diagonal, mu);
    pivots.iter().all(|&p| p > floor)
}

/// `(J M⁻¹ Jᵀ + ε I)⁻¹`: the rows' operational-space inertia, `damping` `ε` keeping it finite
/// near singular configurations (0 for the exact one, refused where rows are redundant).
pub fn contact_inertia<NV: Dim, NC: Dim>(
    jacobian: &OMatrix<f64, NC, NV>,
    response: &OMatrix<f64, NV, NC>,
    damping: f64,
) -> Result<OMatrix<f64, NC, NC>, ContactError>
where
    DefaultAllocator: Allocator<NC, NC> + Allocator<NC, NV> + Allocator<NV, NC>,
{
    delassus_inertia(dense::delassus(jacobian, response), damping)
}

/// [`contact_inertia`] from the Delassus matrix `delassus` (`K = J M⁻¹ Jᵀ`): `(K + ε I)⁻¹`.
pub fn delassus_inertia<NC: Dim>(
    delassus: OMatrix<f64, NC, NC>,
    damping: f64,
) -> Result<OMatrix<f64, NC, NC>, ContactError>
where
    DefaultAllocator: Allocator<NC, NC>,
{
    Ok(dense::inverse(&factor_delassus(delassus, damping)?))
}

/// The constrained acceleration and forces: `J a = rhs` with `a = a_free + M⁻¹ Jᵀ λ`, by
/// proximal iterations from `warm_start` (zero if `None`).
pub fn solve_contacts<NV: Dim, NC: Dim>(
    jacobian: &OMatrix<f64, NC, NV>,
    response: &OMatrix<f64, NV, NC>,
    free: &OVector<f64, NV>,
    rhs: &OVector<f64, NC>,
    settings: &ProximalSettings,
    warm_start: Option<&OVector<f64, NC>>,
) -> Result<ContactSolution<NV, NC>, ContactError>
where
    DefaultAllocator:
        Allocator<NC, NC> + Allocator<NC, NV> + Allocator<NV, NC> + Allocator<NV> + Allocator<NC>,
{
    let delassus = dense::delassus(jacobian, response);
    solve_contacts_with_delassus(jacobian, response, delassus, free, rhs, settings, warm_start)
}

/// [`solve_contacts`] with the Delassus matrix `delassus` (`K = J M⁻¹ Jᵀ`) given, as a
/// generated robot computes it ([`ContactDynamics::contact_system`](super::ContactDynamics::contact_system)).
pub fn solve_contacts_with_delassus<NV: Dim, NC: Dim>(
    jacobian: &OMatrix<f64, NC, NV>,
    response: &OMatrix<f64, NV, NC>,
    delassus: OMatrix<f64, NC, NC>,
    free: &OVector<f64, NV>,
    rhs: &OVector<f64, NC>,
    settings: &ProximalSettings,
    warm_start: Option<&OVector<f64, NC>>,
) -> Result<ContactSolution<NV, NC>, ContactError>
where
    DefaultAllocator:
        Allocator<NC, NC> + Allocator<NC, NV> + Allocator<NV, NC> + Allocator<NV> + Allocator<NC>,
{
    check_iterations(settings)?;
    let lower = factor_delassus(delassus.clone(), settings.mu)?;
    let target = rhs - jacobian * free;
    let forces = match warm_start {
        Some(start) => start.clone(),
        None => OVector::zeros_generic(rhs.shape_generic().0, nalgebra::Const::<1>),
    };
    let (forces, iterations, residual) = iterate(&lower, &delassus, &target, forces, settings, 0);
    let acceleration = free + response * &forces;
    Ok(ContactSolution {
        acceleration,
        forces,
        iterations,
        residual,
    })
}

/// Refuses settings that run no iteration.
pub(super) fn check_iterations(settings: &ProximalSettings) -> Result<(), ContactError> {
    match settings.max_iterations {
        0 => Err(ContactError::Settings("at least one iteration is needed")),
        _ => Ok(()),
    }
}

/// Whether an iteration that moved the forces by `change` and left the rows' residual at
/// `residual` ends the solve.
pub(super) fn converged(residual: f64, change: f64, settings: &ProximalSettings) -> bool {
    residual <= settings.accuracy || change <= settings.accuracy
}

/// The proximal iterations from `forces`, `done` of them run already, with `lower` the factor
/// of `K + μ I` and `target` what `K λ` must equal: the forces, the iterations run in all and
/// the rows' residual at the end.
pub(super) fn iterate<NC: Dim>(
    lower: &OMatrix<f64, NC, NC>,
    delassus: &OMatrix<f64, NC, NC>,
    target: &OVector<f64, NC>,
    mut forces: OVector<f64, NC>,
    settings: &ProximalSettings,
    done: usize,
) -> (OVector<f64, NC>, usize, f64)
where
    DefaultAllocator: Allocator<NC, NC> + Allocator<NC>,
{
    let (mut iterations, mut residual) = (done, f64::INFINITY);
    while iterations < settings.max_iterations {
        iterations += 1;
        let mut next = target + &forces * settings.mu;
        dense::solve_in_place(lower, &mut next);
        let change = (&next - &forces).amax();
        forces = next;
        // `J a − rhs` with `a = a_free + M⁻¹ Jᵀ λ` is `K λ − (rhs − J a_free)`: NC² operations
        // an iteration instead of 2 NC NV, and `a` formed once, after the last.
        residual = (delassus * &forces - target).amax();
        if converged(residual, change, settings) {
            break;
        }
    }
    (forces, iterations, residual)
}
