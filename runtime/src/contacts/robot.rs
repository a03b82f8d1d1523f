//! What a generated robot with contacts implements, and the constrained functions built on it.

use super::dense;
use super::kind::ContactKind;
use super::placement::placement_error;
use super::solve::{
    delassus_inertia, solve_contacts_with_delassus, ContactError, ContactSolution, ProximalSettings,
    Stabilisation,
};
use super::system::{ContactMatrices, ContactSystem};
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
    let ContactSystem {
        matrices,
        drift,
        free_acceleration,
    } = R::contact_system(t, v, tau);
    let mut rhs = -drift;
    if let Some(stabilisation) = stabilisation {
        let velocity = matrices.jacobian * v;
        for (k, row, error) in placement_errors::<R, NV, NC>(t, &stabilisation)? {
            for i in 0..R::CONTACT_KINDS[k].rows() {
                rhs[row + i] -= stabilisation.kp * error[i] + stabilisation.kd * velocity[row + i];
            }
        }
    }
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
    delassus_inertia(R::contact_delassus(t), damping)
}
