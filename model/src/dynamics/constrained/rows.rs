//! The rows a contact adds, from its frame's motion: generic over the scalar, so the same rows
//! are traced for generated code.

use crate::dynamics::frames::FrameMotion;
use crate::model::Contact;
use crate::scalar::Scalar;
use crate::spatial::Vec3;
use dyngen_runtime::ContactKind;
use nalgebra::DMatrix;

/// The stacked rows of a set of contacts at one state.
pub struct ConstraintRows<S> {
    /// `J` (rows × nv).
    pub jacobian: DMatrix<S>,
    /// What `J a` is at `a = 0`: a point's classical acceleration, a frame's spatial one.
    pub drift: Vec<S>,
    /// `J ν`.
    pub velocity: Vec<S>,
}

/// The rows of `contacts`, `motions[k]` the motion of contact `k`'s frame at velocity `qd`.
pub fn constraint_rows<S: Scalar>(
    contacts: &[Contact],
    motions: &[FrameMotion<S>],
    qd: &[S],
) -> ConstraintRows<S> {
    let rows: usize = contacts.iter().map(|c| c.kind.rows()).sum();
    let mut jacobian = DMatrix::from_element(rows, qd.len(), S::zero());
    let (mut drift, mut velocity) = (Vec::with_capacity(rows), Vec::with_capacity(rows));
    let zero = vec![S::zero(); qd.len()];
    let mut row = 0;
    for (contact, motion) in contacts.iter().zip(motions) {
        let j = motion.jacobian_in(contact.reference);
        let v = motion.velocity_in(contact.reference, qd);
        let classical = motion.classical_acceleration_in(contact.reference, qd, &zero);
        let size = contact.kind.rows();
        jacobian.rows_mut(row, size).copy_from(&j.rows(0, size));
        velocity.extend_from_slice(&v[..size]);
        match contact.kind {
            ContactKind::Point => drift.extend_from_slice(&classical[..3]),
            ContactKind::Frame => {
                // The spatial acceleration: the classical one less `ω × v`.
                let (linear, angular) = (Vec3([v[0], v[1], v[2]]), Vec3([v[3], v[4], v[5]]));
                let omega_cross_v = angular.cross(&linear);
                drift.extend((0..3).map(|k| classical[k] - omega_cross_v.0[k]));
                drift.extend_from_slice(&classical[3..]);
            }
        }
        row += size;
    }
    ConstraintRows {
        jacobian,
        drift,
        velocity,
    }
}
