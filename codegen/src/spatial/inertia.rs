//! Rigid-body inertia in the ten standard parameters, which all dynamics is linear in.

use super::{Force, Motion, Transform, Vec3};
use crate::model::PARAMS_PER_BODY;
use crate::scalar::Scalar;

/// Spatial inertia about a frame origin: mass `m`, first moment `h = m·c`, and the rotational
/// inertia about the origin as the symmetric entries `[Ixx, Ixy, Iyy, Ixz, Iyz, Izz]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RigidInertia<S> {
    pub m: S,
    pub h: Vec3<S>,
    pub i: [S; 6],
}

impl<S: Scalar> RigidInertia<S> {
    /// From the standard parameters `[m, mcx, mcy, mcz, Ixx, Ixy, Iyy, Ixz, Iyz, Izz]`.
    pub fn from_parameters(p: &[S; PARAMS_PER_BODY]) -> Self {
        RigidInertia {
            m: p[0],
            h: Vec3([p[1], p[2], p[3]]),
            i: [p[4], p[5], p[6], p[7], p[8], p[9]],
        }
    }

    /// The inertia of parameter `k` set to one and the others to zero. Dynamics is linear in
    /// the parameters, so a body's force with this "inertia" is column `k` of its regressor.
    pub fn unit(k: usize) -> Self {
        let mut p = [S::zero(); PARAMS_PER_BODY];
        p[k] = S::one();
        Self::from_parameters(&p)
    }

    pub fn zero() -> Self {
        Self::from_parameters(&[S::zero(); PARAMS_PER_BODY])
    }

    /// Rotational inertia about the origin times `w`.
    fn rot_mul(&self, w: &Vec3<S>) -> Vec3<S> {
        let [xx, xy, yy, xz, yz, zz] = self.i;
        let [a, b, c] = w.0;
        Vec3([
            xx * a + xy * b + xz * c,
            xy * a + yy * b + yz * c,
            xz * a + yz * b + zz * c,
        ])
    }

    /// Momentum `I·m` of a motion.
    pub fn mul_motion(&self, m: &Motion<S>) -> Force<S> {
        Force {
            ang: self.rot_mul(&m.ang) + self.h.cross(&m.lin),
            lin: m.lin.scale(self.m) - self.h.cross(&m.ang),
        }
    }

    /// The body force `I ẇ + B(I, v)·w`, with the body operator
    /// `B(I, v)·w = ½ [v ×* (I w) + w ×* (I v) − I (v × w)]` (Echeandia & Wensing 2021):
    /// `B(I, v)·v = v ×* I v`, and `B + Bᵀ = İ`, which makes the Coriolis matrix
    /// Christoffel-consistent.
    ///
    /// Computed as `I (ẇ − v × ŵ) + v ×* (I ŵ) + ŵ ×* (I v)` with `ŵ = w / 2`: a regressor
    /// evaluates it for ten unit inertias at one motion, and then `ŵ` and `ẇ − v × ŵ` are one
    /// value each instead of a halving and a subtraction per inertia and entry.
    pub fn body_force(&self, v: &Motion<S>, w: &Motion<S>, wdot: &Motion<S>) -> Force<S> {
        let half = S::from_f64(0.5);
        let w = Motion {
            ang: w.ang.scale(half),
            lin: w.lin.scale(half),
        };
        let wdot = *wdot - v.cross_motion(&w);
        self.mul_motion(&wdot) + v.cross_force(&self.mul_motion(&w)) + w.cross_force(&self.mul_motion(v))
    }

    /// The time derivative `İ = v ×* I − I (v ×)` of this inertia moving with velocity `v`
    /// (angular `ω`, origin velocity `u`), itself of rigid-inertia shape:
    /// `ṁ = 0`, `ḣ = ω × h + m u`, `İ_O = [ω×] I_O − I_O [ω×] + 2 (u·h) 1 − h uᵀ − u hᵀ`.
    pub fn derivative(&self, v: &Motion<S>) -> RigidInertia<S> {
        let (w, u, h) = (&v.ang, &v.lin, &self.h);
        let [xx, xy, yy, xz, yz, zz] = self.i;
        let full = [[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]];
        // ([ω×] I)_ij = ω_{i+1} I_{i+2, j} − ω_{i+2} I_{i+1, j}; the commutator is its symmetric part doubled.
        let wi = |i: usize, j: usize| {
            w.0[(i + 1) % 3] * full[(i + 2) % 3][j] - w.0[(i + 2) % 3] * full[(i + 1) % 3][j]
        };
        let two_uh = S::from_f64(2.0) * u.dot(h);
        let entry = |i: usize, j: usize| {
            let commutator = wi(i, j) + wi(j, i);
            let shift = h.0[i] * u.0[j] + u.0[i] * h.0[j];
            if i == j {
                commutator + two_uh - shift
            } else {
                commutator - shift
            }
        };
        RigidInertia {
            m: S::zero(),
            h: w.cross(h) + u.scale(self.m),
            i: [
                entry(0, 0),
                entry(0, 1),
                entry(1, 1),
                entry(0, 2),
                entry(1, 2),
                entry(2, 2),
            ],
        }
    }

    /// The same inertia expressed in the parent frame of `x` (this inertia is in the child frame).
    pub fn to_parent(&self, x: &Transform<S>) -> RigidInertia<S> {
        let t = x.pos;
        let hr = x.rot.mul_vec(&self.h);
        // R I Rᵀ, then the shift of the reference point from the child origin to the parent's.
        let [xx, xy, yy, xz, yz, zz] = self.i;
        let full = super::Mat3([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]]);
        let r = x.rot * full * x.rot.transpose();
        let two = S::from_f64(2.0);
        let diag = self.m * t.dot(&t) + two * t.dot(&hr);
        let off = |a: usize, b: usize| self.m * t.0[a] * t.0[b] + t.0[a] * hr.0[b] + hr.0[a] * t.0[b];
        RigidInertia {
            m: self.m,
            h: hr + t.scale(self.m),
            i: [
                r.0[0][0] + diag - off(0, 0),
                r.0[0][1] - off(0, 1),
                r.0[1][1] + diag - off(1, 1),
                r.0[0][2] - off(0, 2),
                r.0[1][2] - off(1, 2),
                r.0[2][2] + diag - off(2, 2),
            ],
        }
    }
}

impl<S: Scalar> std::ops::Add for RigidInertia<S> {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        RigidInertia {
            m: self.m + o.m,
            h: self.h + o.h,
            i: std::array::from_fn(|k| self.i[k] + o.i[k]),
        }
    }
}
