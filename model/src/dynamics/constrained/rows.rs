//! The rows a contact adds, from the motion of its frame (and of the frame it is held to, for a
//! loop closure): generic over the scalar, so the same rows are traced for generated code.
//!
//! Everything is first written in world axes at the held frame's origin `p₁`
//! (`LOCAL_WORLD_ALIGNED`), then turned into the frame's own axes for `Local` rows. With `ṗ`,
//! `ω`, `c` (the origin's classical acceleration) and `α` of each frame at `a = 0`, and
//! `r = p₁ − p₂` from the origin of the frame held to (none for the world: its terms vanish):
//! - a point's rows are `ṗ₁ − ṗ₂`, their drift `c₁ − c₂`, turned by `R₁ᵀ` for `Local`;
//! - a frame's rows are frame 1's twist less body 2's at `p₁`, `[ṗ₁ − ṗ₂ − ω₂ × r; ω₁ − ω₂]`,
//!   their drift the spatial accelerations' difference at `p₁`,
//!   `A₁ − A₂ = [c₁ − ω₁ × ṗ₁ − (c₂ − ω₂ × ṗ₂ + α₂ × r); α₁ − α₂]`; in the frame's axes the
//!   drift also gains `V₁ × V₂` (the two twists' spatial cross product), the derivative of
//!   moving body 2's twist into frame 1, so that it is `a₁ − ¹X₂ a₂ + v₁ × ¹X₂ v₂`.
//!
//! These are Pinocchio's rows (`RigidConstraintModel`): for a point held in its own axes the
//! drift is `R₁ᵀ (c₁ − c₂)`, without the term of `R₁` turning, which vanishes where the rows'
//! velocity does.

use crate::dynamics::frames::FrameMotion;
use crate::model::Contact;
use crate::scalar::Scalar;
use crate::spatial::Vec3;
use dyngen_runtime::{ContactKind, ReferenceFrame};
use nalgebra::DMatrix;

/// The motions a contact's rows are made of: its frame's, and the one it is held to's.
pub struct ContactMotion<S> {
    pub frame: FrameMotion<S>,
    /// `None`: held to the world.
    pub to: Option<FrameMotion<S>>,
    /// Both frames' rates at `a = 0` where the caller has them from elsewhere (a tracer, from the
    /// bias pass forward dynamics runs anyway); `None`: from `J̇` ([`OriginRates::of`]).
    pub rates: Option<(OriginRates<S>, Option<OriginRates<S>>)>,
}

impl<S: Scalar> ContactMotion<S> {
    /// Each contact's motions, `motion(k)` the motion of `Model::frames()[k]`.
    pub fn of(contacts: &[Contact], motion: impl Fn(usize) -> FrameMotion<S>) -> Vec<ContactMotion<S>> {
        contacts
            .iter()
            .map(|c| ContactMotion {
                frame: motion(c.frame),
                to: c.to.map(&motion),
                rates: None,
            })
            .collect()
    }
}

/// The stacked rows of a set of contacts at one state.
pub struct ConstraintRows<S> {
    /// `J` (rows × nv).
    pub jacobian: DMatrix<S>,
    /// What `J a` is at `a = 0` (the module docs).
    pub drift: Vec<S>,
    /// `J ν`.
    pub velocity: Vec<S>,
}

/// The rows of `contacts`, `motions[k]` the motions of contact `k` at velocity `qd`.
pub fn constraint_rows<S: Scalar>(
    contacts: &[Contact],
    motions: &[ContactMotion<S>],
    qd: &[S],
) -> ConstraintRows<S> {
    let rows: usize = contacts.iter().map(|c| c.kind.rows()).sum();
    let n = qd.len();
    let mut jacobian = DMatrix::from_element(rows, n, S::zero());
    let (mut drift, mut velocity) = (Vec::with_capacity(rows), Vec::with_capacity(rows));
    let mut row = 0;
    for (contact, motion) in contacts.iter().zip(motions) {
        let (one, two) = match &motion.rates {
            Some((one, two)) => (*one, *two),
            None => (
                OriginRates::of(&motion.frame, qd),
                motion.to.as_ref().map(|m| OriginRates::of(m, qd)),
            ),
        };
        let local = contact.reference == ReferenceFrame::Local;
        let turn = |x: Vec3<S>| match local {
            true => motion.frame.pose.rot.tr_mul_vec(&x),
            false => x,
        };
        // Columns of the rows in world axes at `p₁`, then in the chosen axes.
        for c in 0..n {
            let (mut v, mut w) = column(&motion.frame.jacobian, c);
            if let (Some(to), Some(two)) = (&motion.to, &two) {
                let (v2, w2) = column(&to.jacobian, c);
                let r = one.p - two.p;
                v = match contact.kind {
                    ContactKind::Point => v - v2,
                    ContactKind::Frame => v - v2 - w2.cross(&r),
                };
                w = w - w2;
            }
            let (v, w) = (turn(v), turn(w));
            for k in 0..3 {
                jacobian[(row + k, c)] = v.0[k];
            }
            if contact.kind == ContactKind::Frame {
                for k in 0..3 {
                    jacobian[(row + 3 + k, c)] = w.0[k];
                }
            }
        }
        let (linear, angular) = match (contact.kind, &two) {
            (ContactKind::Point, None) => (one.c, Vec3::zero()),
            (ContactKind::Point, Some(two)) => (one.c - two.c, Vec3::zero()),
            (ContactKind::Frame, None) => (one.c - one.w.cross(&one.v), one.alpha),
            (ContactKind::Frame, Some(two)) => {
                let r = one.p - two.p;
                let spatial_two = two.c - two.w.cross(&two.v) + two.alpha.cross(&r);
                let mut linear = one.c - one.w.cross(&one.v) - spatial_two;
                let mut angular = one.alpha - two.alpha;
                if local {
                    // `V₁ × V₂`, body 2's twist taken at `p₁`.
                    let v2 = two.v + two.w.cross(&r);
                    linear = linear + one.w.cross(&v2) + one.v.cross(&two.w);
                    angular = angular + one.w.cross(&two.w);
                }
                (linear, angular)
            }
        };
        let (linear, angular) = (turn(linear), turn(angular));
        drift.extend_from_slice(&linear.0);
        if contact.kind == ContactKind::Frame {
            drift.extend_from_slice(&angular.0);
        }
        for k in 0..contact.kind.rows() {
            let sum = (0..n).fold(S::zero(), |acc, c| acc + jacobian[(row + k, c)] * qd[c]);
            velocity.push(sum);
        }
        row += contact.kind.rows();
    }
    ConstraintRows {
        jacobian,
        drift,
        velocity,
    }
}

/// A frame origin's velocity and acceleration at `a = 0`, in world axes (not `FrameRates`,
/// the frame functions' velocity and spatial acceleration in the frame's own axes).
#[derive(Clone, Copy)]
pub struct OriginRates<S> {
    /// The origin.
    pub p: Vec3<S>,
    /// `ṗ`.
    pub v: Vec3<S>,
    pub w: Vec3<S>,
    /// The origin's classical acceleration.
    pub c: Vec3<S>,
    pub alpha: Vec3<S>,
}

impl<S: Scalar> OriginRates<S> {
    /// From the frame's `J` and `J̇`.
    pub fn of(motion: &FrameMotion<S>, qd: &[S]) -> OriginRates<S> {
        let lwa = ReferenceFrame::LocalWorldAligned;
        let [v0, v1, v2, w0, w1, w2] = motion.velocity_in(lwa, qd);
        let zero = vec![S::zero(); qd.len()];
        let [c0, c1, c2, a0, a1, a2] = motion.classical_acceleration_in(lwa, qd, &zero);
        OriginRates {
            p: motion.pose.pos,
            v: Vec3([v0, v1, v2]),
            w: Vec3([w0, w1, w2]),
            c: Vec3([c0, c1, c2]),
            alpha: Vec3([a0, a1, a2]),
        }
    }
}

fn column<S: Scalar>(m: &DMatrix<S>, c: usize) -> (Vec3<S>, Vec3<S>) {
    (
        Vec3([m[(0, c)], m[(1, c)], m[(2, c)]]),
        Vec3([m[(3, c)], m[(4, c)], m[(5, c)]]),
    )
}
