//! What a generated robot with contacts implements, and the constrained functions built on it.

use super::dense;
use super::kind::ContactKind;
use super::placement::placement_error;
use super::solve::{
    check_iterations, check_regularisation, converged, delassus_inertia, factor_delassus, iterate,
    pivots_hold, solve_contacts_with_delassus, ContactError, ContactSolution, ProximalSettings,
    Stabilisation,
};
use super::system::{ContactInertia, ContactMatrices, ContactStep, ContactSystem};
use crate::{Pose, ReferenceFrame};
use nalgebra::{Const, SMatrix, SVector, Vector6};

/// A robot with contacts, `NV` velocity coordinates and `NC` contact rows: the pieces of
/// constrained dynamics it generates, from which [`constrained_forward_dynamics`],
/// [`impulse_dynamics`] and [`operational_space_inertia`] are assembled. Generated when a
/// description lists `contacts:` (the group `contacts`).
pub trait ContactDynamics<const NV: usize, const NC: usize> {
    /// What the functions take: `JointTrig<N>`, or `FloatingTrig<N>` on a floating base.
    type Trig;
    /// Each contact's frame, in the order of the rows.
    const CONTACT_FRAMES: &'static [&'static str];
    /// Each contact's kind (three rows for a point, six for a frame).
    const CONTACT_KINDS: &'static [ContactKind];
    /// The axes each contact's rows and force are written in.
    const CONTACT_REFERENCES: &'static [ReferenceFrame];
    /// The frame each contact holds its frame to: `None` the world, else another frame of the
    /// robot (a loop closure).
    const CONTACT_TO: &'static [Option<&'static str>];

    /// `J` (NC × NV): the contacts' rows, stacked.
    fn contact_jacobian(t: &Self::Trig) -> SMatrix<f64, NC, NV>;
    /// What `J a` is at `a = 0` along `v`: a point's classical acceleration, a frame's spatial
    /// one.
    fn contact_drift(t: &Self::Trig, v: &SVector<f64, NV>) -> SVector<f64, NC>;
    /// `M⁻¹ Jᵀ` (NV × NC): how the robot accelerates under a unit force in each row.
    fn contact_response(t: &Self::Trig) -> SMatrix<f64, NV, NC>;
    /// Forward dynamics without contacts, `M⁻¹ (τ − b)`.
    fn free_acceleration(t: &Self::Trig, v: &SVector<f64, NV>, tau: &SVector<f64, NV>) -> SVector<f64, NV>;
    /// `M⁻¹` (NV × NV): how the robot accelerates under a unit generalised force, the free
    /// acceleration's `∂/∂τ`.
    fn torque_response(t: &Self::Trig) -> SMatrix<f64, NV, NV>;
    /// `(∂a/∂q, ∂a/∂ν)` of forward dynamics with the contact forces `lambda` held, at the
    /// acceleration `a` they give: `−M⁻¹ ∂(ID(q, ν, a) − Jᵀ λ)/∂x` (`q` in its tangent space).
    fn contact_forward_dynamics_derivatives(
        t: &Self::Trig,
        v: &SVector<f64, NV>,
        a: &SVector<f64, NV>,
        lambda: &SVector<f64, NC>,
    ) -> (SMatrix<f64, NV, NV>, SMatrix<f64, NV, NV>);
    /// `(∂/∂q, ∂/∂ν)` (NC × NV each) of the rows' acceleration `J a + drift` with `a` held.
    fn contact_acceleration_derivatives(
        t: &Self::Trig,
        v: &SVector<f64, NV>,
        a: &SVector<f64, NV>,
    ) -> (SMatrix<f64, NC, NV>, SMatrix<f64, NC, NV>);
    /// The Jacobian (6 × NV, linear rows first) of contact `contact`'s frame in its own axes
    /// (`Local`); `contact` past the last is the last's.
    fn contact_local_jacobian(t: &Self::Trig, contact: usize) -> SMatrix<f64, 6, NV>;
    /// The pose of contact `contact`'s frame (in the base frame, or the world on a floating
    /// base); `contact` past the last is the last's.
    fn contact_pose(t: &Self::Trig, contact: usize) -> Pose;
    /// The pose of the frame contact `contact` holds its frame to (a loop closure's other
    /// frame; the identity for a contact with the world).
    fn contact_to_pose(t: &Self::Trig, contact: usize) -> Pose;

    /// The Delassus matrix `K = J M⁻¹ Jᵀ` (NC × NC, symmetric), whose inverse is the rows'
    /// operational-space inertia. A generated robot computes it directly, from the factored
    /// mass matrix and the rows' sparsity; by default `J` times `M⁻¹ Jᵀ` at run time.
    fn contact_delassus(t: &Self::Trig) -> SMatrix<f64, NC, NC> {
        dense::delassus(&Self::contact_jacobian(t), &Self::contact_response(t))
    }

    /// `J`, `M⁻¹ Jᵀ` and `K` at once (an impact's solve). A generated robot computes them in
    /// one call, sharing the kinematics and the factored mass matrix; by default the rows one
    /// by one.
    fn contact_matrices(t: &Self::Trig) -> ContactMatrices<NV, NC> {
        let (jacobian, response) = (Self::contact_jacobian(t), Self::contact_response(t));
        ContactMatrices {
            delassus: dense::delassus(&jacobian, &response),
            jacobian,
            response,
        }
    }

    /// [`ContactDynamics::contact_matrices`], the drift along `v` and the free acceleration
    /// under `tau` at once: everything constrained forward dynamics solves with, in one call of
    /// a generated robot (which factors the mass matrix once for all of it).
    fn contact_system(t: &Self::Trig, v: &SVector<f64, NV>, tau: &SVector<f64, NV>) -> ContactSystem<NV, NC> {
        ContactSystem {
            matrices: Self::contact_matrices(t),
            drift: Self::contact_drift(t, v),
            free_acceleration: Self::free_acceleration(t, v, tau),
        }
    }

    /// Constrained forward dynamics in one call, one proximal step from the forces `lambda`
    /// (`λ₀`): with `J a + drift` asked to be `target − kd J v`, `rhs = target − drift −
    /// kd J v − J a_free`, the forces `λ₁ = (K + μ I)⁻¹ (rhs + μ λ₀)` and
    /// `a = M⁻¹ (τ − b + Jᵀ λ₁)`, with `K` and the pivots of `K + μ I`
    /// ([`constrained_forward_dynamics`] checks and refines it). A generated robot computes it
    /// all at once, `K + μ I` factored in its code; by default from
    /// [`ContactDynamics::contact_system`] and a factor at run time.
    fn contact_solve(
        t: &Self::Trig,
        v: &SVector<f64, NV>,
        tau: &SVector<f64, NV>,
        target: &SVector<f64, NC>,
        lambda: &SVector<f64, NC>,
        kd: f64,
        mu: f64,
    ) -> ContactStep<NV, NC> {
        system_steps::<Self, NV, NC>(t, v, tau, target, lambda, kd, mu, 1)
    }

    /// [`ContactDynamics::contact_solve`] with [`ProximalSettings::UNROLLED_ITERATIONS`]
    /// proximal steps, untested between them.
    fn contact_proximal_solve(
        t: &Self::Trig,
        v: &SVector<f64, NV>,
        tau: &SVector<f64, NV>,
        target: &SVector<f64, NC>,
        lambda: &SVector<f64, NC>,
        kd: f64,
        mu: f64,
    ) -> ContactStep<NV, NC> {
        let steps = ProximalSettings::UNROLLED_ITERATIONS;
        system_steps::<Self, NV, NC>(t, v, tau, target, lambda, kd, mu, steps)
    }

    /// An impact in one call: `rhs = −(1 + restitution) J v`, the impulses
    /// `λ = (K + μ I)⁻¹ rhs` and the velocity after, `v + M⁻¹ Jᵀ λ` (as the step's
    /// acceleration), with `K` and the pivots of `K + μ I`. By default from
    /// [`ContactDynamics::contact_matrices`] and a factor at run time.
    fn contact_impulse(
        t: &Self::Trig,
        v: &SVector<f64, NV>,
        restitution: f64,
        mu: f64,
    ) -> ContactStep<NV, NC> {
        let matrices = Self::contact_matrices(t);
        let rhs = -(1.0 + restitution) * (matrices.jacobian * v);
        dense_steps(&matrices, *v, rhs, SVector::zeros(), mu, 1)
    }

    /// Forward dynamics with the contact forces `lambda` applied, `M⁻¹ (τ − b + Jᵀ λ)`.
    fn contact_forward_dynamics(
        t: &Self::Trig,
        v: &SVector<f64, NV>,
        tau: &SVector<f64, NV>,
        lambda: &SVector<f64, NC>,
    ) -> SVector<f64, NV> {
        Self::free_acceleration(t, v, tau) + Self::contact_response(t) * lambda
    }

    /// `(K + ε I)⁻¹` with the pivots of `K + ε I` and `K`'s diagonal
    /// ([`operational_space_inertia`] checks them). By default from
    /// [`ContactDynamics::contact_delassus`] and a factor at run time.
    fn contact_inertia(t: &Self::Trig, damping: f64) -> ContactInertia<NC> {
        let delassus = Self::contact_delassus(t);
        let (lower, pivots) = regularised_factor(&delassus, damping);
        ContactInertia {
            inertia: dense::inverse(&lower),
            pivots,
            delassus_diagonal: delassus.diagonal(),
        }
    }
}

/// The Cholesky factor of `K + μ I` and its pivots (the squares of its diagonal); every pivot
/// not a number where the factor met one, so that the caller's check refuses it.
fn regularised_factor<const NC: usize>(
    delassus: &SMatrix<f64, NC, NC>,
    mu: f64,
) -> (SMatrix<f64, NC, NC>, SVector<f64, NC>) {
    let mut lower = delassus + SMatrix::<f64, NC, NC>::identity() * mu;
    match dense::factor_in_place(&mut lower, f64::NEG_INFINITY) {
        Ok(()) => {
            let pivots = lower.diagonal().map(|d| d * d);
            (lower, pivots)
        }
        Err(_) => (lower, SVector::repeat(f64::NAN)),
    }
}

/// [`ContactDynamics::contact_solve`] with `steps` proximal steps, from
/// [`ContactDynamics::contact_system`].
#[allow(clippy::too_many_arguments)]
fn system_steps<R: ContactDynamics<NV, NC> + ?Sized, const NV: usize, const NC: usize>(
    t: &R::Trig,
    v: &SVector<f64, NV>,
    tau: &SVector<f64, NV>,
    target: &SVector<f64, NC>,
    start: &SVector<f64, NC>,
    kd: f64,
    mu: f64,
    steps: usize,
) -> ContactStep<NV, NC> {
    let ContactSystem {
        matrices,
        drift,
        free_acceleration,
    } = R::contact_system(t, v, tau);
    let velocity = matrices.jacobian * v;
    let rhs = target - drift - velocity * kd - matrices.jacobian * free_acceleration;
    dense_steps(&matrices, free_acceleration, rhs, *start, mu, steps)
}

/// `steps` proximal steps from `start`, `(K + μ I) λ_{k+1} = rhs + μ λ_k`, then
/// `base + M⁻¹ Jᵀ λ`, from the matrices.
fn dense_steps<const NV: usize, const NC: usize>(
    matrices: &ContactMatrices<NV, NC>,
    base: SVector<f64, NV>,
    rhs: SVector<f64, NC>,
    start: SVector<f64, NC>,
    mu: f64,
    steps: usize,
) -> ContactStep<NV, NC> {
    let (lower, pivots) = regularised_factor(&matrices.delassus, mu);
    let (mut previous, mut forces) = (start, start);
    for _ in 0..steps {
        previous = forces;
        forces = rhs + previous * mu;
        dense::solve_in_place(&lower, &mut forces);
    }
    ContactStep {
        acceleration: base + matrices.response * forces,
        forces,
        previous_forces: previous,
        delassus: matrices.delassus,
        pivots,
        rhs,
    }
}

/// `a` and the contact forces with every contact of `R` held (Pinocchio's
/// `constraintDynamics`): exact with the default settings, proximal with `mu > 0`, pulled
/// back with `stabilisation` (to its anchors, one per contact with the world, and each loop to
/// its other frame), from `warm_start` forces if given (the last tick's, in a simulation).
pub fn constrained_forward_dynamics<R: ContactDynamics<NV, NC>, const NV: usize, const NC: usize>(
    t: &R::Trig,
    v: &SVector<f64, NV>,
    tau: &SVector<f64, NV>,
    stabilisation: Option<Stabilisation<'_>>,
    settings: &ProximalSettings,
    warm_start: Option<&SVector<f64, NC>>,
) -> Result<ContactSolution<Const<NV>, Const<NC>>, ContactError> {
    check_iterations(settings)?;
    check_regularisation(settings.mu)?;
    let (mut target, mut kd) = (SVector::<f64, NC>::zeros(), 0.0);
    if let Some(stabilisation) = &stabilisation {
        for (k, row, error) in placement_errors::<R, NV, NC>(t, stabilisation)? {
            for i in 0..R::CONTACT_KINDS[k].rows() {
                target[row + i] -= stabilisation.kp * error[i];
            }
        }
        kd = stabilisation.kd;
    }
    let start = warm_start.copied().unwrap_or_else(SVector::zeros);
    let mu = settings.mu;
    // A regularised solve takes the steps it most often converges in from one call.
    let unrolled = mu > 0.0 && settings.max_iterations >= ProximalSettings::UNROLLED_ITERATIONS;
    let (step, done) = match unrolled {
        true => (
            R::contact_proximal_solve(t, v, tau, &target, &start, kd, mu),
            ProximalSettings::UNROLLED_ITERATIONS,
        ),
        false => (R::contact_solve(t, v, tau, &target, &start, kd, mu), 1),
    };
    if !pivots_hold(
        step.pivots.as_slice(),
        step.delassus.diagonal().iter().copied(),
        mu,
    ) {
        // Rows that depend on one another: the factor at run time names the first (or, where
        // its order of elimination keeps the pivots above the floor, solves).
        return solve_from_system::<R, NV, NC>(t, v, tau, &target, kd, settings, warm_start);
    }
    let residual = (step.delassus * step.forces - step.rhs).amax();
    let change = (step.forces - step.previous_forces).amax();
    if done == settings.max_iterations || converged(residual, change, settings) {
        return Ok(ContactSolution {
            acceleration: step.acceleration,
            forces: step.forces,
            iterations: done,
            residual,
        });
    }
    let lower = factor_delassus(step.delassus, mu)?;
    let (forces, iterations, residual) =
        iterate(&lower, &step.delassus, &step.rhs, step.forces, settings, done);
    Ok(ContactSolution {
        acceleration: R::contact_forward_dynamics(t, v, tau, &forces),
        forces,
        iterations,
        residual,
    })
}

/// [`constrained_forward_dynamics`] from [`ContactDynamics::contact_system`], every step at run
/// time, `target − kd J v` what the rows' acceleration is asked to be.
fn solve_from_system<R: ContactDynamics<NV, NC>, const NV: usize, const NC: usize>(
    t: &R::Trig,
    v: &SVector<f64, NV>,
    tau: &SVector<f64, NV>,
    target: &SVector<f64, NC>,
    kd: f64,
    settings: &ProximalSettings,
    warm_start: Option<&SVector<f64, NC>>,
) -> Result<ContactSolution<Const<NV>, Const<NC>>, ContactError> {
    let ContactSystem {
        matrices,
        drift,
        free_acceleration,
    } = R::contact_system(t, v, tau);
    let rhs = target - drift - (matrices.jacobian * v) * kd;
    solve_contacts_with_delassus(
        &matrices.jacobian,
        &matrices.response,
        matrices.delassus,
        &free_acceleration,
        &rhs,
        settings,
        warm_start,
    )
}

/// Each contact's placement error from where Baumgarte stabilisation holds it
/// ([`placement_error`]): `(contact, its first row, e)`. A loop is held where its other frame
/// is, a contact with the world at its anchor (one each, in order, or refused); gains that are
/// not finite are refused.
pub(super) fn placement_errors<'a, R: ContactDynamics<NV, NC>, const NV: usize, const NC: usize>(
    t: &'a R::Trig,
    stabilisation: &'a Stabilisation<'a>,
) -> Result<impl Iterator<Item = (usize, usize, Vector6<f64>)> + 'a, ContactError> {
    stabilisation.check(R::CONTACT_TO.iter().filter(|to| to.is_none()).count())?;
    let mut anchors = stabilisation.anchors.iter();
    let contacts = (R::CONTACT_KINDS.iter())
        .zip(R::CONTACT_REFERENCES)
        .zip(R::CONTACT_TO);
    let rows = R::CONTACT_KINDS.iter().scan(0, |row, kind| {
        let first = *row;
        *row += kind.rows();
        Some(first)
    });
    Ok(contacts
        .zip(rows)
        .enumerate()
        .map(move |(k, (((&kind, &reference), to), row))| {
            let anchor = match to {
                Some(_) => R::contact_to_pose(t, k),
                // Counted above: one anchor per contact with the world.
                None => anchors.next().copied().unwrap_or_else(Pose::identity),
            };
            (
                k,
                row,
                placement_error(kind, reference, &R::contact_pose(t, k), &anchor),
            )
        }))
}

/// The velocity just after every contact of `R` strikes, with restitution `restitution`
/// (Pinocchio's `impulseDynamics`: `J ν⁺ = −r J ν⁻`, one solve damped by `mu`), and the
/// impulses.
pub fn impulse_dynamics<R: ContactDynamics<NV, NC>, const NV: usize, const NC: usize>(
    t: &R::Trig,
    before: &SVector<f64, NV>,
    restitution: f64,
    mu: f64,
) -> Result<(SVector<f64, NV>, SVector<f64, NC>), ContactError> {
    if !(0.0..=1.0).contains(&restitution) {
        return Err(ContactError::Restitution(restitution));
    }
    check_regularisation(mu)?;
    let step = R::contact_impulse(t, before, restitution, mu);
    if pivots_hold(
        step.pivots.as_slice(),
        step.delassus.diagonal().iter().copied(),
        mu,
    ) {
        return Ok((step.acceleration, step.forces));
    }
    // Rows that depend on one another: the factor at run time names the first.
    let matrices = R::contact_matrices(t);
    let rhs = -(1.0 + restitution) * (matrices.jacobian * before);
    let settings = ProximalSettings {
        mu,
        max_iterations: 1,
        accuracy: 0.0,
    };
    let change = solve_contacts_with_delassus(
        &matrices.jacobian,
        &matrices.response,
        matrices.delassus,
        &SVector::zeros(),
        &rhs,
        &settings,
        None,
    )?;
    Ok((before + change.acceleration, change.forces))
}

/// `(J M⁻¹ Jᵀ + ε I)⁻¹`: the contact rows' operational-space inertia, `damping` `ε` keeping
/// it finite near singular configurations (0 for the exact one, refused where rows are
/// redundant).
pub fn operational_space_inertia<R: ContactDynamics<NV, NC>, const NV: usize, const NC: usize>(
    t: &R::Trig,
    damping: f64,
) -> Result<SMatrix<f64, NC, NC>, ContactError> {
    check_regularisation(damping)?;
    let inertia = R::contact_inertia(t, damping);
    let diagonal = inertia.delassus_diagonal.iter().copied();
    match pivots_hold(inertia.pivots.as_slice(), diagonal, damping) {
        true => Ok(inertia.inertia),
        // Rows that depend on one another: the factor at run time names the first.
        false => delassus_inertia(R::contact_delassus(t), damping),
    }
}

#[cfg(test)]
mod tests;
